"""Shared fixtures of the Python tests (run by CTest as `/usr/bin/python3 -m pytest python/tests` with PYTHONPATH at
the build's python directory)."""
import os
import subprocess

import pytest

import mesohex
from mesohex._build_paths import MESOHEX_CLI

PROJECT_DIR = os.environ.get("MESOHEX_PROJECT_DIR", os.path.dirname(os.path.dirname(os.path.dirname(__file__))))


@pytest.fixture
def cli():
    """Runs the `mesohex` executable of this build; returns the CompletedProcess (text output)."""
    def run(*args, check=True):
        proc = subprocess.run([MESOHEX_CLI] + [str(a) for a in args], capture_output=True, text=True)
        if check and proc.returncode != 0:
            raise AssertionError("mesohex %s -> %d\n%s%s" % (" ".join(map(str, args)), proc.returncode, proc.stdout,
                                                             proc.stderr))
        return proc
    return run


def block(nx, ny, nz):
    """nx x ny x nz unit cubes as a mesohex.HexMesh: vertex (i, j, k) has id i + (nx+1) (j + (ny+1) k) and position
    (i, j, k); hex (i, j, k) has id i + nx (j + ny k) (the same numbering as tests/unit/hex_fixtures.h)."""
    import numpy as np
    pts = np.array([[i, j, k] for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)], dtype=float)

    def vid(i, j, k):
        return i + (nx + 1) * (j + (ny + 1) * k)
    hexes = [[vid(i, j, k), vid(i + 1, j, k), vid(i + 1, j + 1, k), vid(i, j + 1, k),
              vid(i, j, k + 1), vid(i + 1, j, k + 1), vid(i + 1, j + 1, k + 1), vid(i, j + 1, k + 1)]
             for k in range(nz) for j in range(ny) for i in range(nx)]
    return mesohex.HexMesh(pts, np.array(hexes))

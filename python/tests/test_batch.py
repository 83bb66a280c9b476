"""Batch meshing on a 2-worker local Dask cluster: generated shapes, a bad job, a crashing job, a rerun that skips
the done jobs, a timeout."""
import csv
import json
import os
import stat
import subprocess
import sys

import pytest

import mesohex
from mesohex._build_paths import MESOHEX_CLI

FAST = "--levels 0 --iterations 30"  # small meshes, short fitting: each job takes about a second


def run_batch(*args):
    env = dict(os.environ)
    return subprocess.run([sys.executable, "-m", "mesohex.batch"] + [str(a) for a in args], capture_output=True,
                          text=True, env=env, timeout=300)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def shapes(tmp_path_factory):
    """Three generated skeletons with their thickened domains, a broken skeleton file, and a wrapper of the
    `mesohex` executable that crashes (SIGSEGV) on jobs whose output name contains 'crash' and hangs on 'sleepy'."""
    d = tmp_path_factory.mktemp("batch")
    for name, args in (("plate", ["plate", "-n", "2", "-m", "2"]), ("tfan", ["tfan", "-n", "1", "-m", "1"]),
                       ("box", ["box", "-n", "1"])):
        subprocess.run([MESOHEX_CLI, "generate"] + args + ["-o", str(d / (name + ".obj"))], check=True,
                       capture_output=True)
        subprocess.run([MESOHEX_CLI, "thicken", str(d / (name + ".obj")), "-o", str(d / (name + ".off")),
                        "--resolution", "2"], check=True, capture_output=True)
    (d / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nl 1 7\n")  # edge to a vertex that does not exist
    wrapper = d / "flaky_mesohex.sh"
    wrapper.write_text("#!/bin/sh\ncase \"$*\" in\n"
                       "  *crash*) echo 'about to crash' >&2; kill -SEGV $$ ;;\n"
                       "  *sleepy*) sleep 60 ;;\n"
                       "esac\nexec %s \"$@\"\n" % MESOHEX_CLI)
    wrapper.chmod(wrapper.stat().st_mode | stat.S_IXUSR)
    return d


def test_batch_meshes_a_manifest_and_survives_bad_jobs(shapes):
    d = shapes
    out = d / "out"
    out.mkdir()
    manifest = d / "jobs.csv"
    manifest.write_text(
        "skeleton,surface,output,options\n"
        "plate.obj,plate.off,out/plate.vtu,%s\n"
        "tfan.obj,tfan.off,out/tfan.mesh,%s --partitions 2\n"
        ",plate.off,out/plate_auto.vtu,--raw\n"
        "broken.obj,plate.off,out/broken.vtu,%s\n"
        "box.obj,box.off,out/crash.vtu,%s\n" % (FAST, FAST, FAST, FAST))
    proc = run_batch(manifest, "--mesohex", d / "flaky_mesohex.sh", "--retries", "1")
    assert proc.returncode == 1, proc.stdout + proc.stderr  # some jobs failed
    rows = read_csv(d / "jobs.results.csv")
    assert [r["row"] for r in rows] == ["1", "2", "3", "4", "5"]
    by_name = {os.path.basename(r["output"]): r for r in rows}
    for name in ("plate.vtu", "tfan.mesh", "plate_auto.vtu"):
        r = by_name[name]
        assert r["status"] == "ok", r
        assert r["exit_code"] == "0"
        mesh = mesohex.read_hex_mesh(str(out / name))
        assert int(r["hexes"]) == len(mesh.hexes) > 0
        q = mesohex.quality(mesh)
        assert abs(float(r["sj_min"]) - q["sj_min"]) < 1e-9 and float(r["sj_min"]) > 0
        assert abs(float(r["sj_avg"]) - q["sj_avg"]) < 1e-9
        assert float(r["seconds"]) > 0 and r["attempts"] == "1"
    assert float(by_name["plate.vtu"]["hausdorff"]) > 0  # finished meshes have a distance to the surface
    assert by_name["plate_auto.vtu"]["hausdorff"] == ""  # a raw mesh does not
    bad = by_name["broken.vtu"]
    assert bad["status"] == "failed" and bad["exit_code"] == "2" and bad["attempts"] == "1"  # bad input: no retry
    assert "broken.obj" in bad["stderr"]
    assert not (out / "broken.vtu").exists()
    crash = by_name["crash.vtu"]
    assert crash["status"] == "crashed" and crash["attempts"] == "2"  # retried once
    assert "about to crash" in crash["stderr"] and "signal 11" in crash["stderr"]
    # The JSON table has the same records, with the whole stderr.
    records = json.loads((d / "jobs.results.json").read_text())
    assert [r["status"] for r in records] == ["ok", "ok", "ok", "failed", "crashed"]

    # A rerun skips the three done jobs (their outputs stay untouched) and retries the others.
    mtimes = {name: (out / name).stat().st_mtime_ns for name in ("plate.vtu", "tfan.mesh", "plate_auto.vtu")}
    proc = run_batch(manifest, "--mesohex", d / "flaky_mesohex.sh", "--retries", "0")
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert proc.stdout.count("skipped") == 3, proc.stdout
    for name, t in mtimes.items():
        assert (out / name).stat().st_mtime_ns == t
    rows = read_csv(d / "jobs.results.csv")
    assert [r["status"] for r in rows] == ["ok", "ok", "ok", "failed", "crashed"]


def test_batch_timeout_fails_that_job_only(shapes):
    d = shapes
    manifest = d / "slow.csv"
    manifest.write_text("skeleton,surface,output,options\n"
                        "plate.obj,plate.off,sleepy.vtu,%s\n"
                        "plate.obj,plate.off,quick.vtu,%s\n" % (FAST, FAST))
    proc = run_batch(manifest, "--mesohex", d / "flaky_mesohex.sh", "--timeout", "2", "--retries", "0",
                     "--results", d / "slow_results")
    assert proc.returncode == 1, proc.stdout + proc.stderr
    rows = read_csv(d / "slow_results.csv")
    assert [r["status"] for r in rows] == ["timeout", "ok"]
    assert "timeout" in rows[0]["stderr"]


def test_bad_manifests_are_rejected(tmp_path):
    m = tmp_path / "m.csv"
    m.write_text("skeleton,output\na.obj,a.vtu\n")
    proc = run_batch(m)
    assert proc.returncode == 2 and "surface" in proc.stderr
    m.write_text("skeleton,surface,output\na.obj,a.off,x.vtu\nb.obj,b.off,x.vtu\n")
    proc = run_batch(m)
    assert proc.returncode == 2 and "m.csv:3" in proc.stderr and "line 2" in proc.stderr
    proc = run_batch(tmp_path / "missing.csv")
    assert proc.returncode == 2 and "missing.csv" in proc.stderr

#!/usr/bin/env python3
"""Checks that the project's C++ files are formatted with .clang-format (test `format`).

  tools/check_format.py CLANG_FORMAT ROOT

Runs CLANG_FORMAT --dry-run --Werror on every .h / .cpp file under ROOT's lib, apps, tests, bench, fuzz and python
folders (skipping node_modules and build folders); exits 1 and names the files that differ. To fix: run
CLANG_FORMAT -i on them.
"""
import os
import subprocess
import sys

FOLDERS = ('lib', 'apps', 'tests', 'bench', 'fuzz', 'python')
SKIP = {'node_modules', 'build', '__pycache__'}


def sources(root):
    for top in FOLDERS:
        for path, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = sorted(d for d in dirs if d not in SKIP and not d.startswith('build'))
            for f in sorted(files):
                if f.endswith(('.h', '.cpp')):
                    yield os.path.join(path, f)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    tool, root = sys.argv[1], sys.argv[2]
    bad = []
    for f in sources(root):
        r = subprocess.run([tool, '--dry-run', '--Werror', '--style=file', f], capture_output=True, text=True)
        if r.returncode != 0:
            bad.append(os.path.relpath(f, root))
    for f in bad:
        print('not formatted: ' + f)
    print(f'{len(bad)} file(s) differ from .clang-format')
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())

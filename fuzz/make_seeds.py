#!/usr/bin/env python3
"""Seed corpus for the fuzz targets, from the project's test inputs (tests/data, data/tiny) and a few small
hand-written files of the formats the tests generate inline (surfaces, medial meshes, binary PLY / STL).

Every input starts with one byte that selects the file extension (see fuzz/fuzz_<name>.cpp): its index in the
target's extension list. Usage: make_seeds.py PROJECT_DIR OUT_DIR   (writes OUT_DIR/<target>/<n>)."""
import os
import struct
import sys

EXTS = {
    "hex": ["mesh", "vtk", "vtu", "msh"],
    "skeleton": ["ig", "cg", "cgr", "skel", "obj"],
    "analysis": ["ig", "cg", "cgr", "skel", "obj"],
    "surface": ["off", "obj", "stl", "ply"],
    "medial": ["ma"],
}
MAX_SEED = 64 * 1024  # bytes: small seeds keep the fuzzers fast


def tetra_surfaces():
    pts = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    tris = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    off = "OFF\n4 4 0\n" + "".join("%g %g %g\n" % p for p in pts) + "".join("3 %d %d %d\n" % t for t in tris)
    obj = "".join("v %g %g %g\n" % p for p in pts) + "".join("f %d %d %d\n" % tuple(i + 1 for i in t) for t in tris)
    stl = "solid t\n" + "".join(
        "facet normal 0 0 0\nouter loop\n" + "".join("vertex %g %g %g\n" % pts[i] for i in t) + "endloop\nendfacet\n"
        for t in tris) + "endsolid t\n"
    bstl = b"\0" * 80 + struct.pack("<I", len(tris)) + b"".join(
        struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *pts[i]) for i in t) + b"\0\0" for t in tris)
    head = "ply\nformat %s 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n" \
           "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
    aply = head % "ascii" + "".join("%g %g %g\n" % p for p in pts) + "".join("3 %d %d %d\n" % t for t in tris)
    bply = (head % "binary_little_endian").encode() + b"".join(struct.pack("<3f", *p) for p in pts) + b"".join(
        struct.pack("<B3i", 3, *t) for t in tris)
    eply = ("ply\nformat binary_big_endian 1.0\nelement empty 5\nelement vertex 4\nproperty double x\n"
            "property double y\nproperty double z\nelement face 4\nproperty list uchar uint vertex_indices\n"
            "end_header\n").encode() + b"".join(struct.pack(">3d", *p) for p in pts) + b"".join(
        struct.pack(">B3I", 3, *t) for t in tris)
    return [(0, off.encode()), (1, obj.encode()), (2, stl.encode()), (2, bstl), (3, aply.encode()), (3, bply),
            (3, eply)]


def medial_seeds():
    return [(0, s.encode()) for s in [
        "4 4 1\nv 0 0 0 0.5\nv 1 0 0 0.25\nv 0 1 0 0.5\n\nv 5 5 5 1\ne 0 1\ne 1 2\ne 2 0\ne 2 3\nf 0 1 2\n",
        "# comment\n2 1 0\nv 0 0 0 1\nv 1 0 0 1\ne 0 1\n",
        "5 7 2\nv 0 0 0 1\nv 1 0 0 1\nv 1 1 0 1\nv 0 1 0 1\nv 2 0 0 1\n"
        "e 0 1\ne 1 2\ne 2 0\ne 2 3\ne 3 0\ne 1 4\ne 0 4\nf 0 1 2\nf 0 2 3\n",
    ]]


def main():
    root, out = sys.argv[1], sys.argv[2]
    seeds = {name: [] for name in EXTS}
    for d in ("tests/data", "data/tiny"):
        for dirpath, _, files in os.walk(os.path.join(root, d)):
            for f in sorted(files):
                ext = f.rsplit(".", 1)[-1].lower()
                path = os.path.join(dirpath, f)
                if os.path.getsize(path) > MAX_SEED:
                    continue
                data = open(path, "rb").read()
                for name, exts in EXTS.items():
                    if ext in exts and not (name == "surface" and ext == "obj" and b"\nl " in data):
                        seeds[name].append((exts.index(ext), data))
    seeds["surface"] += tetra_surfaces()
    seeds["medial"] += medial_seeds()
    for name, items in seeds.items():
        os.makedirs(os.path.join(out, name), exist_ok=True)
        for n, (selector, data) in enumerate(items):
            with open(os.path.join(out, name, "seed_%03d" % n), "wb") as fh:
                fh.write(bytes([selector]) + data)
        print("%s: %d seeds" % (name, len(items)))


if __name__ == "__main__":
    main()

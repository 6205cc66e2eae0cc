#!/usr/bin/env python3
"""Writes the damaged mesh and image files of issue 18 (and a scene per mesh)
into OUTDIR, at configure time: binary files and a 1 MB cut are easier made
than committed. Deterministic (fixed seed).

usage: make_bad_meshes.py OUTDIR TORUS_OFF
"""
import json
import os
import random
import struct
import sys

out, torus = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)


def write(name, data):
    with open(os.path.join(out, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())
    if not name.endswith(".pfm"):
        scene = {"objects": [{"mesh": name}],
                 "lights": [{"type": "rect", "center": [0, 0, 5], "normal": [0, 0, -1], "size": [1, 1]}]}
        with open(os.path.join(out, os.path.splitext(name)[0] + "_" + name.rsplit(".", 1)[1] + ".json"), "w") as f:
            json.dump(scene, f)


def ply_header(fmt, nv, nf):
    return ("ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (fmt, nv, nf)).encode()


rng = random.Random(18)
# an STL file of random bytes
write("random.stl", bytes(rng.getrandbits(8) for _ in range(4096)))
# a PLY with a header and no data
write("nodata.ply", ply_header("binary_little_endian", 3, 1))
# a binary PLY cut at 1 MB (a 200x200 grid: 40,000 vertices, 79,202 triangles)
n = 200
body = b"".join(struct.pack("<3f", i, j, 0) for j in range(n) for i in range(n))
faces = []
for j in range(n - 1):
    for i in range(n - 1):
        a = j * n + i
        faces.append(struct.pack("<B3i", 3, a, a + 1, a + n + 1))
        faces.append(struct.pack("<B3i", 3, a, a + n + 1, a + n))
full = ply_header("binary_little_endian", n * n, len(faces)) + body + b"".join(faces)
write("cut.ply", full[:1000000])
# OBJ indices: 0 (they start at 1), past the end, relative past the start
tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
write("zero_index.obj", tri + "f 0 1 2\n")
write("index_99.obj", tri + "f 1 2 99\n")
write("index_minus_99.obj", tri + "f 1 2 -99\n")
# a PLY whose header claims 999,999,999 vertices
write("huge_count.ply", ply_header("ascii", 999999999, 1) + b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
# a PLY face index 7 with 3 vertices
write("index_7.ply", ply_header("ascii", 3, 1) + b"0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
# OFF: cut after 82 of 768 faces; a header of 1536 faces over 768
lines = open(torus).read().split("\n")
nv = int(lines[1].split()[0])
write("cut_82.off", "\n".join(lines[:2 + nv + 82]) + "\n")
write("more_faces.off", "\n".join([lines[0], "%d 1536 0" % nv] + lines[2:]))
# OFF: an out-of-range index; counts of 2e9 and -5
write("index_7.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
write("huge_count.off", "OFF\n2000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
write("negative_count.off", "OFF\n-5 1 0\n0 0 0\n")
# OFF: a face that repeats a vertex (OpenMesh cannot add it: dropped with a warning)
write("repeated_vertex.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 0 3\n")
# a binary STL claiming 1e6 triangles that holds 10
t = struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0)
write("short.stl", b"\0" * 80 + struct.pack("<I", 1000000) + t * 10)
# PFM: scale 0; a 2e9 x 2e9 header; a good 1x1 reference
write("scale0.pfm", b"Pf\n1 1\n0\n" + struct.pack("<f", 0.5))
write("huge.pfm", b"Pf\n2000000000 2000000000\n-1.0\n" + struct.pack("<f", 0.5))
write("good.pfm", b"Pf\n1 1\n-1.0\n" + struct.pack("<f", 0.5))

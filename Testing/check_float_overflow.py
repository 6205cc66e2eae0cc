#!/usr/bin/env python3
"""Issue 17: an inline vertex of 1e39 (finite in JSON, beyond float) must be
dropped with a warning (scene-format.md: drop-and-warn), and the rest of the
scene must still cast: before the fix the triangle was counted as a caster,
blew up the caster set's float box, and the box cast no shadow at all.

usage: check_float_overflow.py SOFTSHADOWS SCENE OUTDIR"""
import json
import os
import subprocess
import sys

import numpy as np

exe, scene, out = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out, exist_ok=True)
stats, vis, pos = (os.path.join(out, n) for n in ("fo.json", "fo_v.pfm", "fo_p.pfm"))
env = dict(os.environ)
env.pop("DISPLAY", None)
run = subprocess.run([exe, "render", scene, "--method", "pcss", "--stats", stats, "--visibility", vis,
                      "--positions", pos, "--output", os.path.join(out, "fo.png")],
                     env=env, capture_output=True, text=True)
print(run.stderr)
failures = []
if run.returncode != 0:
    failures.append("exit code %d" % run.returncode)


def pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    kind, size, scale, body = data.split(b"\n", 3)
    w, h = map(int, size.split())
    ch = 3 if kind == b"PF" else 1
    return np.frombuffer(body, dtype="<f4").reshape(h, w, ch)


if not failures:
    s = json.load(open(stats))
    if s["triangles"] != 12:  # the box's 12; the plane does not cast
        failures.append("caster triangles %s, expected 12 (the 1e39 triangle dropped)" % s["triangles"])
    if "objects[2]: 1 vertices beyond the float range" not in run.stderr:
        failures.append("no warning naming objects[2]")
    v = pfm(vis)[:, :, 0]
    p = pfm(pos) + np.array(s["positions_origin"], dtype=np.float64)
    under = (np.abs(p[:, :, 2]) < 1e-3) & (np.abs(p[:, :, 0]) < 0.4) & (np.abs(p[:, :, 1]) < 0.4)
    n = int(under.sum())
    if n < 20:
        failures.append("only %d ground pixels under the box in view" % n)
    else:
        mean = float(v[under].mean())
        print("ground pixels under the box: %d, mean V %.3f" % (n, mean))
        if mean > 0.2:
            failures.append("the box casts no shadow: mean V under it %.3f" % mean)
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("1e39 vertex dropped with a warning; the box still casts")

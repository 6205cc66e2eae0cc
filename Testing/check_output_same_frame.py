#!/usr/bin/env python3
"""`render --output` must not change what `--visibility` reports: both come
from the last measured frame. Before, the picture was taken by one more
render (vtkWindowToImageFilter's default), which rasterises the surfaces at
slightly other positions, and --visibility reported that extra frame: the
canopy at 160 x 120 under GEARS had 42 pixels off by one light sample from
the same command without --output.

usage: check_output_same_frame.py SOFTSHADOWS SCENE OUTDIR [METHOD,...]"""
import json
import os
import subprocess
import sys

exe, scene, out = sys.argv[1:4]
methods = sys.argv[4].split(",") if len(sys.argv) > 4 else ["gears", "pcss"]
os.makedirs(out, exist_ok=True)
env = dict(os.environ)
env.pop("DISPLAY", None)
failures = []
for method in methods:
    alone = os.path.join(out, "alone_%s.pfm" % method)
    withpic = os.path.join(out, "with_picture_%s.pfm" % method)
    png = os.path.join(out, "picture_%s.png" % method)
    for cmd in ([exe, "render", scene, "--method", method, "--size", "160x120", "--visibility", alone],
                [exe, "render", scene, "--method", method, "--size", "160x120", "--visibility", withpic,
                 "--output", png]):
        run = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if run.returncode != 0:
            failures.append("%s: exit code %d: %s" % (" ".join(cmd), run.returncode, run.stderr))
    if failures:
        continue
    if not os.path.getsize(png) > 0:
        failures.append("%s: empty picture %s" % (method, png))
    cmp = subprocess.run([exe, "compare", alone, withpic], capture_output=True, text=True)
    d = json.loads(cmp.stdout)
    a = d["all"]
    print("%s: %d pixels, max |dV| %g, background mismatch %d" % (method, a["pixels"], a["max"],
                                                                 d["background_mismatch"]))
    if a["pixels"] < 1000 or a["max"] != 0.0 or d["background_mismatch"] != 0:
        failures.append("%s: V with --output differs from V without it: %s" % (method, json.dumps(d)))
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("--output leaves --visibility unchanged for %s" % ", ".join(methods))

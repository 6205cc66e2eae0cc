#!/usr/bin/env python3
"""A scene 2e6 units from the origin (a site in UTM metres, a plant in mm)
renders as the same scene at the origin: the primitives' points are double
(before, float snapped the radius-0.6 sphere to a 0.25 grid at 2e6: a lumpy
sphere and a shadow with MAE 0.01 and pixels off by 1 under every method).

usage: check_far_from_origin.py SOFTSHADOWS ORIGIN_SCENE FAR_SCENE OUTDIR"""
import json
import os
import subprocess
import sys

exe, near, far, out = sys.argv[1:5]
os.makedirs(out, exist_ok=True)
env = dict(os.environ)
env.pop("DISPLAY", None)
failures = []
for method in ("hard", "pcss", "pvsm", "gears", "reference"):
    pfm = {}
    rendered = True
    for tag, scene in (("origin", near), ("far", far)):
        pfm[tag] = os.path.join(out, "%s_%s.pfm" % (tag, method))
        run = subprocess.run([exe, "render", scene, "--method", method, "--visibility", pfm[tag],
                              "--output", os.path.join(out, "%s_%s.png" % (tag, method))],
                             env=env, capture_output=True, text=True)
        if run.returncode != 0:
            failures.append("%s %s: exit code %d: %s" % (method, tag, run.returncode, run.stderr))
            rendered = False
    if not rendered:
        continue
    cmp = subprocess.run([exe, "compare", pfm["origin"], pfm["far"]], capture_output=True, text=True)
    d = json.loads(cmp.stdout)
    a = d["all"]
    print("%-9s mae %.3g max %.3g background mismatch %d non-finite %d" % (
        method, a["mae"], a["max"], d["background_mismatch"], d["nonfinite_in_a"]))
    # the two frames differ only by rounding: at most one light sample of
    # 16 x 16 on a pixel, and no pixel changes from object to background
    if a["mae"] > 1e-4 or a["max"] > 0.01 or d["background_mismatch"] != 0:
        failures.append("%s: far from the origin differs: mae %g, max %g, background mismatch %d" % (
            method, a["mae"], a["max"], d["background_mismatch"]))
if failures:
    sys.exit("FAIL:\n  " + "\n  ".join(failures))
print("PASS")

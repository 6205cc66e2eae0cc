#!/usr/bin/env python3
"""Two scenes that must render the same frame under each method (issue 17):
- a scene 2e6 units from the origin (a site in UTM metres, a plant in mm) and
  the same scene at the origin: the primitives' points are double (before,
  float snapped the radius-0.6 sphere to a 0.25 grid at 2e6: a lumpy sphere
  and a shadow with MAE 0.01 and pixels off by 1 under every method);
- a scene and the same scene with one stray triangle 4e5 units away, out of
  view: the clipping range, the casters' float origin, the ray start offset
  and PCSS' search depth come from what is seen and from the casters' bulk
  (before, the picture was empty; with the camera fixed, V was 0 almost
  everywhere under gears and reference, and PCSS lost penumbrae).

usage: check_same_frames.py SOFTSHADOWS SCENE_A SCENE_B OUTDIR [METHOD,...]
A METHOD may carry solver options: pvsm@pvsm_map_raster=cpu (@key=value each)."""
import json
import os
import subprocess
import sys

exe, near, far, out = sys.argv[1:5]
methods = sys.argv[5].split(",") if len(sys.argv) > 5 else ["hard", "pcss", "pvsm", "gears", "reference"]
os.makedirs(out, exist_ok=True)
env = dict(os.environ)
env.pop("DISPLAY", None)
failures = []
for method in methods:
    pfm = {}
    rendered = True
    for tag, scene in (("origin", near), ("far", far)):
        pfm[tag] = os.path.join(out, "%s_%s.pfm" % (tag, method))
        name, *options = method.split("@")
        cmd = [exe, "render", scene, "--method", name, "--visibility", pfm[tag],
               "--output", os.path.join(out, "%s_%s.png" % (tag, method))]
        for o in options:
            cmd += ["--option", o]
        run = subprocess.run(cmd, env=env, capture_output=True, text=True)
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
        failures.append("%s: the frames differ: mae %g, max %g, background mismatch %d" % (
            method, a["mae"], a["max"], d["background_mismatch"]))
if failures:
    sys.exit("FAIL:\n  " + "\n  ".join(failures))
print("PASS")

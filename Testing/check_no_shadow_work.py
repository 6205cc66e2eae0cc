#!/usr/bin/env python3
"""`render --visibility` without shadow work (no shadow-casting object, or no
light) must report V = 1 on every surface pixel and NaN on the background.
Before (found by a bad-input sweep, stop 44), the pass kept no surface
positions then and every pixel came out NaN. A receiver-only scene must also
give the same surface pixels as the same scene with a caster far outside the
view (which does run the solver and keeps the positions). GEARS's backend in
use is "none" without shadow work, "cpu" with the far caster.

usage: check_no_shadow_work.py SOFTSHADOWS OUTDIR"""
import json
import math
import os
import struct
import subprocess
import sys

exe, out = sys.argv[1:3]
os.makedirs(out, exist_ok=True)
env = dict(os.environ)
env.pop("DISPLAY", None)


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        fmt = ("<" if scale < 0 else ">") + "%df" % (w * h * channels)
        return struct.unpack(fmt, f.read(4 * w * h * channels))


def scene(objects, lights):
    return {"image": {"width": 96, "height": 72},
            "camera": {"position": [0, -7, 5], "focal_point": [0, 0, 0.6], "view_up": [0, 0, 1], "view_angle": 30},
            "lights": lights, "objects": objects}


light = [{"type": "rect", "center": [0, 0, 5], "normal": [0, 0, -1], "up": [0, 1, 0], "size": [1.2, 1.2]}]
ground = {"primitive": "plane", "size": [8, 8], "color": [0.9, 0.9, 0.9], "casts_shadows": False}
far_caster = {"primitive": "sphere", "center": [300, 300, 1], "radius": 0.5}
cases = {
    "receiver_only": scene([ground], light),
    "no_lights": scene([ground, {"primitive": "sphere", "center": [0, 0, 1.2], "radius": 0.6}], []),
    "far_caster": scene([ground, far_caster], light),
}
failures = []
V = {}
for name, sc in cases.items():
    path = os.path.join(out, name + ".json")
    with open(path, "w") as f:
        json.dump(sc, f)
    for method in ("gears", "pcss"):
        vis = os.path.join(out, "%s_%s.pfm" % (name, method))
        stats = os.path.join(out, "%s_%s.json" % (name, method))
        run = subprocess.run([exe, "render", path, "--method", method, "--visibility", vis, "--stats", stats],
                             env=env, capture_output=True, text=True)
        if run.returncode != 0:
            failures.append("%s %s: exit code %d: %s" % (name, method, run.returncode, run.stderr))
            continue
        if method == "gears":
            # the backend in use is "none" when GEARS solved nothing (ParaView's
            # Gears Backend In Use), else the one that ran
            with open(stats) as f:
                backend = json.load(f)["pass"]["gears"]["backend"]
            want = "cpu" if name == "far_caster" else "none"
            print("%s, gears: backend in use %s" % (name, backend))
            if backend != want:
                failures.append("%s gears: backend in use %r, expected %r" % (name, backend, want))
        v = read_pfm(vis)
        finite = [x for x in v if not math.isnan(x)]
        print("%s, %s: %d surface pixels of %d, V in [%g, %g]" % (name, method, len(finite), len(v),
                                                                  min(finite, default=float("nan")),
                                                                  max(finite, default=float("nan"))))
        if len(finite) < len(v) // 4:
            failures.append("%s %s: only %d of %d pixels have a V" % (name, method, len(finite), len(v)))
        if name != "far_caster" and any(x != 1.0 for x in finite):
            failures.append("%s %s: V is not 1 everywhere without shadow work" % (name, method))
        V[(name, method)] = v
for method in ("gears", "pcss"):
    a, b = V.get(("receiver_only", method)), V.get(("far_caster", method))
    if a and b:
        differ = sum(1 for x, y in zip(a, b) if math.isnan(x) != math.isnan(y))
        print("%s: surface pixels differing between no shadow work and a far caster: %d" % (method, differ))
        if differ > len(a) // 200:
            failures.append("%s: the surface without shadow work is not the solver's (%d pixels)" % (method, differ))
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("no shadow work: V = 1 on every surface pixel")

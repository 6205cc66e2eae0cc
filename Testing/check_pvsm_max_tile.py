#!/usr/bin/env python3
"""PVSM's largest tile at the top of its range (pvsm_max_tile=16384) must
render like the default (4096) on the demo scene, whose tiles need less:
before (found in a ParaView sweep, stop 44), llvmpipe could not allocate the
16384^2 tile array with its mip levels, the tiles were drawn into no texture
(GL errors) and the shadows came out wrong. The solver now halves the size
until the context can hold it, and says so.

usage: check_pvsm_max_tile.py SOFTSHADOWS SCENE OUTDIR"""
import json
import os
import subprocess
import sys

exe, scene, out = sys.argv[1:4]
os.makedirs(out, exist_ok=True)
env = dict(os.environ)
env.pop("DISPLAY", None)
failures = []
vis = {}
for tile in (4096, 16384):
    vis[tile] = os.path.join(out, "tile_%d.pfm" % tile)
    stats = os.path.join(out, "tile_%d.json" % tile)
    cmd = [exe, "render", scene, "--method", "pvsm", "--size", "160x120", "--option", "pvsm_max_tile=%d" % tile,
           "--visibility", vis[tile], "--stats", stats]
    run = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if run.returncode != 0:
        failures.append("%s: exit code %d: %s" % (" ".join(cmd), run.returncode, run.stderr))
        continue
    if "GL error" in run.stderr or "OpenGL error" in run.stderr or "ERR|" in run.stderr:
        failures.append("pvsm_max_tile=%d: errors: %s" % (tile, run.stderr))
    with open(stats) as f:
        used = json.dumps(json.load(f)).split('"max_tile_used": ')[1].split(",")[0]
    print("pvsm_max_tile=%d: tiles up to %s used" % (tile, used))
if not failures:
    cmp = subprocess.run([exe, "compare", vis[4096], vis[16384]], capture_output=True, text=True)
    d = json.loads(cmp.stdout)
    a = d["all"]
    print("V: %d pixels, max |dV| %g, background mismatch %d" % (a["pixels"], a["max"], d["background_mismatch"]))
    if a["pixels"] < 1000 or a["max"] != 0.0 or d["background_mismatch"] != 0:
        failures.append("pvsm_max_tile=16384 changes V: %s" % json.dumps(d))
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("pvsm_max_tile=16384 renders like 4096")

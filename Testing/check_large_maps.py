#!/usr/bin/env python3
"""Maps at the top of their ranges, which llvmpipe allows by size (16384^2)
but cannot allocate as RG32F arrays with their mip levels (found in a
ParaView sweep, stop 44):
- PVSM's largest tile (pvsm_max_tile=16384) must render like the default
  (4096) on the demo scene, whose tiles need less; before, the tiles were
  drawn into no texture (GL errors) and the shadows came out wrong;
- shadow_map_size=16384 must render shadows (at the largest size the context
  holds, with a note when smaller); before, the command failed (no shadows);
- asm_memory_mb=4096 must render ASM's shadows (an atlas the context holds,
  with a note); before (stop 45), the light was left unshadowed.

usage: check_large_maps.py SOFTSHADOWS SCENE OUTDIR"""
import json
import os
import subprocess
import sys

exe, scene, out = sys.argv[1:4]
os.makedirs(out, exist_ok=True)
env = dict(os.environ)
env.pop("DISPLAY", None)
failures = []


def render(name, method, option):
    """Renders the scene at 160x120 with one --option; (visibility path, stats)
    or (path, None) after a failure, which it records."""
    vis_path, stats_path = os.path.join(out, name + ".pfm"), os.path.join(out, name + ".json")
    cmd = [exe, "render", scene, "--method", method, "--size", "160x120", "--option", option,
           "--visibility", vis_path, "--stats", stats_path]
    run = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if run.returncode != 0:
        failures.append("%s: exit code %d: %s" % (" ".join(cmd), run.returncode, run.stderr))
        return vis_path, None
    if "GL error" in run.stderr or "OpenGL error" in run.stderr or "ERR|" in run.stderr:
        failures.append("%s: errors: %s" % (option, run.stderr))
    with open(stats_path) as f:
        return vis_path, json.load(f)


vis = {}
for tile in (4096, 16384):
    vis[tile], st = render("tile_%d" % tile, "pvsm", "pvsm_max_tile=%d" % tile)
    if st is None:
        continue
    used = json.dumps(st).split('"max_tile_used": ')[1].split(",")[0]
    print("pvsm_max_tile=%d: tiles up to %s used" % (tile, used))
if not failures:
    cmp = subprocess.run([exe, "compare", vis[4096], vis[16384]], capture_output=True, text=True)
    d = json.loads(cmp.stdout)
    a = d["all"]
    print("V: %d pixels, max |dV| %g, background mismatch %d" % (a["pixels"], a["max"], d["background_mismatch"]))
    if a["pixels"] < 1000 or a["max"] != 0.0 or d["background_mismatch"] != 0:
        failures.append("pvsm_max_tile=16384 changes V: %s" % json.dumps(d))
# the whole-view shadow maps at 16384
vis_m, st = render("maps_16384", "pcss", "shadow_map_size=16384")
if st is not None:
    text = json.dumps(st)
    size = int(text.split('"shadow_map_size": ')[1].split(",")[0])
    note = text.split('"shadow_map_size_note": "')[1].split('"')[0]
    with open(vis_m, "rb") as f:
        f.readline()
        w, h = (int(x) for x in f.readline().split())
        sc = float(f.readline())
        import struct
        v = struct.unpack(("<" if sc < 0 else ">") + "%df" % (w * h), f.read(4 * w * h))
    shadow = sum(1 for x in v if x == x and x < 0.5)
    print("shadow_map_size=16384: maps of %d (%s), %d pixels with V < 0.5" % (size, note or "no note", shadow))
    if shadow < 100:
        failures.append("shadow_map_size=16384: no shadows (%d pixels with V < 0.5)" % shadow)
    if size < 16384 and not note:
        failures.append("shadow_map_size=16384: maps of %d without a note" % size)
# ASM's atlas at the top of asm_memory_mb's range (stop 45's Python sweep:
# 2048 and 4096 MB could not be allocated and left the light unshadowed): it
# is halved until it can be, with a note, and gives the 16 MB budget's V
# (the sphere's few nodes fit both)
vis_a = {}
for mb in (16, 4096):
    vis_a[mb], st = render("asm_%d" % mb, "asm", "asm_memory_mb=%d" % mb)
    if st is None:
        continue
    atlas = st["pass"]["asm"]["atlas"]
    print("asm_memory_mb=%d: atlas of %d bytes (%s)" % (mb, atlas["bytes"], atlas["note"] or "no note"))
    if mb == 4096 and atlas["bytes"] < (4096 << 20) // 2 and not atlas["note"]:
        failures.append("asm_memory_mb=4096: a smaller atlas without a note")
if len(vis_a) == 2 and os.path.exists(vis_a[4096]):
    d = json.loads(subprocess.run([exe, "compare", vis_a[4096], vis_a[16]], capture_output=True, text=True).stdout)
    print("asm 4096 MB vs 16 MB: %s" % d["all"])
    if d["all"]["pixels"] < 1000 or d["all"]["max"] != 0.0:
        failures.append("asm_memory_mb=4096 changes V: %s" % json.dumps(d["all"]))
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("pvsm_max_tile=16384 renders like 4096; shadow_map_size=16384 renders shadows; asm's atlas fits the context")

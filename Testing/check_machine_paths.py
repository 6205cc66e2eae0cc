#!/usr/bin/env python3
"""Renders the demo scene the way other machines would, on this one, and
checks each path gives the result it should (issue 16's audit):

- llvmpipe with 1 or 4 rasteriser threads (core counts differ): V identical;
- a GPU whose GL_MAX_TEXTURE_SIZE is 1024: a 4096 shadow map request is
  capped at 1024 with a note in the stats (not an allocation failure), V
  identical to asking for 1024; PVSM's tiles stay within the limit;
- an OpenGL 3.2 context: the map methods run (PVSM with the GPU's map too),
  GEARS's GL backend falls back
  to the CPU with the reason in the stats, V identical to the 4.5 context;
- a small SSBO limit: GEARS's GL backend falls back with the reason, and so
  do the translucent receivers' fragment lists (the same picture);
- Embree on AVX2 and SSE4.2 kernels (when this CPU has them): the reference's
  V identical to the widest ISA's;
- GEARS on AVX2 and scalar kernels (SOFTSHADOWS_GEARS_ISA): V identical to
  the widest kernels', the stats naming the kernels that ran.

usage: check_machine_paths.py SOFTSHADOWS SCENE OUTDIR
"""
import json
import os
import subprocess
import sys

cli, scene, out = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out, exist_ok=True)
failures = []


def render(name, method, env=None, options=()):
    e = dict(os.environ)
    e.pop("DISPLAY", None)
    e.update(env or {})
    vis = os.path.join(out, name + "_v.pfm")
    stats = os.path.join(out, name + ".json")
    cmd = [cli, "render", scene, "--method", method, "--size", "200x150",
           "--visibility", vis, "--stats", stats]
    for o in options:
        cmd += ["--option", o]
    r = subprocess.run(cmd, env=e, capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        failures.append(f"{name}: exit {r.returncode}: {r.stderr.strip()[-400:]}")
        return None, None
    with open(stats) as f:
        return vis, json.load(f)


def compare(a, b):
    r = subprocess.run([cli, "compare", a, b], capture_output=True, text=True)
    if r.returncode != 0:
        return None
    return json.loads(r.stdout)


def check(ok, what):
    print(("ok:   " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


def identical(name, a, b):
    if a is None or b is None:
        return
    c = compare(a, b)
    check(c is not None and c["all"]["max"] == 0.0 and c["background_mismatch"] == 0
          and c["all"]["pixels"] > 1000, f"{name}: V identical ({c and c['all']})")


# llvmpipe thread counts
for m in ("pcss", "pvsm"):
    a, _ = render(f"lp1_{m}", m, {"LP_NUM_THREADS": "1"})
    b, _ = render(f"lp4_{m}", m, {"LP_NUM_THREADS": "4"})
    identical(f"{m} with 1 and 4 llvmpipe threads", a, b)

# a smaller texture limit
small = {"SOFTSHADOWS_GL_MAX_TEXTURE_SIZE": "1024"}
a, sa = render("limit_pcss", "pcss", small, ["shadow_map_size=4096"])
b, sb = render("ask1024_pcss", "pcss", None, ["shadow_map_size=1024"])
if sa:
    check(sa["pass"]["shadow_map_size"] == 1024, "4096 request capped at the 1024 limit")
    check("capped" in sa["pass"]["shadow_map_size_note"], "the cap is noted in the stats")
if sb:
    check(sb["pass"]["shadow_map_size_note"] == "", "no note when nothing is capped")
identical("pcss capped at 1024 vs asked for 1024", a, b)
a, sa = render("limit_pvsm", "pvsm", small)
b, sb = render("tile1024_pvsm", "pvsm", None, ["pvsm_max_tile=1024", "pvsm_low_resolution=1024"])
if sa:
    check(sa["pass"]["shadow_map_size"] <= 1024, "PVSM's low-resolution map within the limit")
identical("pvsm under a 1024 limit vs tiles capped at 1024", a, b)

# an OpenGL 3.2 context
gl32 = {"MESA_GL_VERSION_OVERRIDE": "3.2", "MESA_GLSL_VERSION_OVERRIDE": "150"}
for m in ("pcss", "pvsm"):
    a, _ = render(f"gl32_{m}", m, gl32)
    b, _ = render(f"gl45_{m}", m)
    identical(f"{m} on GL 3.2 vs 4.5", a, b)
# PVSM's conservative map as a GPU machine draws it (the geometry shader;
# llvmpipe picks the CPU raster), on GL 3.2 and 4.5
a, sa = render("gl32_pvsm_gpu_map", "pvsm", gl32, ["pvsm_map_raster=gpu"])
b, sb = render("gl45_pvsm_gpu_map", "pvsm", None, ["pvsm_map_raster=gpu"])
identical("pvsm with the GPU's map on GL 3.2 vs 4.5", a, b)
for tag, st, want in (("GL 3.2", sa, "gpu"), ("GL 4.5", sb, "gpu")):
    if st:
        check(st["pass"]["pvsm"]["map_raster"] == want, f"pvsm_map_raster=gpu on {tag}: the map is the GPU's")
# auto on llvmpipe: the CPU when the casters have at least S^2 / 8 triangles
# (the demo's 5,218 against a 64^2 map), else the geometry shader (1024^2)
_, sc = render("gl45_pvsm_auto_map64", "pvsm", None, ["pvsm_low_resolution=64"])
if sc:
    check(sc["pass"]["pvsm"]["map_raster"] == "cpu", "pvsm_map_raster=auto, 64^2 map: the map is the CPU's")
_, sc = render("gl45_pvsm_auto_map1024", "pvsm", None, ["pvsm_low_resolution=1024"])
if sc:
    check(sc["pass"]["pvsm"]["map_raster"] == "gpu", "pvsm_map_raster=auto, 1024^2 map: the map is the GPU's")
b, sb = render("cpu_gears", "gears", None, ["gears_backend=cpu"])


def gears_falls_back(name, env, reason, what):
    """GEARS asked for the GL backend under `env` runs on the CPU, with
    `reason` in its note, and gives the CPU backend's V."""
    a, sa = render(name, "gears", env, ["gears_backend=gl"])
    if sa:
        g = sa["pass"]["gears"]
        check(g["backend"] == "cpu" and reason in g["backend_note"], f"GEARS GL {what} falls back: {g['backend_note']}")
    identical(f"gears {name} vs CPU", a, b)


gears_falls_back("gl32_gears", gl32, "4.3", "on GL 3.2")
# a small SSBO limit
gears_falls_back("ssbo_gears", {"SOFTSHADOWS_GL_MAX_SSBO_BYTES": "100000"}, "SSBO limit", "beyond the SSBO limit")
# fewer storage buffer bindings than the GL backend's buffers (GL 4.3
# guarantees 8): it declines, naming the limit, and the CPU backend runs
gears_falls_back("bindings_gears", {"SOFTSHADOWS_GL_MAX_SSBO_BINDINGS": "16"}, "storage buffer bindings",
                 "with too few SSBO bindings")

# translucent receivers whose fragment lists exceed a small SSBO limit: the
# shading runs their lookups itself (the way without the lists), with the
# reason in the stats, and the picture is the lists' picture
sheet = os.path.join(os.path.dirname(scene), "translucent_sheet.json")


def render_sheet(name, env):
    e = dict(os.environ)
    e.pop("DISPLAY", None)
    e.update(env)
    png, stats = os.path.join(out, name + ".png"), os.path.join(out, name + ".json")
    r = subprocess.run([cli, "render", sheet, "--method", "vpcss", "--size", "200x150", "--output", png,
                        "--stats", stats], env=e, capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        failures.append(f"{name}: exit {r.returncode}: {r.stderr.strip()[-400:]}")
        return None, None, ""
    with open(stats) as f:
        return png, json.load(f)["pass"]["translucent_receivers"], r.stderr


la, ta, _ = render_sheet("sheet_lists", {})
lb, tb, errb = render_sheet("sheet_small_ssbo", {"SOFTSHADOWS_GL_MAX_SSBO_BYTES": "100000"})
if ta and tb:
    check(ta["listed"] and ta["fragments"] > 0 and ta["note"] == "", f"the sheet's fragments are listed: {ta}")
    check(not tb["listed"] and "storage block" in tb["note"] and "storage block" in errb,
          f"lists over a 100 kB SSBO limit fall back with the reason: {tb}")
    r = subprocess.run(["idiff", "-fail", "0.0040", "-failpercent", "0.01", la, lb], capture_output=True, text=True)
    check(r.returncode in (0, 1), f"the fallback's picture is the lists' (idiff exit {r.returncode}): "
          f"{r.stdout.strip()[-200:]}")

# fewer array layers than the lights need: a clear error, not a wrong picture
e = dict(os.environ)
e.pop("DISPLAY", None)
e["SOFTSHADOWS_GL_MAX_ARRAY_TEXTURE_LAYERS"] = "1"
two = os.path.join(os.path.dirname(scene), "two_lights.json")
r = subprocess.run([cli, "render", two, "--method", "pcss", "--size", "64x48",
                    "--output", os.path.join(out, "layers.png")], env=e, capture_output=True, text=True, timeout=300)
check(r.returncode == 2 and "array texture layers" in r.stderr,
      f"two lights over a 1-layer limit: exit {r.returncode}, {r.stderr.strip()[-200:]}")

# Embree ISAs this CPU has
flags = open("/proc/cpuinfo").read()
a, _ = render("isa_default_ref", "reference", None, ["reference_samples=6"])
for isa, flag in (("avx2", " avx2"), ("sse4.2", " sse4_2")):
    if flag not in flags:
        print(f"skip: this CPU has no {isa}")
        continue
    b, _ = render(f"isa_{isa}_ref", "reference", {"SOFTSHADOWS_EMBREE_ISA": isa}, ["reference_samples=6"])
    identical(f"reference on Embree {isa} kernels vs the widest", a, b)

# GEARS's kernels of narrower ISAs (SOFTSHADOWS_GEARS_ISA): the stats name
# them, and V is the widest kernels' (bit-identical bitmasks)
a, sa = render("gears_isa_default", "gears", None, ["gears_backend=cpu"])
for isa, flag in (("avx2", " avx2"), ("scalar", "")):
    if flag and flag not in flags:
        print(f"skip: this CPU has no {isa}")
        continue
    b, sb = render(f"gears_isa_{isa}", "gears", {"SOFTSHADOWS_GEARS_ISA": isa}, ["gears_backend=cpu"])
    if sb:
        check(sb["pass"]["gears"]["stats"]["simd"] == isa,
              f"SOFTSHADOWS_GEARS_ISA={isa}: the stats say {sb['pass']['gears']['stats']['simd']}")
    identical(f"gears on {isa} kernels vs the widest ({sa and sa['pass']['gears']['stats']['simd']})", a, b)

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("all machine paths agree")

"""Checks what `softshadows bench --pvsm --smoke` wrote: for every camera
(overview, close-up) and light (large, small) a reference row and measured
pvsm, fixed-PCSS and hardavg rows with positive times, finite errors in [0, 1]
(the picture error at most the V error)
and no non-finite visibility; PVSM without tile culling gives the same error
(the same maps) after drawing more caster triangles into the tiles; hardavg rendered k x k maps; the point-light
PVSM rows for the large light; an anti-aliased reference row and errors
against it; the report with both tables."""
import json
import math
import os
import sys

out = sys.argv[1]
maps_expected = int(sys.argv[2]) if len(sys.argv) > 2 else 4
failures = []
rows = json.load(open(os.path.join(out, "pvsm-bench.json")))
md = open(os.path.join(out, "pvsm-bench.md")).read()
csv = open(os.path.join(out, "pvsm-bench.csv")).read().splitlines()
if len(csv) != len(rows) + 1:
    failures.append("CSV has %d lines for %d rows" % (len(csv), len(rows)))
for cam in ("overview", "close-up"):
    for light in ("large", "small"):
        got = {r["config"]: r for r in rows if r["camera"] == cam and r["light"] == light}
        want = ["reference", "reference anti-aliased", "pvsm", "pvsm no tile culling", "pcss fixed", "hardavg"] + (["pvsm point light"] if light == "large" else [])
        for c in want:
            if c not in got:
                failures.append("no %s row for %s/%s" % (c, cam, light))
        for c, r in got.items():
            if not (r["ms"] > 0 and math.isfinite(r["ms"])):
                failures.append("bad time in %s" % r)
            if c in ("pvsm", "pvsm no tile culling", "pcss fixed", "hardavg"):
                for k in ("mae", "max", "penumbra_mae", "picture_mae", "aa_mae", "aa_penumbra_mae"):
                    if not (k in r and 0.0 <= r[k] <= 1.0):
                        failures.append("bad %s in %s" % (k, r))
                # the picture error weights V's error by a factor in [0, 1]
                if "picture_mae" in r and "mae" in r and r["picture_mae"] > r["mae"] + 1e-12:
                    failures.append("picture error above the V error in %s" % r)
                if r.get("nonfinite", 1) != 0:
                    failures.append("non-finite visibility in %s" % r)
        if "pvsm" in got and "pvsm no tile culling" in got:
            a, b = got["pvsm"], got["pvsm no tile culling"]
            if a.get("mae") != b.get("mae") or a.get("tiles") != b.get("tiles"):
                failures.append("tile culling changed the result: %s vs %s" % (a, b))
            if not (0 < a.get("tile_triangles", 0) <= b.get("tile_triangles", 0)):
                failures.append("culled tiles drew more triangles than the whole set: %s vs %s" % (a, b))
        if "hardavg" in got and got["hardavg"].get("maps") != maps_expected:
            failures.append("hardavg rendered %s maps, expected %d" % (got["hardavg"].get("maps"), maps_expected))
        for c in ("pvsm", "pvsm point light"):
            if c in got and not got[c].get("texels", 0) > 0:
                failures.append("%s rendered no texels: %s" % (c, got[c]))
if "| scene | camera | light | config |" not in md or "hardavg / PVSM time" not in md or "no culling / culling time" not in md or "AA MAE" not in md:
    failures.append("report lacks its tables")
for f in failures:
    print("FAIL: " + f)
sys.exit(1 if failures else 0)

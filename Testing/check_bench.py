"""Checks what `softshadows bench --smoke` wrote: the report, CSV and JSON with
one reference row and measured rows (positive times, finite errors in [0,1],
PCSS more accurate than hard shadows against the area-light reference), and a
non-empty plot PNG."""
import json
import math
import os
import sys

out = sys.argv[1]
failures = []
rows = json.load(open(os.path.join(out, "accuracy-vs-time.json")))
md = open(os.path.join(out, "accuracy-vs-time.md")).read()
csv = open(os.path.join(out, "accuracy-vs-time.csv")).read().splitlines()
if len(csv) != len(rows) + 1:
    failures.append("CSV has %d lines for %d rows" % (len(csv), len(rows)))
methods = [r["method"] for r in rows]
for m in ("reference", "hard", "pcss", "gears", "pvsm", "hardavg", "vtk"):
    if m not in methods:
        failures.append("no %s row" % m)
for r in rows:
    if not (r["ms"] > 0 and math.isfinite(r["ms"])):
        failures.append("bad time in %s" % r)
    if "mae" in r:
        for k in ("mae", "max", "p99", "penumbra_mae"):
            if not (0.0 <= r[k] <= 1.0):
                failures.append("bad %s in %s" % (k, r))
        if r["nonfinite"] != 0:
            failures.append("non-finite visibility in %s" % r)
err = {r["method"]: r.get("mae") for r in rows if r["method"] in ("hard", "pcss")}
if not (err.get("pcss") is not None and err.get("hard") is not None and err["pcss"] < err["hard"]):
    failures.append("PCSS is not closer to the area-light reference than hard shadows: %s" % err)
plots = os.path.join(out, "plots")
pngs = [p for p in os.listdir(plots) if p.endswith(".png")] if os.path.isdir(plots) else []
if not pngs or os.path.getsize(os.path.join(plots, pngs[0])) < 5000:
    failures.append("no plot")
if "| method | settings | ms |" not in md or "![" not in md:
    failures.append("report lacks its table or plot")
for f in failures:
    print("FAIL: " + f)
print("%d rows checked" % len(rows))
sys.exit(1 if failures else 0)

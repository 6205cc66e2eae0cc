"""Checks what `softshadows bench --asm --smoke` wrote: one row per frame and
configuration (the uniform map and two ASM budgets) with a positive time, a
finite error in [0, 1] against the exact hard shadow and no non-finite
visibility; every ASM row within its memory budget (the budget is never
exceeded) with an effective resolution of at least its page; the CSV, the
report with both tables, the per-frame plot and the pictures it names."""
import json
import math
import os
import re
import sys

out = sys.argv[1]
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 4
failures = []
rows = json.load(open(os.path.join(out, "asm-bench.json")))
md = open(os.path.join(out, "asm-bench.md")).read()
csv = open(os.path.join(out, "asm-bench.csv")).read().splitlines()
if len(csv) != len(rows) + 1:
    failures.append("CSV has %d lines for %d rows" % (len(csv), len(rows)))
configs = sorted({r["config"] for r in rows})
if len(configs) != 3 or not any(c.startswith("uniform") for c in configs):
    failures.append("expected the uniform map and two ASM budgets, got %s" % configs)
for c in configs:
    got = sorted(r["frame"] for r in rows if r["config"] == c)
    if got != list(range(frames)):
        failures.append("%s: frames %s, expected 0..%d" % (c, got, frames - 1))
for r in rows:
    tag = "%s frame %d" % (r["config"], r["frame"])
    if not (r["ms"] > 0 and math.isfinite(r["ms"])):
        failures.append(tag + ": time %r" % r["ms"])
    if "mae" not in r or not (0.0 <= r["mae"] <= 1.0):
        failures.append(tag + ": error %r" % r.get("mae"))
    if r.get("nonfinite", 0) != 0:
        failures.append(tag + ": %d non-finite V" % r["nonfinite"])
    if r["config"].startswith("asm"):
        if not (0 < r["asm_memory_bytes"] <= r["asm_budget_bytes"]):
            failures.append(tag + ": memory %r of budget %r" % (r["asm_memory_bytes"], r["asm_budget_bytes"]))
        if r["effective_resolution"] < 64:
            failures.append(tag + ": effective resolution %r" % r["effective_resolution"])
for heading in ("| scene | config | median ms", "## Against the targets"):
    if heading not in md:
        failures.append("report lacks %r" % heading)
for f in re.findall(r"`(asm-[^`<]*\.png)`", md) + ["asm-bench-wires.png"]:
    p = os.path.join(out, f)
    if not (os.path.exists(p) and os.path.getsize(p) > 1000):
        failures.append("picture %s missing or empty" % f)
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("bench --asm smoke: %d rows, %d configurations checked" % (len(rows), len(configs)))

#!/usr/bin/python3
"""Checks a `softshadows bench --gears` smoke run: the report and data exist, every
row has finite times, GEARS's V equals the reference's on nearly every pixel (same
samples), the necessary assignments are a part of the total, and the GL backend,
where it ran, is bit-identical to the CPU backend. With a second argument N, the
report was merged by --report-from from N copies of one run."""
import json
import math
import sys
from pathlib import Path

out = Path(sys.argv[1])
md = (out / "gears-bench.md").read_text()
assert "## Time and equality" in md and "## Assignments" in md and "## Process CPU time" in md, "gears-bench.md lacks its tables"
data = json.loads((out / "gears-bench.json").read_text())
rows = data["rows"]
assert rows, "no rows"
for r in rows:
    name = f'{r["scene"]} {r["width"]}x{r["height"]} k={r["k"]}'
    for key in ("minimal_ms", "reference_ms", "gears_ms", "lut_ms", "minimal_cpu_ms", "reference_cpu_ms", "gears_cpu_ms"):
        assert math.isfinite(r[key]) and r[key] > 0, f"{name}: {key} = {r[key]}"
    assert r["gears_vs_reference"]["equal_fraction"] >= 0.999, f"{name}: GEARS differs from the reference"
    assert r["gears_vs_reference"]["max_diff_samples"] <= 2, f"{name}: a pixel differs by > 2 samples"
    assert r["minimal_vs_reference"]["equal_fraction"] >= 0.999, f"{name}: minimal loop differs from the reference"
    a = r["necessary_stats"]["assignments"]
    assert 0 < a["necessary"] <= a["total"] <= r["necessary_stats"]["assignments_listed"], f"{name}: {a}"
    assert r["necessary_identical"] == 1.0, f"{name}: counting necessary assignments changed V"
    if r.get("gl_ran"):
        assert r["gl_identical_fraction"] == 1.0, f"{name}: GL backend differs from the CPU"
# an optional second argument: the number of runs merged by --report-from (each run's
# rows kept, in order, and the report says how many runs it holds)
if len(sys.argv) > 2:
    runs = int(sys.argv[2])
    assert data["meta"]["runs"] == runs, f'meta.runs = {data["meta"].get("runs")}, expected {runs}'
    n = len(rows) // runs
    assert len(rows) % runs == 0 and all(rows[i * n : (i + 1) * n] == rows[:n] for i in range(runs)), "rows not kept in order"
    assert f"in {runs} runs (`--report-from`)" in md, "the report does not say it merges runs"
print(f"gears bench smoke: {len(rows)} rows OK")

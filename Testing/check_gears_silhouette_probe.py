#!/usr/bin/python3
"""Checks a `softshadows bench --gears --silhouette-probe` smoke run: the probe's data
exist, the silhouette winding raster solved some (pixel, piece) pairs, every one of
them identical to the triangle raster, and only receivers on a piece were declined."""
import json
import sys
from pathlib import Path

data = json.loads((Path(sys.argv[1]) / "gears-silhouette-probe.json").read_text())
rows = data["rows"]
assert rows, "no rows"
for r in rows:
    name = f'{r["scene"]} {r["width"]}x{r["height"]} k={r["k"]}'
    assert r["pieces"] > 0 and r["pixels_probed"] > 0, f"{name}: nothing probed"
    assert r["piece_pixels_solved"] > 0, f"{name}: the winding raster solved nothing: {r['declined']}"
    assert r["identical_to_triangle_raster"] == r["piece_pixels_solved"], \
        f'{name}: {r["piece_pixels_solved"] - r["identical_to_triangle_raster"]} masks differ from the triangle raster'
    for why in r["declined"]:
        assert "start rule" in why, f"{name}: declined for another reason: {why}"
    assert r["cell_candidate_edges_per_pixel"] >= r["silhouette_edges_per_pixel"], \
        f"{name}: the per-cell candidate rule keeps fewer edges than one pixel's silhouette"
print(f"gears silhouette probe smoke: {len(rows)} rows OK")

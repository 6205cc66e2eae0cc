#!/bin/bash
# PVSM vs fixed-4096 PCSS against the 16x16 reference, one run, median of 3 frames
cd "$(dirname "$0")/.."
out=${1:-/tmp/pvsm-bench}; mkdir -p $out
echo "scene,config,ms,mae,pen_mae,tiles,texels" > $out/results.csv
for sc in demo bunny canopy field_iso_1m; do
  f=Data/Scenes/$sc.json
  xvfb-run -a build/bin/softshadows render $f --method reference --option reference_samples=16 --visibility $out/${sc}_ref.pfm > /dev/null 2>&1
  run() { # name method options...
    local name=$1; shift; local m=$1; shift
    local opts=(); for o in "$@"; do opts+=(--option $o); done
    xvfb-run -a build/bin/softshadows render $f --method $m "${opts[@]}" --frames 3 --visibility $out/${sc}_$name.pfm --stats $out/${sc}_$name.json > /dev/null 2>&1
    python3 - "$sc" "$name" "$out" <<'PY'
import json, subprocess, sys
sc, name, out = sys.argv[1:]
st = json.load(open(f"{out}/{sc}_{name}.json"))
c = json.loads(subprocess.check_output(["build/bin/softshadows", "compare", f"{out}/{sc}_{name}.pfm", f"{out}/{sc}_ref.pfm"]))
p = st["pass"].get("pvsm", {}).get("stats", {})
ms = st["timings_ms"].get("median_frame", None)
print(",".join(str(x) for x in [sc, name, st["timings_ms"]["total"], c["all"]["mae"], c["penumbra"]["mae"], p.get("tiles", ""), p.get("texels_rendered", "")]))
PY
  }
  run pcss4096 pcss shadow_map_size=4096 >> $out/results.csv
  run pcss2048 pcss shadow_map_size=2048 >> $out/results.csv
  run pvsm_q0.5 pvsm pvsm_quality=0.5 >> $out/results.csv
  run pvsm_q1 pvsm >> $out/results.csv
  run pvsm_q2 pvsm pvsm_quality=2 >> $out/results.csv
done
# the table for Documentation/pvsm-bench.md
python3 - "$out/results.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| scene | config | ms/frame (median of 3) | MAE | penumbra MAE | tiles | texels rendered |")
print("|---|---|---|---|---|---|---|")
for r in rows:
    tex = f"{float(r['texels'])/1e6:.1f} M" if r["texels"] else "-"
    print(f"| {r['scene']} | {r['config']} | {float(r['ms']):.0f} | {float(r['mae']):.4f} | {float(r['pen_mae']):.4f} | {r['tiles'] or '-'} | {tex} |")
PY

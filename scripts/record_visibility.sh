#!/usr/bin/env bash
# Records V (--visibility) and the stats of every method on every scene of
# Data/Scenes, so that a refactoring can show that nothing moved:
#
#   scripts/record_visibility.sh record OUT [SOFTSHADOWS]   render everything into OUT
#   scripts/record_visibility.sh compare BEFORE AFTER       one table row per render
#
# `compare` says per scene, method and light whether the two V files are
# byte-identical, the max |difference| that `softshadows compare` prints, and
# whether the stats are the same once timings are dropped (the keys of
# timings_ms must still match). It exits non-zero when anything differs.
# SCENES="demo bunny" or METHODS="pcss gears_gl" restrict a run (names below);
# PARTIAL=1 compares such a subset (BEFORE) with a full recording (AFTER).
#
# Sizes: each scene's default, except 256x192 for the 1M/5M-triangle scenes
# and for reference and hardavg (the slow ones); the same arguments every run.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

all_methods="hard pcf pcss pvsm hardavg reference gears_cpu gears_gl auto none"

method_args() { # config name -> softshadows arguments
  case "$1" in
    gears_cpu) echo "--method gears --option gears_backend=cpu" ;;
    gears_gl) echo "--method gears --option gears_backend=gl" ;;
    *) echo "--method $1" ;;
  esac
}

size_args() { # scene config -> --size or nothing
  case "$1" in
    assembly_5m | field_iso_1m) echo "--size 256x192"; return ;;
  esac
  case "$2" in
    reference | hardavg) echo "--size 256x192" ;;
  esac
}

record() {
  local out=$1 bin=${2:-$here/build/bin/softshadows}
  mkdir -p "$out"
  : > "$out/failures.txt"
  local scenes=${SCENES:-$(cd "$here/Data/Scenes" && ls *.json | sed 's/\.json$//')}
  for sc in $scenes; do
    local f="$here/Data/Scenes/$sc.json"
    local nlights
    nlights=$(/usr/bin/python3 -c "import json,sys; print(len(json.load(open(sys.argv[1])).get('lights', [])))" "$f")
    for m in ${METHODS:-$all_methods}; do
      local lights=$((nlights > 0 ? nlights : 1))
      [ "$m" = none ] && lights=1 # no shadow light: --light 1 is out of range
      for ((light = 0; light < lights; ++light)); do
        local name="$sc.$m.light$light"
        # shellcheck disable=SC2046
        if ! nice "$bin" render "$f" $(method_args "$m") $(size_args "$sc" "$m") --light "$light" \
          --visibility "$out/$name.pfm" --stats "$out/$name.json" > "$out/$name.log" 2>&1; then
          echo "$name" >> "$out/failures.txt"
          echo "record: $name failed (see $out/$name.log)" >&2
        fi
      done
    done
  done
}

# The stats without what varies from run to run (timings, rays per second,
# the scene's absolute path); timings_ms keeps its keys.
stable_stats() {
  jq -S 'walk(if type == "object" then ((if has("timings_ms") then .timings_ms |= keys else . end)
    | del(.ms, .rays_per_second)) else . end) | del(.scene)' "$1"
}

compare() {
  local a=$1 b=$2 bin=${3:-$here/build/bin/softshadows} bad=0
  echo "| scene | method | light | V bytes | max abs diff | stats |"
  echo "|---|---|---|---|---|---|"
  for fa in "$a"/*.pfm; do
    local name
    name=$(basename "$fa" .pfm)
    local fb="$b/$name.pfm"
    IFS=. read -r sc m light <<< "$name"
    if [ ! -f "$fb" ]; then
      echo "| $sc | $m | ${light#light} | missing | - | - |"
      bad=1
      continue
    fi
    local same="identical" maxd stats="same"
    cmp -s "$fa" "$fb" || { same="differ"; bad=1; }
    maxd=$("$bin" compare "$fb" "$fa" | jq -r '"\(.all.max) (bg mismatch \(.background_mismatch))"')
    if ! diff -q <(stable_stats "$a/$name.json") <(stable_stats "$b/$name.json") > /dev/null; then
      stats="differ"
      bad=1
    fi
    echo "| $sc | $m | ${light#light} | $same | $maxd | $stats |"
  done
  [ -n "${PARTIAL:-}" ] && return $bad # BEFORE holds a subset (SCENES/METHODS) on purpose
  for fb in "$b"/*.pfm; do
    [ -f "$a/$(basename "$fb")" ] || { echo "| $(basename "$fb" .pfm) | only in $b |"; bad=1; }
  done
  return $bad
}

case "${1:-}" in
  record) shift; record "$@" ;;
  compare) shift; compare "$@" ;;
  *) echo "usage: $0 record OUT [SOFTSHADOWS] | compare BEFORE AFTER [SOFTSHADOWS]" >&2; exit 2 ;;
esac

#!/usr/bin/env bash
# Long libFuzzer runs of the reader guards (Testing/Fuzz), for developers:
#   scripts/fuzz.sh [SECONDS] [TARGET...]      (default 600 s; all targets)
# Targets: off ply stl obj pfm scene. Needs the clang build that the main
# build makes when clang++ is installed (build/fuzz-clang). Each target runs
# under `nice` for SECONDS on its committed corpus (Testing/Fuzz/corpus/T);
# new inputs and any crash go to build/fuzz-runs/T. A finding stops the script
# with the crash file's path. After a clean run the inputs that add coverage
# are merged into the committed corpus (libFuzzer -merge=1, inputs up to
# 4 KiB), so the corpus grows only by what the run found new.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-600}"
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(off ply stl obj pfm scene)
bin="$here/build/fuzz-clang"
for t in "${targets[@]}"; do
  if [ ! -x "$bin/fuzz_$t" ]; then
    echo "fuzz.sh: $bin/fuzz_$t missing: build the main tree with clang++ installed" >&2
    exit 2
  fi
done
mkdir -p "$here/build/fuzz-runs"
for t in "${targets[@]}"; do
  runs="$here/build/fuzz-runs/$t"
  corpus="$here/Testing/Fuzz/corpus/$t"
  echo "fuzz.sh: $t for ${seconds}s ($(date -u +%H:%M:%S))"
  if ! nice -n 10 "$here/Testing/Fuzz/run_fuzzer.sh" "$bin/fuzz_$t" "$runs" "$corpus" "$seconds" \
      > "$runs.log" 2>&1; then
    echo "fuzz.sh: $t: FINDING (see $runs.log and $runs/crash-* / leak-* / timeout-* / oom-*)" >&2
    tail -n 30 "$runs.log" >&2
    exit 1
  fi
  grep -E "^stat::(number_of_executed_units|peak_rss_mb)|DONE" "$runs.log" || tail -n 3 "$runs.log"
  mkdir -p "$runs.tmp"
  ASAN_OPTIONS=detect_leaks=0 TMPDIR="$runs.tmp" nice -n 10 "$bin/fuzz_$t" -merge=1 -max_len=4096 \
    "$corpus" "$runs" > "$runs.merge.log" 2>&1 || true
  echo "fuzz.sh: $t: clean; corpus now $(ls "$corpus" | wc -l) files"
done

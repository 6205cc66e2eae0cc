#!/usr/bin/env bash
# run_fuzzer.sh FUZZER SCRATCH_DIR CORPUS_DIR SECONDS [extra libFuzzer flags]
# Runs a libFuzzer target for SECONDS on the committed corpus; new inputs go to
# SCRATCH_DIR (emptied first), crash files too. Fails on any finding.
set -euo pipefail
fuzzer="$1"; scratch="$2"; corpus="$3"; seconds="$4"; shift 4
rm -rf "$scratch"; mkdir -p "$scratch"
# ASan: leaks inside VTK's and OpenMesh's singletons are not findings here.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0:abort_on_error=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
mkdir -p "$scratch.tmp"; export TMPDIR="$scratch.tmp"
exec "$fuzzer" -max_total_time="$seconds" -rss_limit_mb=4096 -timeout=60 -print_final_stats=1 \
  -artifact_prefix="$scratch/" "$@" "$scratch" "$corpus"

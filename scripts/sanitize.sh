#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer,
# in its own build directory (build-asan), with one command:
#   scripts/sanitize.sh [ctest arguments, e.g. -R cli]
#   scripts/sanitize.sh --build-only
# Every target of the project (libraries, Python modules, the ParaView plugin,
# the CLI, the tests) is compiled and linked with -fsanitize=address,undefined
# (GCC; UB aborts: -fno-sanitize-recover). The flags come in through CFLAGS,
# CXXFLAGS and LDFLAGS, so the install test's own CMake project gets them too.
# Python and pvpython are not instrumented: the tests that load our modules
# into them preload libasan (CMake adds `env LD_PRELOAD=...` to those test
# commands when it sees -fsanitize=address). Leak detection is off: VTK,
# Mesa, Python and ParaView keep allocations to exit by design, and their
# reports would drown ours; ASan's memory errors and UBSan stay fatal.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
san="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
export CFLAGS="$san -g" CXXFLAGS="$san -g" LDFLAGS="-fsanitize=address,undefined"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_init_order=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
if [ ! -f build-asan/CMakeCache.txt ]; then
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOFTSHADOWS_LIBFUZZER=OFF
fi
nice cmake --build build-asan -j "$(nproc 2>/dev/null || echo 2)"
# the large scene meshes are shared with the main tree (scripts/setup.sh)
if [ ! -f Data/Meshes/generated/assembly_5m.ply ]; then
  /usr/bin/python3 scripts/generate_scenes.py --large
fi
[ "${1:-}" = "--build-only" ] && exit 0
cd build-asan
ctest --output-on-failure -j 2 "$@"

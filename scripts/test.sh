#!/usr/bin/env bash
# Quick start 2: set up, build, and run the whole test suite (headless).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/scripts/setup.sh"
cd "$here/build"
ctest --output-on-failure -j 2 "$@"

#!/usr/bin/env bash
# Quick start 1: set up, build, and render the demo scene with soft shadows.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/scripts/setup.sh"
cd "$here"
mkdir -p out
./build/bin/softshadows render Data/Scenes/demo.json --method auto \
  --output out/demo.png --visibility out/demo-visibility.pfm --positions out/demo-positions.pfm \
  --stats out/demo-stats.json --frames 3

#!/usr/bin/env bash
# Installs what is missing (Debian 12, idempotent) and builds SoftShadows in ./build.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"

want=$(grep -v '^#' scripts/debian-packages.txt | grep -v '^$')
missing=()
for p in $want; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian package(s): ${missing[*]}"
  sudo_cmd=""
  if [ "$(id -u)" != 0 ]; then sudo_cmd="sudo"; fi
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc 2>/dev/null || echo 2)
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build -j "$jobs"

# Meshes of the scene suite that are generated or extracted (not committed).
if [ ! -f Data/Meshes/generated/assembly_5m.ply ] || [ ! -f Data/Meshes/generated/field_iso_1m.ply ]; then
  /usr/bin/python3 scripts/generate_scenes.py --large
fi

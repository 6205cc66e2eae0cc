#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, then configures, builds and
# runs the C++ example of Documentation/getting-started.md against it with
# find_package(SoftShadows): the documented way for VTK applications.
set -euo pipefail
src="$1"; build="$2"; work="$3"
rm -rf "$work"
mkdir -p "$work/example"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
doc="$src/Documentation/getting-started.md"
awk '/^```cmake/{f=1;next} /^```/{if(f){exit}} f' "$doc" > "$work/example/CMakeLists.txt"
awk '/^```cpp/{f=1;next} /^```/{if(f){exit}} f' "$doc" > "$work/example/demo.cxx"
cmake -S "$work/example" -B "$work/example/build" -DCMAKE_BUILD_TYPE=Release \
  -DSoftShadows_DIR="$work/prefix/lib/cmake/softshadows" > "$work/configure.log"
cmake --build "$work/example/build" -j 2 > "$work/build.log"
LD_LIBRARY_PATH="$work/prefix/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
  "$src/Testing/headless.sh" "$work/example/build/demo"
echo "getting-started example: configured, built and ran against the installed SoftShadows"

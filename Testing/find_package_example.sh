#!/usr/bin/env bash
# Installs the build tree into a scratch prefix and uses it as a consumer
# would, with only CMAKE_PREFIX_PATH pointing to it (issue 24):
# - the prefix's include/ holds nothing but the project's own directory (VTK's
#   generated headers such as Python.h once shadowed CPython's);
# - a project calling find_package(Python3 Development) and
#   find_package(SoftShadows) configures;
# - Examples/cxx (the C++ program of Documentation/getting-started.md, which
#   must show the same files) configures, builds, runs and saves a picture.
set -euo pipefail
src="$1"; build="$2"; work="$3"
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
prefix="$work/prefix"

stray=$(find "$prefix/include" -mindepth 1 -maxdepth 1 ! -name softshadows)
if [ -n "$stray" ] || [ -n "$(find "$prefix" -name Python.h)" ]; then
  echo "install: headers outside include/softshadows or a Python.h in the prefix:"
  echo "$stray"; find "$prefix" -name Python.h
  exit 1
fi

doc="$src/Documentation/getting-started.md"
for pair in "cmake:CMakeLists.txt" "cpp:demo.cxx"; do
  lang="${pair%%:*}"; file="${pair#*:}"
  if ! diff <(awk -v lang="$lang" '$0 == "```" lang {f=1;next} /^```/{if(f){exit}} f' "$doc") \
      "$src/Examples/cxx/$file" > "$work/doc-$file.diff"; then
    echo "getting-started.md's \`\`\`$lang block differs from Examples/cxx/$file:"
    cat "$work/doc-$file.diff"
    exit 1
  fi
done

mkdir -p "$work/python-consumer"
cat > "$work/python-consumer/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(PythonConsumer C CXX)
find_package(Python3 REQUIRED COMPONENTS Interpreter Development)
find_package(SoftShadows REQUIRED)
message(STATUS "Python3_INCLUDE_DIRS=${Python3_INCLUDE_DIRS}")
CMAKE
# Debian's ParaView config needs Debian's Python (mpi4py): name it when
# another python3 (pyenv) comes first in PATH
py=()
[ -x /usr/bin/python3 ] && py=(-DPython3_EXECUTABLE=/usr/bin/python3)
cmake -S "$work/python-consumer" -B "$work/python-consumer/build" -DCMAKE_PREFIX_PATH="$prefix" "${py[@]}" \
  > "$work/python-consumer.log" 2>&1 || { cat "$work/python-consumer.log"; exit 1; }
if grep "Python3_INCLUDE_DIRS=" "$work/python-consumer.log" | grep -q "$prefix"; then
  echo "FindPython3 took its headers from the SoftShadows prefix:"; grep Python3_INCLUDE_DIRS "$work/python-consumer.log"
  exit 1
fi

cp -r "$src/Examples/cxx" "$work/example"
cmake -S "$work/example" -B "$work/example/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/example/build" -j 2 > "$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
LD_LIBRARY_PATH="$prefix/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
  "$src/Testing/headless.sh" "$work/example/build/demo" "$work/demo.png"
test -s "$work/demo.png"
echo "Examples/cxx: configured with CMAKE_PREFIX_PATH only, built, ran and saved $work/demo.png"

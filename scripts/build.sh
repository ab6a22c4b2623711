#!/usr/bin/env bash
# Configures and builds inertial (Release) in ./build (or $INERTIAL_BUILD_DIR) with Ninja, every
# compile through ccache (CMakeLists.txt, "ccache"). Arguments that start with - go to CMake's
# configure step (-DNAME=V, or -D NAME=V, -U, -G, -C with their value), the others name the targets
# to build (default: all of them), e.g.
#   scripts/build.sh inertial                  the CLI and the libraries it links, nothing else
#   scripts/build.sh -DINERTIAL_ASSERTS=ON     everything, with the internal assertions live
set -euo pipefail
cd "$(dirname "$0")/.."
build=${INERTIAL_BUILD_DIR:-build}
configure=()
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    -D|-U|-G|-C|-T|-A) configure+=("$1" "${2:?scripts/build.sh: $1 needs a value}"); shift 2 ;;
    -*) configure+=("$1"); shift ;;
    *) targets+=(--target "$1"); shift ;;
  esac
done
generator=()
# A build directory made earlier with another generator keeps it (CMake refuses to switch).
if [ ! -f "$build/CMakeCache.txt" ] && [[ " ${configure[*]} " != *" -G "* ]]; then generator=(-G Ninja); fi
cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${configure[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)" "${targets[@]}"

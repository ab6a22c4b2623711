#!/usr/bin/env bash
# Configures and builds inertial (Release) in ./build with Ninja, every compile through ccache
# (CMakeLists.txt, "ccache"). Arguments that start with -D go to CMake's configure step, the others
# name the targets to build (default: all of them), e.g.
#   scripts/build.sh inertial                  the CLI and the libraries it links, nothing else
#   scripts/build.sh -DINERTIAL_ASSERTS=ON     everything, with the internal assertions live
set -euo pipefail
cd "$(dirname "$0")/.."
build=${INERTIAL_BUILD_DIR:-build}
configure=()
targets=()
for a in "$@"; do
  case "$a" in
    -D*) configure+=("$a") ;;
    *) targets+=(--target "$a") ;;
  esac
done
generator=()
# A build directory made earlier with another generator keeps it (CMake refuses to switch).
if [ ! -f "$build/CMakeCache.txt" ]; then generator=(-G Ninja); fi
cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${configure[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)" "${targets[@]}"

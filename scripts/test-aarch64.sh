#!/usr/bin/env bash
# The embedded target: cross-compiles the core (inertia, model, signal, estimation, diagnosis, study), its tests and
# the benchmarks (bench/inertial_bench: per-tick latency) for 64-bit Arm into ./build-aarch64, then
# runs the core's tests under qemu-aarch64 (CTest prepends the emulator; cmake/aarch64-linux-gnu.cmake).
# Installs what it needs from Debian first: the cross compiler, qemu-user, and the arm64 GoogleTest
# and Google Benchmark packages through multiarch. .ci/run runs it after the README's test command;
# it builds through scripts/build.sh (Ninja, ccache). Extra arguments go to ctest. Copy
# build-aarch64/bench/inertial_bench to the robot's computer and run it there for the real latency
# (README, "On the robot's computer").
set -euo pipefail
cd "$(dirname "$0")/.."
# The tests labelled "long" (tests/long_tests.cmake: full-size accuracy studies the README's test
# command runs natively) are left out here unless the first argument is --all.
subset=(-LE long)
if [ "${1:-}" = "--all" ]; then subset=(); shift; fi

scripts/install-deps.sh
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
packages=(g++-aarch64-linux-gnu qemu-user libgtest-dev:arm64 libbenchmark-dev:arm64)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then missing+=("$p"); fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "test-aarch64: installing ${missing[*]}"
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then $SUDO dpkg --add-architecture arm64; fi
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

INERTIAL_BUILD_DIR=build-aarch64 scripts/build.sh -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake \
  -DINERTIAL_CORE_ONLY=ON
echo "build-aarch64/bench/inertial_bench: $(aarch64-linux-gnu-readelf -h build-aarch64/bench/inertial_bench | sed -n "s/^ *Machine: *//p")"
ctest --test-dir build-aarch64 --output-on-failure -j"$(nproc)" ${subset[@]+"${subset[@]}"} "$@"

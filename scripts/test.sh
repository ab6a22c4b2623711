#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test (CTest); then the same suite in the sanitizer
# build and the fuzz harnesses for a bounded time (scripts/test-sanitizers.sh); then the core's
# tests cross-compiled for 64-bit Arm under qemu (scripts/cross-aarch64.sh). This is the README's
# test command and what .ci/run calls. Extra arguments go to both ctest runs, e.g.
# scripts/test.sh -L unit. INERTIAL_SANITIZERS=0 skips the sanitizer build and INERTIAL_AARCH64=0
# the Arm build (a quick local run).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
if [ "${INERTIAL_SANITIZERS:-1}" != "0" ]; then
  scripts/test-sanitizers.sh "$@"
fi
# The embedded target: the core, its tests and the benchmarks cross-compiled for 64-bit Arm, the
# tests run under qemu-aarch64: all of them (only the core's tests exist there, so the arguments,
# which select tests of the full build, are not passed).
if [ "${INERTIAL_AARCH64:-1}" != "0" ]; then
  scripts/cross-aarch64.sh
fi

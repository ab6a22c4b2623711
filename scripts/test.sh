#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test (CTest); then the core's tests cross-compiled
# for 64-bit Arm and run under qemu (scripts/cross-aarch64.sh); then the same suite in the sanitizer
# build and the fuzz harnesses for a bounded time (scripts/test-sanitizers.sh). This is the README's
# test command and what .ci/run calls. Extra arguments go to every ctest run, e.g.
# scripts/test.sh -L unit. INERTIAL_SANITIZERS=0 skips the sanitizer build and INERTIAL_AARCH64=0 the
# Arm build (quick local runs; CI runs all three).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
if [ "${INERTIAL_AARCH64:-1}" != "0" ]; then
  scripts/cross-aarch64.sh "$@"
fi
if [ "${INERTIAL_SANITIZERS:-1}" != "0" ]; then
  scripts/test-sanitizers.sh "$@"
fi

#!/usr/bin/env bash
# The README's test command: installs what the tests need, builds everything in ./build
# (scripts/build.sh) and runs the whole normal suite with CTest: unit and end-to-end tests. Extra
# arguments go to ctest, e.g. scripts/test.sh -L unit, or -R 'inertia\.'.
# The other two halves of CI are their own commands (.ci/run runs all three):
#   scripts/test-aarch64.sh     the core cross-built for 64-bit Arm, its tests under qemu
#   scripts/test-sanitizers.sh  the suite again under ASan + UBSan (clang), then the fuzz harnesses
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --tests
scripts/build.sh
ctest --test-dir "${INERTIAL_BUILD_DIR:-build}" --output-on-failure -j"$(nproc)" "$@"

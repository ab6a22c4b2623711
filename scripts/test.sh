#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test (CTest). This is the README's test command and
# what .ci/run calls. Extra arguments go to ctest, e.g. scripts/test.sh -L unit
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"

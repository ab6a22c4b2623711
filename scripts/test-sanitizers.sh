#!/usr/bin/env bash
# The sanitizer build: every library, tool and test compiled by clang with AddressSanitizer and
# UndefinedBehaviorSanitizer (any report fails the test that caused it) and instrumented for
# libFuzzer, in ./build-sanitize; then the whole test suite there, then every fuzz harness for a
# bounded time (scripts/fuzz.sh). .ci/run runs it after the README's test command and the Arm half;
# compiles go through ccache like every build (CMakeLists.txt). Extra arguments go to ctest.
# Not detect_stack_use_after_return: it made the suite a fifth slower.
set -euo pipefail
cd "$(dirname "$0")/.."
# The tests labelled "long" (tests/long_tests.cmake: full-size accuracy studies the README's test
# command runs natively) are left out here unless the first argument is --all.
subset=(-LE long)
if [ "${1:-}" = "--all" ]; then subset=(); shift; fi
scripts/install-deps.sh --sanitizers
# -O1: a third of -O2's compile time with most of its speed; the sanitizers' checks are the point.
CXX=clang++ INERTIAL_BUILD_DIR=build-sanitize scripts/build.sh -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DINERTIAL_SANITIZE=address,undefined -DINERTIAL_FUZZ=ON \
  -DINERTIAL_BUILD_BENCHMARKS=OFF
# detect_leaks: a leak fails the test. abort_on_error: a report ends the process with a signal CTest shows.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Stack traces with file and line (clang's symbolizer; Debian installs it without the plain name).
for s in /usr/lib/llvm-14/bin/llvm-symbolizer /usr/bin/llvm-symbolizer; do
  if [ -x "$s" ]; then export ASAN_SYMBOLIZER_PATH="$s"; break; fi
done
# Every test but the long ones, at the size it has in the normal build (the slowest take 20-70 s here: the
# simulator's plant is Newton-Euler on the true bodies, not the regressor).
ctest --test-dir build-sanitize --output-on-failure -j"$(nproc)" ${subset[@]+"${subset[@]}"} "$@"
# A fixed sequence of inputs from a fixed seed (scripts/fuzz.sh: the same inputs for one build), 20,000
# of them or 60 s a harness, whichever comes first: with the large inputs of issue 35 the slowest
# harnesses (candump, motors.yaml) run 20-60 inputs a second, so 20,000 would add half an hour to CI.
# scripts/fuzz.sh --seconds or --runs for long runs.
INERTIAL_BUILD_DIR=build-sanitize scripts/fuzz.sh --runs "${INERTIAL_FUZZ_RUNS:-20000}" --seconds "${INERTIAL_FUZZ_SECONDS:-60}" --seed 1

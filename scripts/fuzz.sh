#!/usr/bin/env bash
# Runs the libFuzzer harnesses of tests/fuzz (built by scripts/test-sanitizers.sh in
# ./build-sanitize: clang, ASan + UBSan, coverage) for a bounded time or number of inputs each, from
# the repository's seed corpus and the large seeds tests/fuzz/large_seeds.sh writes (new inputs go
# to build-sanitize/fuzz-corpus/<name>, never into the repository). Prints, per harness, the inputs
# run, the rate and the result; a finding leaves its input in build-sanitize/fuzz-findings/, prints
# the report and makes the script exit 1.
#   scripts/fuzz.sh [--seconds S] [--runs N] [--seed K] [HARNESS...]   (default: --seconds 20, every harness)
# Given both, a harness stops at whichever comes first. With --runs and --seed the run is
# reproducible (the same inputs in the same order; with --seconds too, a prefix of them) for one build:
# the programs run without address-space randomization (setarch -R), since libFuzzer's comparison
# tracing also records pointer values. CI uses that.
#
# What each harness is given (issue 35): the text formats a -max_len far above libFuzzer's default
# of 4096 bytes (which can hold neither 100,000 levels of nesting nor a million commas): 1 MiB for
# URDFs, checkpoints and CSV logs; 256 KiB for candump logs (a replayed frame costs an estimator
# update); 128 KiB for the JSON config, a little over the settings limit (64 KiB, input_file.hpp) so
# both sides of it are reached; 8 KiB for motors.yaml, whose parser (yaml-cpp) costs about 4 us a
# token: an input near the limit takes 1 s under the sanitizers, so a run of 10^6 would take days,
# while the class only a larger input reaches (over the limit) is refused by its size before yaml-cpp
# runs (tests/config/motors_yaml_test.cpp); a dictionary of the format's structure, nesting and
# separators (tests/fuzz/dict/); large seeds. The binary LCM formats keep the default (their lengths are
# fields, which the corpus and mutations reach).
# -timeout=10: a slow input is a finding. The slowest honest input of any harness takes well under a
# second under the sanitizers (the 1 MiB logs, checkpoints and URDFs are parsed in linear time), and
# the slow inputs issue 35 found took 2-10 s without sanitizers; 10 s leaves room for a loaded machine.
set -euo pipefail
cd "$(dirname "$0")/.."
limit=()
seed=()
names=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) limit+=(-max_total_time="$2"); shift 2 ;;
    --runs) limit+=(-runs="$2"); shift 2 ;;
    --seed) seed=(-seed="$2"); shift 2 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) names+=("$1"); shift ;;
  esac
done
[ ${#limit[@]} -gt 0 ] || limit=(-max_total_time=20)
build=${INERTIAL_BUILD_DIR:-build-sanitize}  # the sanitizer build (another for long runs beside rebuilds)
if [ ${#names[@]} -eq 0 ]; then
  for f in tests/fuzz/*_fuzz.cpp; do n=$(basename "$f" _fuzz.cpp); names+=("$n"); done
fi
mkdir -p "$build/fuzz-findings"
seeds="$build/fuzz-seeds/$$"  # this run's own (runs for different harnesses may go side by side)
trap 'rm -rf "$seeds"' EXIT
tests/fuzz/large_seeds.sh "$seeds"
# Per harness: -max_len and dictionary (empty: libFuzzer's defaults).
options_of() {
  case "$1" in
    urdf) echo "-max_len=1048576 -dict=tests/fuzz/dict/urdf.dict" ;;
    motors_yaml) echo "-max_len=8192 -dict=tests/fuzz/dict/yaml.dict" ;;
    daemon_config) echo "-max_len=131072 -dict=tests/fuzz/dict/json.dict" ;;
    checkpoint) echo "-max_len=1048576 -dict=tests/fuzz/dict/json.dict" ;;
    joint_csv | body_csv) echo "-max_len=1048576 -dict=tests/fuzz/dict/csv.dict" ;;
    candump) echo "-max_len=262144 -dict=tests/fuzz/dict/csv.dict" ;;
    *) echo "" ;;
  esac
}
norandom=()
if setarch "$(uname -m)" -R true 2>/dev/null; then norandom=(setarch "$(uname -m)" -R); fi
status=0
printf '%-14s %12s %10s  %s\n' harness inputs "inputs/s" result
for n in "${names[@]}"; do
  program="$build/tests/fuzz/fuzz_$n"
  if [ ! -x "$program" ]; then
    echo "fuzz.sh: $program is not built (scripts/test-sanitizers.sh builds it)" >&2
    exit 2
  fi
  work="$build/fuzz-corpus/$n"
  mkdir -p "$work"
  log="$build/fuzz-$n.log"
  # -rss_limit_mb: the CI machine has 24 GiB; 2 GiB per input is far above any honest need and catches
  # the allocations a length field could ask for. -timeout: seconds for one input.
  mkdir -p "$seeds/$n"
  # shellcheck disable=SC2046  # options_of's words are separate options
  if "${norandom[@]}" "$program" "${limit[@]}" "${seed[@]}" $(options_of "$n") -print_final_stats=1 -rss_limit_mb=2048 \
       -timeout=10 -artifact_prefix="$build/fuzz-findings/$n-" "$work" "tests/fuzz/corpus/$n" "$seeds/$n" >"$log" 2>&1; then
    result="no finding"
  else
    result="FINDING (see $log)"
    status=1
    # The report itself, so that a CI log shows what was found.
    grep -E -A12 "^==[0-9]+==ERROR|runtime error|fuzz finding|ALARM|out-of-memory|Test unit written|SUMMARY" "$log" | head -40 | cut -c1-240 >&2 || true
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  printf '%-14s %12s %10s  %s\n' "$n" "${runs:-?}" "${rate:-?}" "$result"
done
exit $status

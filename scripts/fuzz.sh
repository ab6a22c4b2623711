#!/usr/bin/env bash
# Runs the libFuzzer harnesses of tests/fuzz (built by scripts/test-sanitizers.sh in
# ./build-sanitize: clang, ASan + UBSan, coverage) for a bounded time or number of inputs each, from
# a copy of the repository's seed corpus (new inputs go to build-sanitize/fuzz-corpus/<name>, never
# into the repository). Prints, per harness, the inputs run, the rate and the result; a finding
# leaves its input in build-sanitize/fuzz-findings/ and makes the script exit 1.
#   scripts/fuzz.sh [--seconds S | --runs N] [--seed K] [HARNESS...]   (default: --seconds 20, every harness)
# With --runs and --seed the run is reproducible (the same inputs in the same order): CI uses that.
set -euo pipefail
cd "$(dirname "$0")/.."
limit=(-max_total_time=20)
seed=()
names=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) limit=(-max_total_time="$2"); shift 2 ;;
    --runs) limit=(-runs="$2"); shift 2 ;;
    --seed) seed=(-seed="$2"); shift 2 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) names+=("$1"); shift ;;
  esac
done
build=build-sanitize
if [ ${#names[@]} -eq 0 ]; then
  for f in tests/fuzz/*_fuzz.cpp; do n=$(basename "$f" _fuzz.cpp); names+=("$n"); done
fi
mkdir -p "$build/fuzz-findings"
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
  if "$program" "${limit[@]}" "${seed[@]}" -print_final_stats=1 -rss_limit_mb=2048 -timeout=30 \
       -artifact_prefix="$build/fuzz-findings/$n-" "$work" "tests/fuzz/corpus/$n" >"$log" 2>&1; then
    result="no finding"
  else
    result="FINDING (see $log)"
    status=1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  printf '%-14s %12s %10s  %s\n' "$n" "${runs:-?}" "${rate:-?}" "$result"
done
exit $status

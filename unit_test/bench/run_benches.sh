#!/usr/bin/env bash
# Runs benchmarks one after another (make bench, make bench-check) and ends with
# one summary line. Every benchmark runs, whatever the ones before it did.
#
#   run_benches.sh [--check] BENCH...
#
# A BENCH is an executable, or a script ending in .sh (run with bash). Its exit
# status says what happened (unit_test/bench/bench_targets.hpp):
#   0  ran, every target it checks met
#   3  ran, at least one target missed (it printed which: MISSED / NOT MET / FAIL)
#   other  could not run (setup failed, bad option, crash)
# Exit status: non-zero when a benchmark could not run; with --check also when
# one missed a target, so a script sees a missed target as a failure. Without
# --check (make bench) a missed target is reported but the exit status stays 0.
#
# The exit status 3 is the contract: unit_test/integration/harness_counts_test.sh
# checks this script against fake benchmarks.
set -u
check=0
if [ "${1:-}" = "--check" ]; then
  check=1
  shift
fi
readonly kMissed=3

met=() missed=() broken=()
for b in "$@"; do
  echo "### $b"
  if [[ "$b" == *.sh ]]; then
    bash "$b"
  else
    "$b"
  fi
  rc=$?
  name=$(basename "$b")
  if [ "$rc" -eq 0 ]; then
    met+=("$name")
  elif [ "$rc" -eq "$kMissed" ]; then
    missed+=("$name")
  else
    broken+=("$name (exit $rc)")
  fi
  echo
done

summary="### bench summary: $# benchmarks, ${#met[@]} met every target, ${#missed[@]} missed a target"
[ "${#missed[@]}" -gt 0 ] && summary+=" (${missed[*]})"
summary+=", ${#broken[@]} could not run"
[ "${#broken[@]}" -gt 0 ] && summary+=" (${broken[*]})"
echo "$summary"
if [ "${#broken[@]}" -gt 0 ]; then
  exit 1
fi
if [ "$check" -eq 1 ] && [ "${#missed[@]}" -gt 0 ]; then
  echo "bench-check: FAILED: a target was missed"
  exit 1
fi
if [ "$check" -eq 1 ]; then
  echo "bench-check: every target met"
fi
exit 0

#!/usr/bin/env bash
# The test harness's own counts: unit_test/run_suites.sh and summarize.sh (make
# test) and unit_test/bench/run_benches.sh (make bench, make bench-check), fed
# fake suites and fake benchmarks whose output and exit status are known.
# Runs no built executable; a second or so. Ends with "N passed, N failed".
set -u
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0 failed=0

check() {  # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then passed=$((passed + 1)); echo "  pass: $name"
  else failed=$((failed + 1)); echo "  FAIL: $name"; fi
}

# fake NAME EXIT-STATUS [LINE...]: an executable that prints the lines and exits.
fake() {
  local name=$1 rc=$2; shift 2
  { echo '#!/bin/sh'; for line in "$@"; do printf "echo '%s'\n" "$line"; done; echo "exit $rc"; } >"$work/$name"
  chmod +x "$work/$name"
}

# The line run_suites.sh records for one fake suite: "<label>/<suite> P F"
# (its fourth field, the suite's seconds, is checked on its own below).
counted() {  # counted SUITE
  local results="$work/results-$1.txt"
  rm -f "$results"
  "$root/unit_test/run_suites.sh" "$results" fake "" "$work/$1" >"$work/$1.out" 2>&1
  cut -d' ' -f1-3 "$results"
}

echo "run_suites.sh: what a suite's output counts as"
fake zero_plain 0 "0 passed, 0 failed"
check "'0 passed, 0 failed' counts as one failure" test "$(counted zero_plain)" = "fake/zero_plain 0 1"
check "... and says why" grep -q "ran no test" "$work/zero_plain.out"
fake zero_cpputest 0 "OK (0 tests, 0 ran, 0 checks, 0 ignored, 5 filtered out, 0 ms)"
check "CppUTest 'OK (0 tests, 0 ran' counts as one failure" test "$(counted zero_cpputest)" = "fake/zero_cpputest 0 1"
fake zero_named 0 "tshark: 0 passed, 0 failed"
check "a named '0 passed, 0 failed' counts as one failure" test "$(counted zero_named)" = "fake/zero_named 0 1"
fake plain 0 "3 passed, 0 failed"
check "'3 passed, 0 failed' counts 3 passed" test "$(counted plain)" = "fake/plain 3 0"
fake cpputest_ok 0 "OK (5 tests, 5 ran, 40 checks, 0 ignored, 0 filtered out, 12 ms)"
check "CppUTest OK counts its tests" test "$(counted cpputest_ok)" = "fake/cpputest_ok 5 0"
fake cpputest_errors 1 "Errors (2 failures, 5 tests, 5 ran, 40 checks, 0 ignored, 0 filtered out, 12 ms)"
check "CppUTest Errors counts passed and failed" test "$(counted cpputest_errors)" = "fake/cpputest_errors 3 2"
fake silent 0
check "no summary counts one failure" test "$(counted silent)" = "fake/silent 0 1"
fake crash_after 1 "2 passed, 0 failed"
check "non-zero exit without a failed test counts one failure" test "$(counted crash_after)" = "fake/crash_after 2 1"
fake crash_zero 139 "0 passed, 0 failed"
check "a crash that ran nothing counts one failure, not two" test "$(counted crash_zero)" = "fake/crash_zero 0 1"
check "a missing binary counts one failure" test "$(counted no_such_suite)" = "fake/no_such_suite 0 1"
printf '#!/bin/sh\nsleep 1\necho "1 passed, 0 failed"\n' >"$work/slow" && chmod +x "$work/slow"
counted slow >/dev/null
check "the fourth field is the suite's whole seconds (a 1 s suite: 1 or 2)" \
  grep -qE '^fake/slow 1 0 [12]$' "$work/results-slow.txt"

echo "summarize.sh: the closing line and exit status"
printf 'x/a 5 0\nx/b 3 0\n' >"$work/all_pass.txt"
"$root/unit_test/summarize.sh" "$work/all_pass.txt" >"$work/sum.out"; rc=$?
check "all passed: exit 0" test "$rc" -eq 0
check "all passed: last line '8 passed, 0 failed'" test "$(tail -1 "$work/sum.out")" = "8 passed, 0 failed"
printf 'x/a 5 0 3\ny/a 2 1 7\nx/b 3 0 4\n' >"$work/two_targets.txt"
"$root/unit_test/summarize.sh" "$work/two_targets.txt" >"$work/sum.out"
check "per-target table: x has 2 suites, 8 passed, 0 failed, 7 s" grep -qE '^  x +2 +8 +0 +7$' "$work/sum.out"
check "per-target table: y has 1 suite, 2 passed, 1 failed, 7 s" grep -qE '^  y +1 +2 +1 +7$' "$work/sum.out"
check "suites grouped by target: x/b listed before y/a" \
  test "$(grep -oE '^  (x/b|y/a) ' "$work/sum.out" | tr -d ' \n')" = "x/by/a"
check "two targets: last line '10 passed, 1 failed'" test "$(tail -1 "$work/sum.out")" = "10 passed, 1 failed"
rm -f "$work/results-zero.txt"
"$root/unit_test/run_suites.sh" "$work/results-zero.txt" fake "" "$work/plain" "$work/zero_plain" >/dev/null 2>&1
"$root/unit_test/summarize.sh" "$work/results-zero.txt" >"$work/sum.out"; rc=$?
check "a suite that ran no test fails the run" test "$rc" -ne 0
check "... and the last line counts it: '3 passed, 1 failed'" test "$(tail -1 "$work/sum.out")" = "3 passed, 1 failed"

echo "run_benches.sh: make bench and make bench-check"
fake bench_met 0 "target: < 5000 ns/frame -> met"
fake bench_missed 3 "target: p99 < 200 us -> MISSED"
fake bench_broken 1 "bench: executive init failed"
bench() { "$root/unit_test/bench/run_benches.sh" "$@" >"$work/bench.out" 2>&1; }
bench --check "$work/bench_met" "$work/bench_met"; rc=$?
check "bench-check, every target met: exit 0" test "$rc" -eq 0
bench --check "$work/bench_met" "$work/bench_missed" "$work/bench_met"; rc=$?
check "bench-check, a target missed: exit non-zero" test "$rc" -ne 0
check "... every bench still ran" test "$(grep -c '^### .*/bench_' "$work/bench.out")" -eq 3
check "... the summary names the bench that missed" \
  grep -q "^### bench summary: 3 benchmarks, 2 met every target, 1 missed a target (bench_missed), 0 could not run" \
  "$work/bench.out"
bench "$work/bench_met" "$work/bench_missed"; rc=$?
check "bench (report only), a target missed: exit 0" test "$rc" -eq 0
check "... the miss is in the summary" grep -q "1 missed a target (bench_missed)" "$work/bench.out"
bench "$work/bench_broken" "$work/bench_met"; rc=$?
check "bench, a bench that could not run: exit non-zero" test "$rc" -ne 0
check "... named with its status" grep -q "1 could not run (bench_broken (exit 1))" "$work/bench.out"
bench --check "$work/bench_broken"; rc=$?
check "bench-check, a bench that could not run: exit non-zero" test "$rc" -ne 0

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]

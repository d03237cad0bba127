#!/usr/bin/env bash
# Runs test suite binaries and appends one line per suite to a results file:
#   <label>/<suite> <passed> <failed> <seconds>
# (seconds: the suite's wall time; several runs may append to one file at once,
# make test's targets side by side: each line is one short O_APPEND write).
# A suite passes tests per its runner's own summary: CppUTest's "OK (N tests, N ran,
# ...)" / "Errors (F failures, N tests, N ran, ...)", or a plain "N passed, N failed"
# line. A suite that crashes, times out, exits non-zero or prints no summary counts
# one extra failure, and so does a suite whose summary says it ran no test ("0
# passed, 0 failed", "OK (0 tests, 0 ran, ...)": a filter or a build that lost
# its tests), so nothing fails silently. unit_test/integration/harness_counts_test.sh
# feeds this script fake suites and checks these counts.
#
# A suite ending in .sh is a script that runs built executables itself; it gets
# the runner prefix as RSE_RUNNER (and RSE_BIN_DIR from the caller).
#
# usage: run_suites.sh RESULTS LABEL "RUNNER" SUITE...
set -u
results=$1 label=$2 runner=$3
shift 3
SUITE_TIMEOUT=${SUITE_TIMEOUT:-900}
log_dir=$(dirname "$results")/logs
mkdir -p "$log_dir"

for bin in "$@"; do
  suite=$(basename "$bin" .sh)
  log="$log_dir/$label-$suite.log"
  if [ ! -x "$bin" ]; then
    echo "[$label] $suite: binary missing (build failed)"
    echo "$label/$suite 0 1 0" >> "$results"
    continue
  fi
  started=$SECONDS
  echo "=== [$label] $suite"
  # The lockstep suite flies some forty missions; under emulation on the
  # 2-core CI machine, beside the other targets' runs, s390x took over 900 s
  # (383 s alone): it gets twice the time there. A hang still ends.
  limit=$SUITE_TIMEOUT
  if [ -n "$runner" ] && [ "$suite" = test_system_lockstep ] && [ "$limit" -lt 1800 ]; then
    limit=1800
  fi
  if [[ "$bin" == *.sh ]]; then
    RSE_RUNNER=$runner timeout "$limit" bash "$bin" 2>&1 | tee "$log"
  else
    # shellcheck disable=SC2086  # RUNNER is a command prefix, split on purpose
    timeout "$limit" $runner "$bin" 2>&1 | tee "$log"
  fi
  rc=${PIPESTATUS[0]}
  read -r passed failed < <(awk '
    /^OK \(/     { for (i = 1; i <= NF; i++) if ($(i+1) ~ /^ran/) ran = $i + 0; fails = 0; found = 1 }
    /^Errors \(/ { gsub(/[(,]/, " "); for (i = 1; i <= NF; i++) { if ($(i+1) ~ /^ran/) ran = $i + 0; if ($(i+1) ~ /^failure/) fails = $i + 0 } found = 1 }
    /^([A-Za-z0-9_-]+: )?[0-9]+ passed, [0-9]+ failed/ { sub(/^[A-Za-z0-9_-]+: /, ""); ran = $1 + $3; fails = $3 + 0; found = 1 }
    END { if (!found) { print 0, 0 } else { print ran - fails, fails } }' "$log")
  if [ "$rc" -ne 0 ] && [ "$failed" -eq 0 ]; then
    echo "[$label] $suite: exited with status $rc without reporting a failed test (crash or timeout)"
    failed=1
  elif ! grep -qE '^(OK \(|Errors \(|([A-Za-z0-9_-]+: )?[0-9]+ passed, [0-9]+ failed)' "$log"; then
    echo "[$label] $suite: printed no test summary"
    failed=$((failed + 1))
  elif [ $((passed + failed)) -eq 0 ]; then
    echo "[$label] $suite: ran no test (counted as failed)"
    failed=1
  fi
  echo "$label/$suite $passed $failed $((SECONDS - started))" >> "$results"
done

#!/usr/bin/env bash
# The display's JavaScript library (dictionary, limits, history paging, risk
# ellipses, ...) under Node's test runner, no browser and no server; its
# counts as the "N passed, N failed" line make test's summary reads.
set -u
log=$(mktemp)
trap 'rm -f "$log"' EXIT
node --test unit_test/ground/mission_control/web/web_lib.test.mjs 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
pass=$(sed -n 's/^# pass \([0-9]*\)$/\1/p' "$log")
fail=$(sed -n 's/^# fail \([0-9]*\)$/\1/p' "$log")
if [ -z "$pass" ] || [ -z "$fail" ]; then
  echo "web_lib_test: node --test printed no counts"
  exit 1
fi
[ "$rc" -ne 0 ] && [ "$fail" -eq 0 ] && fail=1
echo "$pass passed, $fail failed"
exit $((fail > 0 ? 1 : 0))

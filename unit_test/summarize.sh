#!/usr/bin/env bash
# Prints the per-suite results and the closing total line "N passed, N failed";
# exits non-zero when anything failed or no test ran at all.
set -u
results=$1
if [ ! -s "$results" ]; then
  echo "no suite reported results"
  echo "0 passed, 1 failed"
  exit 1
fi
echo "=== results"
awk '{ printf "  %-28s %5d passed %5d failed\n", $1, $2, $3 }' "$results"
read -r passed failed < <(awk '{ p += $2; f += $3 } END { print p + 0, f + 0 }' "$results")
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]

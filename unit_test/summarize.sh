#!/usr/bin/env bash
# Prints the per-suite results grouped by target, the per-target table (suites,
# passed, failed, the suites' wall time added up) and the closing total line
# "N passed, N failed"; exits non-zero when anything failed or no test ran at all.
# Results lines: "<target>/<suite> <passed> <failed> [<seconds>]" (run_suites.sh).
set -u
results=$1
if [ ! -s "$results" ]; then
  echo "no suite reported results"
  echo "0 passed, 1 failed"
  exit 1
fi
echo "=== results"
# Targets in the order they first reported (make test runs them side by side).
awk '{ split($1, part, "/"); t = part[1]
       if (!(t in seen)) { seen[t] = 1; order[++n] = t }
       line[t] = line[t] sprintf("  %-32s %5d passed %5d failed %6d s\n", $1, $2, $3, $4) }
     END { for (i = 1; i <= n; i++) printf "%s", line[order[i]] }' "$results"
echo "=== per target"
awk '{ split($1, part, "/"); t = part[1]
       if (!(t in seen)) { seen[t] = 1; order[++n] = t }
       suites[t]++; p[t] += $2; f[t] += $3; s[t] += $4 }
     END { printf "  %-14s %7s %8s %8s %9s\n", "target", "suites", "passed", "failed", "seconds"
           for (i = 1; i <= n; i++) { t = order[i]
             printf "  %-14s %7d %8d %8d %9d\n", t, suites[t], p[t], f[t], s[t] } }' "$results"
read -r passed failed < <(awk '{ p += $2; f += $3 } END { print p + 0, f + 0 }' "$results")
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]

#!/bin/bash
# Runs one libFuzzer target for a bounded time (make fuzz; unit_test/fuzz/README.md).
#
#   run_fuzz.sh NAME BINARY SEEDS_DIR WORK_DIR SECONDS [EXTRA_CORPUS_DIR...]
#
# WORK_DIR/corpus starts as a fresh copy of SEEDS_DIR plus the files of any
# EXTRA_CORPUS_DIR (crash reproducers) that exists, so libFuzzer's new inputs
# never land in the committed seeds. The fuzzer's output goes to WORK_DIR/fuzz.log,
# a crash input to WORK_DIR/artifacts/. Prints one summary line (also written to
# WORK_DIR/summary.txt) and exits non-zero on any crash, sanitizer report,
# timeout or leak.
set -u
name=$1 bin=$2 seeds=$3 work=$4 seconds=$5
shift 5

rm -rf "$work/corpus" "$work/artifacts"
mkdir -p "$work/corpus" "$work/artifacts"
cp "$seeds"/* "$work/corpus/"
for extra in "$@"; do
  if [ -d "$extra" ] && [ -n "$(ls -A "$extra")" ]; then cp "$extra"/* "$work/corpus/"; fi
done
seeded=$(ls "$work/corpus" | wc -l)

# halt_on_error and abort_on_error off: libFuzzer itself turns a sanitizer report
# into a crash with a saved reproducer and a non-zero exit.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
echo "fuzz $name: ${seconds}s from $seeded seed inputs (log: $work/fuzz.log)"
"$bin" -max_total_time="$seconds" -print_final_stats=1 -timeout=25 \
  -artifact_prefix="$work/artifacts/" "$work/corpus" >"$work/fuzz.log" 2>&1
rc=$?

stat() { sed -n "s/^stat::$1: *//p" "$work/fuzz.log" | tail -1; }
execs=$(stat number_of_executed_units)
speed=$(stat average_exec_per_sec)
peak=$(stat peak_rss_mb)
corpus=$(ls "$work/corpus" | wc -l)
# The last status line: "#N DONE cov: C ft: F corp: K/Sb ...".
last=$(grep -E '^#[0-9]+' "$work/fuzz.log" | tail -1)
cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
artifacts=$(ls "$work/artifacts")

if [ "$rc" -eq 0 ] && [ -z "$artifacts" ] && ! grep -qE '^(==[0-9]+==ERROR|SUMMARY: )|runtime error:' "$work/fuzz.log"; then
  result="no crash"
  status=0
else
  result="FAILED (exit $rc): reproducer(s): $(for a in $artifacts; do printf '%s ' "$work/artifacts/$a"; done)"
  status=1
  echo "---- $name: end of $work/fuzz.log ----"
  tail -n 60 "$work/fuzz.log"
  echo "----"
fi
line=$(printf 'fuzz %-8s %ss: %s execs (%s/s), corpus %s files (%s seeds), cov %s, ft %s, peak %s MB: %s' \
  "$name" "$seconds" "${execs:-?}" "${speed:-?}" "$corpus" "$seeded" "${cov:-?}" "${ft:-?}" "${peak:-?}" "$result")
echo "$line" | tee "$work/summary.txt"
exit $status

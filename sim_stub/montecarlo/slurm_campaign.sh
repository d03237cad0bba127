#!/usr/bin/env bash
# A Monte Carlo campaign of the lockstep mission as a Slurm array job
# (docs/montecarlo.md, "On a Slurm cluster"): one array task per block of
# seeds, each running `rse-montecarlo block` into a result file of its own in
# DIR/results/; with --wait, it waits for the array and merges the files into
# the campaign table (DIR/table.txt).
#
# usage: slurm_campaign.sh --seeds FIRST:COUNT --block-size B --dir DIR [--bin PATH]
#          [--partition P] [--cpus-per-task C] [--max-running M] [--time LIMIT]
#          [--sbatch-arg ARG]... [--wait SECONDS] [-- MISSION...]
#   --bin       rse-montecarlo (default build/x86_64/bin/rse-montecarlo); it, DIR and the
#               scenario must be on a filesystem every node sees, at the same path
#   --partition the partition to run in (default: the cluster's default)
#   --cpus-per-task  worker processes per array task (default 1)
#   --max-running    at most M array tasks at once (sbatch --array=...%M)
#   --time      each task's time limit (sbatch --time)
#   --sbatch-arg     one more sbatch option, as is (repeatable: --account, --qos, ...)
#   --wait      wait up to SECONDS for the array (sbatch --wait), cancel it if it is not done,
#               then merge; without it, print the job id and how to merge later
#   MISSION     rse-montecarlo's mission options (--scenario, --goto, --duration, --no-faults)
# Runs from the directory the jobs run in (the checkout holding the scenario).
# Exit status: 0 submitted (or, with --wait, merged with every check passed), 3 merged with
# a check failed, 1 the job or the merge failed, 2 bad usage, 124 the wait timed out.
set -u

die() { echo "slurm_campaign: $*" >&2; exit 2; }

seeds="" block="" dir="" bin="build/$(uname -m)/bin/rse-montecarlo" partition="" cpus=1 maxrun="" limit=""
wait_s="" extra=() mission=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) seeds=${2:-}; shift 2 ;;
    --block-size) block=${2:-}; shift 2 ;;
    --dir) dir=${2:-}; shift 2 ;;
    --bin) bin=${2:-}; shift 2 ;;
    --partition) partition=${2:-}; shift 2 ;;
    --cpus-per-task) cpus=${2:-}; shift 2 ;;
    --max-running) maxrun=${2:-}; shift 2 ;;
    --time) limit=${2:-}; shift 2 ;;
    --sbatch-arg) extra+=("${2:-}"); shift 2 ;;
    --wait) wait_s=${2:-}; shift 2 ;;
    --) shift; mission=("$@"); break ;;
    *) die "unknown option '$1' (see the comment at the top of $0)" ;;
  esac
done
[[ "$seeds" =~ ^([0-9]+):([0-9]+)$ ]] || die "--seeds FIRST:COUNT is needed"
first=${BASH_REMATCH[1]} count=${BASH_REMATCH[2]}
[[ "$block" =~ ^[1-9][0-9]*$ ]] || die "--block-size B (> 0) is needed"
[ -n "$dir" ] || die "--dir DIR is needed"
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || die "--cpus-per-task must be a count"
[ -z "$wait_s" ] || [[ "$wait_s" =~ ^[1-9][0-9]*$ ]] || die "--wait must be seconds"
[ "$count" -gt 0 ] || die "COUNT must be > 0"
[ -x "$bin" ] || die "$bin: not an executable (make build/$(uname -m)/bin/rse-montecarlo)"
command -v sbatch > /dev/null || die "sbatch not found (Debian: slurm-client)"

tasks=$(( (count + block - 1) / block ))
mkdir -p "$dir/results" "$dir/logs" || exit 1
dir=$(cd "$dir" && pwd) bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
rm -f "$dir"/results/block-*.txt

# The job script: one array task, one block (rse-montecarlo block reads
# SLURM_ARRAY_TASK_ID and SLURM_CPUS_PER_TASK).
script=$dir/campaign.sbatch
{
  echo "#!/bin/bash"
  echo "# rse-montecarlo campaign: seeds $first..$((first + count - 1)), $block per array task ($tasks tasks)"
  printf 'exec %q block --seeds %q --block-size %q --out %q' "$bin" "$first:$count" "$block" "$dir/results"
  for a in "${mission[@]+"${mission[@]}"}"; do printf ' %q' "$a"; done
  echo
} > "$script"
chmod +x "$script"

array="0-$((tasks - 1))${maxrun:+%$maxrun}"
args=(--parsable --job-name=rse-montecarlo --array="$array" --cpus-per-task="$cpus" --ntasks=1
      --chdir="$PWD" --output="$dir/logs/%A_%a.out")
[ -n "$partition" ] && args+=(--partition="$partition")
[ -n "$limit" ] && args+=(--time="$limit")
args+=("${extra[@]+"${extra[@]}"}")

if [ -z "$wait_s" ]; then
  job=$(sbatch "${args[@]}" "$script") || { echo "slurm_campaign: sbatch failed" >&2; exit 1; }
  echo "$job" > "$dir/job_id"
  echo "slurm_campaign: job $job, array $array ($tasks tasks of up to $block seeds); results in $dir/results"
  echo "slurm_campaign: when it is done: $bin merge --table $dir/table.txt $dir/results"
  exit 0
fi

# sbatch --wait prints the id at once, then exits with the highest exit code
# of the array's tasks when they are all done.
start=$(date +%s)
timeout "$wait_s" sbatch --wait "${args[@]}" "$script" > "$dir/job_id"
rc=$?
job=$(head -n 1 "$dir/job_id" 2> /dev/null | cut -d';' -f1)
if [ "$rc" -eq 124 ]; then
  echo "slurm_campaign: job ${job:-?} not done after $wait_s s: cancelled" >&2
  [ -n "$job" ] && scancel "$job"
  exit 124
fi
echo "slurm_campaign: job ${job:-?}, array $array, done in $(( $(date +%s) - start )) s (sbatch exit $rc)"
if [ "$rc" -ne 0 ]; then
  echo "slurm_campaign: a task failed; logs in $dir/logs" >&2
  exit 1
fi
"$bin" merge --table "$dir/table.txt" "$dir/results"

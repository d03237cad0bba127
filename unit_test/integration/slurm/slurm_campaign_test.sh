#!/usr/bin/env bash
# The Monte Carlo campaign on Slurm (issue 17; docs/montecarlo.md): a one-node
# Slurm cluster on localhost started here (munged with a key made here,
# slurmctld and slurmd with a config written into build/slurm_test/), a
# 20-seed campaign submitted with sbatch --array in 4 tasks of 5 seeds
# (sim_stub/montecarlo/slurm_campaign.sh --wait), its result files merged, and
# the merged table checked byte for byte against a local run of the same seeds
# (rse-montecarlo run), the rows too. Every daemon started here is stopped on
# the way out, failure or not (trap), and that is checked.
#
# Host only, as root (slurmd runs jobs as their user). Where Slurm is missing
# or cannot run, the checks fail with the reason: nothing is skipped.
# Prints pass:/FAIL: lines and "slurm_campaign: N passed, N failed".
# env: RSE_BIN_DIR (default build/x86_64/bin), RSE_SLURM_WAIT_S (default 300).
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
bin=${RSE_BIN_DIR:-build/$(uname -m)/bin}
case "$bin" in /*) ;; *) bin="$root/$bin" ;; esac
mc="$bin/rse-montecarlo"
campaign_sh="$root/sim_stub/montecarlo/slurm_campaign.sh"
wait_s=${RSE_SLURM_WAIT_S:-300}
work="$root/build/slurm_test"
seeds=1:20 block=5 tasks=4
cd "$root" || exit 1

pass=0
fail=0
check() {  # NAME COMMAND...: counts it and returns the command's status
  local name=$1 rc=0; shift
  "$@" || rc=$?
  if [ "$rc" -eq 0 ]; then echo "pass: $name"; pass=$((pass + 1)); else echo "FAIL: $name"; fail=$((fail + 1)); fi
  return "$rc"
}
show() {  # the tail of a log, for a failure's evidence
  local f
  for f in "$@"; do [ -s "$f" ] && { echo "--- $f (last 15 lines)"; tail -n 15 "$f"; }; done
}

munged_pid="" ctld_pid="" slurmd_pid="" job=""
stop_pid() {  # TERM, up to 15 s, then KILL: only the processes started here
  local pid=$1 i
  [ -n "$pid" ] || return 0
  kill -TERM "$pid" 2> /dev/null || return 0
  for i in $(seq 150); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
  kill -KILL "$pid" 2> /dev/null
  wait "$pid" 2> /dev/null
  return 0
}
alive() { [ -n "$1" ] && kill -0 "$1" 2> /dev/null; }
cleanup() {
  local i
  trap - EXIT INT TERM
  if [ -n "$job" ] && alive "$ctld_pid"; then
    scancel "$job" 2> /dev/null
    for i in $(seq 100); do [ -z "$(squeue -h -j "$job" 2> /dev/null)" ] && break; sleep 0.2; done
  fi
  stop_pid "$slurmd_pid"
  stop_pid "$ctld_pid"
  stop_pid "$munged_pid"
  local left=""
  for p in $slurmd_pid $ctld_pid $munged_pid; do alive "$p" && left="$left $p"; done
  if [ -n "$munged_pid$ctld_pid$slurmd_pid" ]; then
    check "every daemon started here is stopped (munged, slurmctld, slurmd${left:+; still running:$left})" \
      test -z "$left"
  fi
  echo "slurm_campaign: $pass passed, $fail failed"
  exit $(( fail > 0 || pass == 0 ? 1 : 0 ))
}
trap cleanup EXIT
trap 'echo "FAIL: interrupted"; fail=$((fail + 1)); exit 1' INT TERM

# --- What it needs ---------------------------------------------------------
missing=""
for t in munged mungekey munge unmunge slurmctld slurmd sbatch squeue sinfo scancel; do
  command -v "$t" > /dev/null || missing="$missing $t"
done
if [ -n "$missing" ]; then
  echo "FAIL: not installed:$missing (make deps installs Debian's slurm-wlm and munge)"; fail=$((fail + 1)); exit 1
fi
if [ "$(id -u)" != 0 ]; then
  echo "FAIL: the one-node cluster needs root (slurmd starts jobs as their user)"; fail=$((fail + 1)); exit 1
fi
if [ ! -x "$mc" ]; then
  echo "FAIL: $mc missing (make build/$(uname -m)/bin/rse-montecarlo)"; fail=$((fail + 1)); exit 1
fi

rm -rf "$work"
mkdir -p "$work"/{munge-key,munge-run,state,spool,log,local,campaign} || exit 1
chmod 700 "$work/munge-key"
chmod 755 "$work" "$work/munge-run"
# A Unix socket path has at most 107 bytes: a deep checkout gets a short one in /tmp.
sock="$work/munge-run/munge.socket"
if [ ${#sock} -gt 100 ]; then
  sockdir=$(mktemp -d /tmp/rse-munge.XXXXXX) && chmod 755 "$sockdir" && sock="$sockdir/munge.socket"
fi

# --- munge: a key of our own, munged on our own socket ----------------------
mungekey --create --keyfile="$work/munge-key/munge.key" 2> "$work/log/mungekey.log" \
  || { echo "FAIL: mungekey could not make a key"; show "$work/log/mungekey.log"; fail=$((fail + 1)); exit 1; }
munged -F --key-file="$work/munge-key/munge.key" --socket="$sock" --pid-file="$work/munge-run/munged.pid" \
  --seed-file="$work/munge-key/munged.seed" --log-file="$work/log/munged.log" > "$work/log/munged.out" 2>&1 &
munged_pid=$!
for _ in $(seq 100); do [ -S "$sock" ] && break; alive "$munged_pid" || break; sleep 0.1; done
munge_ok() { munge -S "$sock" -n 2> /dev/null | unmunge -S "$sock" > "$work/log/unmunge.out" 2>&1; }
check "munged started with its own key; a credential round-trips (munge | unmunge)" munge_ok \
  || { show "$work/log/munged.out" "$work/log/munged.log"; exit 1; }

# --- slurmctld and slurmd: a config of our own, ports that are free ---------
port_free() { ! (exec 3<> "/dev/tcp/127.0.0.1/$1") 2> /dev/null; }
base=$(( 20000 + ($$ % 400) * 50 ))
ctld_port="" slurmd_port=""
for p in $(seq "$base" $((base + 49))); do
  port_free "$p" && port_free $((p + 1)) && { ctld_port=$p; slurmd_port=$((p + 1)); break; }
done
[ -n "$ctld_port" ] || { echo "FAIL: no two free ports in $base..$((base + 50))"; fail=$((fail + 1)); exit 1; }
node=$(hostname -s 2> /dev/null || hostname)
cpus=$(nproc)
conf="$work/slurm.conf"
cat > "$conf" <<EOF
# Written by unit_test/integration/slurm/slurm_campaign_test.sh: one node, this machine.
ClusterName=rsetest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
# No cgroups, no systemd: process tracking through /proc, no task binding.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MailProg=/bin/true
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=rse Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$conf"
slurmctld -D -i -f "$conf" > "$work/log/slurmctld.out" 2>&1 &
ctld_pid=$!
slurmd -D -N "$node" -f "$conf" > "$work/log/slurmd.out" 2>&1 &
slurmd_pid=$!
node_idle() {
  local i
  for i in $(seq 120); do
    alive "$ctld_pid" && alive "$slurmd_pid" || return 1
    [ "$(sinfo -h -N -n "$node" -o %t 2> /dev/null)" = idle ] && return 0
    sleep 0.5
  done
  return 1
}
check "slurmctld and slurmd up on ports $ctld_port/$slurmd_port; node $node idle in partition rse" node_idle \
  || { show "$work/log/slurmctld.out" "$work/log/slurmctld.log" "$work/log/slurmd.out" "$work/log/slurmd.log"; exit 1; }

# --- The same seeds, locally and on the cluster -----------------------------
t0=$(date +%s.%N)
"$mc" run --seeds "$seeds" --jobs "$cpus" --out "$work/local/results.txt" --table "$work/local/table.txt" \
  > "$work/local/run.log" 2>&1
local_rc=$?
t1=$(date +%s.%N)
check "local run of seeds $seeds (exit $local_rc: 0 or 3)" test "$local_rc" = 0 -o "$local_rc" = 3 \
  || show "$work/local/run.log"

"$campaign_sh" --seeds "$seeds" --block-size "$block" --dir "$work/campaign" --bin "$mc" --partition rse \
  --wait "$wait_s" > "$work/campaign/submit.log" 2>&1
campaign_rc=$?
t2=$(date +%s.%N)
job=$(cut -d';' -f1 "$work/campaign/job_id" 2> /dev/null | head -n 1)
check "sbatch --array=0-$((tasks - 1)) job ${job:-?} ran, waited for and merged (exit $campaign_rc = local $local_rc)" \
  test "$campaign_rc" = "$local_rc"
[ "$campaign_rc" = "$local_rc" ] || show "$work/campaign/submit.log" "$work/campaign"/logs/*.out "$work/log/slurmd.log"

from_array() {  # one result file per array task, each written under this job's array task
  local i f
  for i in $(seq 0 $((tasks - 1))); do
    f=$(printf '%s/campaign/results/block-%06d.txt' "$work" "$i")
    grep -q "^B .* task=$i .*slurm_job=$job\$" "$f" 2> /dev/null || { echo "  $f: no B line of task $i of job $job"; return 1; }
  done
  [ "$(ls "$work/campaign/results" | wc -l)" -eq "$tasks" ]
}
check "$tasks result files, one from each array task of job ${job:-?}" from_array
check "merged table = local run's table, byte for byte" cmp "$work/local/table.txt" "$work/campaign/table.txt" \
  || diff "$work/local/table.txt" "$work/campaign/table.txt" | head -20
rows_equal() {
  cmp <(grep '^R ' "$work/local/results.txt") <(cat "$work"/campaign/results/block-*.txt | grep '^R ' | sort -t= -k2 -n)
}
check "every seed's row on the cluster = its row in the local run (20 R lines)" rows_equal

# A campaign with a block missing does not merge into a table.
mkdir -p "$work/partial"
cp "$work"/campaign/results/block-00000[012].txt "$work/partial/" 2> /dev/null
"$mc" merge "$work/partial" > "$work/partial/merge.log" 2>&1
partial_rc=$?
partial_refused() { [ "$partial_rc" = 1 ] && grep -q "5 seeds of the campaign missing.* 16 17 18 19 20" "$work/partial/merge.log"; }
check "a merge with task 3's block missing fails (exit $partial_rc) naming seeds 16..20" partial_refused \
  || show "$work/partial/merge.log"

awk -v a="$t0" -v b="$t1" -v c="$t2" 'BEGIN { printf "slurm_campaign: local run %.1f s, Slurm campaign (submit, 4 tasks, wait, merge) %.1f s\n", b - a, c - b }'

# Shared by the vcan guest scripts (busybox sh; sourced, not run): the pass/FAIL
# counters and a clean stop. Passed to the VM with --file (in $RSE_GUEST_DATA,
# /opt/rse/data there); natively it is beside the scripts.
pass=0
fail=0
# check NAME COMMAND...: "pass: NAME" when the command succeeds, else "FAIL: NAME".
check() {
  name=$1; shift
  if "$@"; then echo "pass: $name"; pass=$((pass + 1)); else echo "FAIL: $name"; fail=$((fail + 1)); fi
}
# stop PID: SIGTERM, up to 10 s to stop, then SIGKILL; returns its exit status.
stop() {
  kill -TERM $1 2>/dev/null
  k=0
  while [ $k -lt 100 ] && kill -0 $1 2>/dev/null; do sleep 0.1; k=$((k + 1)); done
  kill -KILL $1 2>/dev/null
  wait $1
}

# Guest side of the watchdog test (POSIX sh, busybox; run by run_in_vm.sh):
# softdog is /dev/watchdog. 1) rse-fsw arms it, feeds it and stops cleanly:
# the magic close disarms it and the computer keeps running past the timeout.
# 2) rse-fsw arms it and hangs (SIGSTOP): the computer restarts at the
# timeout. This script prints what it sees; the host side judges, because a
# restart ends the script before it can.
set -u
TIMEOUT_S=3
# softdog needs the watchdog core (its depends=; run_in_vm.sh copies both).
if [ -f /lib/modules/rse/watchdog.ko ]; then
    insmod /lib/modules/rse/watchdog.ko || { echo "FAIL: insmod watchdog.ko"; exit 1; }
fi
insmod /lib/modules/rse/softdog.ko || { echo "FAIL: insmod softdog.ko"; exit 1; }
[ -c /dev/watchdog ] || { echo "FAIL: no /dev/watchdog after insmod softdog"; exit 1; }

rse-fsw --no-rt --quiet --lab-key --watchdog /dev/watchdog --watchdog-timeout "$TIMEOUT_S" --duration 3 > /tmp/fsw1.log 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then
    echo "FAIL: rse-fsw with the watchdog exited $rc"; cat /tmp/fsw1.log; exit 1
fi
echo "WATCHDOG-CLEAN-STOP rc=0"
sleep $((TIMEOUT_S + 3))
echo "WATCHDOG-ALIVE-AFTER-CLEAN-STOP"

rse-fsw --no-rt --quiet --lab-key --watchdog /dev/watchdog --watchdog-timeout "$TIMEOUT_S" > /tmp/fsw2.log 2>&1 &
pid=$!
sleep 2
kill -0 "$pid" || { echo "FAIL: rse-fsw died before the hang"; cat /tmp/fsw2.log; exit 1; }
kill -STOP "$pid"
echo "WATCHDOG-HUNG"
sleep $((TIMEOUT_S + 10))
echo "WATCHDOG-STILL-RUNNING-AFTER-HANG"
exit 1

#!/usr/bin/env bash
# The watchdog on a real kernel watchdog (softdog), in the VM of ../vcan_vm:
# a clean stop of rse-fsw disarms it (the VM runs on past the timeout), a hung
# rse-fsw makes the kernel restart the computer at the timeout (qemu runs with
# -no-reboot, so the restart ends the VM). Ends with "N passed, N failed".
#
# env: RSE_BIN_DIR (default build/x86_64/bin)
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
bin=${RSE_BIN_DIR:-build/x86_64/bin}
out="$root/build/watchdog_test"
mkdir -p "$out"
cd "$root" || exit 1

"$root/unit_test/integration/vcan_vm/run_in_vm.sh" --bin "$bin/rse-fsw" "$here/watchdog_guest_test.sh" \
    > "$out/vm.log" 2>&1
vm_rc=$?
tr -d '\r' < "$out/vm.log" > "$out/vm.clean.log"
passed=0 failed=0
check() {  # $1 description, $2 command
    if eval "$2"; then echo "pass: $1"; passed=$((passed + 1)); else echo "FAIL: $1"; failed=$((failed + 1)); fi
}
has() { grep -q "$1" "$out/vm.clean.log"; }
check "rse-fsw armed softdog and stopped cleanly (exit 0)" "has WATCHDOG-CLEAN-STOP"
check "the clean stop disarmed it: the VM ran on past the timeout" "has WATCHDOG-ALIVE-AFTER-CLEAN-STOP"
check "rse-fsw was hung (SIGSTOP) with the watchdog armed" "has WATCHDOG-HUNG"
check "the kernel restarted the computer at the timeout" "has 'softdog: Initiating system reboot' && ! has WATCHDOG-STILL-RUNNING-AFTER-HANG"
check "the guest script reported no failure" "! grep -q '^FAIL' $out/vm.clean.log"
# run_in_vm.sh reports a VM that stopped without its result line as 125: the restart.
check "the VM ended by the restart, not by the script (run_in_vm status 125, was $vm_rc)" "[ $vm_rc -eq 125 ]"
echo "log: $out/vm.log"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]

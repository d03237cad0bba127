#!/usr/bin/env bash
# The real-SocketCAN integration test (make test-vcan; run by make test on the
# host): runs vcan_guest_test.sh with rse-fsw, rse-sim and rse-isotp on a real
# vcan0 (natively if the host has one, else in the VM of ../vcan_vm), then
# decodes the session's candump log against the ICD. Ends with "N passed, N failed".
#
# env: RSE_BIN_DIR (default build/x86_64/bin)
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
bin=${RSE_BIN_DIR:-build/x86_64/bin}
out="$root/build/vcan_test"
mkdir -p "$out"
cd "$root" || exit 1

# Natively where this kernel already has vcan0 up with can-isotp loaded (a
# user's Linux machine); otherwise in the VM with Debian's kernel (the
# development and CI machines have no CAN). The native path is not exercised on
# those machines.
if [ -e /sys/class/net/vcan0 ] && grep -q '^can_isotp' /proc/modules 2>/dev/null && [ -z "${RSE_FORCE_VM:-}" ]; then
  echo "vcan0 present: running natively"
  RSE_GUEST_BIN="$root/$bin" RSE_GUEST_DATA="$here" sh "$here/vcan_guest_test.sh" > "$out/vm.log" 2>&1
else
  "$root/unit_test/integration/vcan_vm/run_in_vm.sh" \
    --bin "$bin/rse-fsw" --bin "$bin/rse-sim" --bin "$bin/rse-isotp" --bin "$bin/rse-ground" \
    --file "$here/vcan_session.toml" --file "$here/vcan_guest_lib.sh" "$here/vcan_guest_test.sh" > "$out/vm.log" 2>&1
fi
vm_rc=$?

# Everything but the candump log goes to the console.
awk '/^=== CANDUMP BEGIN/ { skip = 1 } !skip { print } /^=== CANDUMP END/ { skip = 0 }' "$out/vm.log"
passed=$(grep -c '^pass: ' "$out/vm.log")
failed=$(grep -c '^FAIL: ' "$out/vm.log")

awk '/^=== CANDUMP END/ { on = 0 } on { print } /^=== CANDUMP BEGIN/ { on = 1 }' "$out/vm.log" \
  | tr -d '\r' > "$out/session.candump"
if [ -s "$out/session.candump" ] && awk -f "$here/decode_candump.awk" "$out/session.candump" > "$out/session.decoded"; then
  echo "pass: every frame of the session decodes against the ICD ($(tail -n 1 "$out/session.decoded"))"
  passed=$((passed + 1))
else
  echo "FAIL: the session's candump log does not decode against the ICD:"
  grep UNDECODED "$out/session.decoded" 2>/dev/null | head -n 10
  failed=$((failed + 1))
fi
grep '^count ' "$out/session.decoded" 2>/dev/null | sed 's/^/  /'
if [ "$vm_rc" -ne 0 ] && [ "$failed" -eq 0 ]; then
  echo "FAIL: the VM run ended with status $vm_rc (see $out/vm.log)"
  failed=$((failed + 1))
fi
echo "logs: $out/vm.log, $out/session.candump, $out/session.decoded"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]

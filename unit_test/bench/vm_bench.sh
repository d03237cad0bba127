#!/usr/bin/env bash
# make bench, VM part: runs bench_socketcan inside the vcan VM (real SocketCAN).
set -u
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RSE_BIN_DIR:-$root/build/x86_64/bin}
guest=$(mktemp)
trap 'rm -f "$guest"' EXIT
echo "bench_socketcan inside the vcan VM ($bin/bench_socketcan)"
printf '#!/bin/sh\n/opt/rse/bin/bench_socketcan vcan0\n' > "$guest"
"$root/unit_test/integration/vcan_vm/run_in_vm.sh" --bin "$bin/bench_socketcan" "$guest" 2>&1 \
  | grep -E '^(==|   |  (PASS|FAIL) |targets: )'
exit "${PIPESTATUS[0]}"

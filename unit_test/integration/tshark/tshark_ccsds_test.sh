#!/usr/bin/env bash
# An independent decoder agrees with ours: Wireshark's CCSDS dissector (tshark)
# decodes a capture of the UDP ground link, and its APIDs, sequence counts and
# packet lengths match what rse-ground decoded live (telemetry) and what the rover
# itself read from each command's header (the CMD_ACKs). docs/icd.md §5.
#
# Host only (captures on the loopback interface: needs root or the capture
# capability). Prints pass:/FAIL: lines and "N passed, N failed".
# env: RSE_BIN_DIR (default build/x86_64/bin), RSE_TSHARK_CMD_PORT / _TLM_PORT.
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
bin=${RSE_BIN_DIR:-build/x86_64/bin}
case "$bin" in /*) ;; *) bin="$root/$bin" ;; esac
cmd_port=${RSE_TSHARK_CMD_PORT:-31234}
tlm_port=${RSE_TSHARK_TLM_PORT:-31235}
out="$root/build/tshark_test"
rm -rf "$out" && mkdir -p "$out"
pass=0
fail=0
check() {
  local name=$1; shift
  if "$@"; then echo "pass: $name"; pass=$((pass + 1)); else echo "FAIL: $name"; fail=$((fail + 1)); fi
}
finish() { echo "$pass passed, $fail failed"; exit $(( fail > 0 ? 1 : 0 )); }

if ! command -v tshark >/dev/null || ! command -v dumpcap >/dev/null; then
  echo "FAIL: tshark/dumpcap not installed (make deps installs Debian's tshark)"; fail=1; finish
fi

pcap="$out/ground_link.pcapng"
dumpcap -q -i lo -f "udp port $cmd_port or udp port $tlm_port" -w "$pcap" > "$out/dumpcap.log" 2>&1 &
cap=$!
for _ in $(seq 50); do grep -q "Capturing on" "$out/dumpcap.log" 2>/dev/null && break; sleep 0.1; done
if ! kill -0 $cap 2>/dev/null; then
  echo "FAIL: dumpcap could not capture on lo:"; cat "$out/dumpcap.log"; fail=1; finish
fi

"$bin/rse-fsw" --udp --no-rt --quiet --lab-key --duration 7 --cmd-port "$cmd_port" --tlm-port "$tlm_port" \
    --auth-store "$out/auth.dat" --auth-store-create > "$out/fsw.log" 2>&1 &
fsw=$!
sleep 0.5
G=("$bin/rse-ground" --udp "127.0.0.1:$cmd_port" --tlm-port "$tlm_port" --state-dir "$out/ground-state")
# The watcher is the only telemetry listener; commands go out without waiting.
"${G[@]}" watch --seconds 4 > "$out/watch.log" 2>&1 &
watch=$!
sleep 0.5
"${G[@]}" send NOOP --auth-seq 100 --no-wait > /dev/null 2>&1
"${G[@]}" send SET_MODE mode=1 --no-wait > /dev/null 2>&1
"${G[@]}" send GOTO x=4 y=-2 risk=1e-4 --no-wait > /dev/null 2>&1
"${G[@]}" send REQUEST_HK --no-wait > /dev/null 2>&1
"${G[@]}" send NOOP --auth-seq 100 --no-wait > /dev/null 2>&1   # a replay: rejected, still acknowledged
wait $watch
wait $fsw
sleep 0.5
kill -INT $cap 2>/dev/null; wait $cap 2>/dev/null

# What tshark makes of it: direction, APID, type, sequence count, length field, UDP payload length.
fields=(-T fields -E separator=' ' -e udp.dstport -e ccsds.apid -e ccsds.type -e ccsds.seqnum -e ccsds.length -e udp.length)
tshark -r "$pcap" -d "udp.port==$cmd_port,ccsds" -d "udp.port==$tlm_port,ccsds" "${fields[@]}" > "$out/tshark.txt" 2> "$out/tshark.err"
check "tshark read the capture" [ -s "$out/tshark.txt" ]
awk -v p=$tlm_port '$1 == p { printf "%d %d\n", $2, $4 }' "$out/tshark.txt" > "$out/tshark_tlm.txt"
awk -v p=$cmd_port '$1 == p { printf "%d %d\n", $2, $4 }' "$out/tshark.txt" > "$out/tshark_cmd.txt"
echo "captured: $(wc -l < "$out/tshark_tlm.txt") telemetry and $(wc -l < "$out/tshark_cmd.txt") command packets"

# Every packet: CCSDS length field = UDP payload - 7 (UDP header 8 bytes).
check "every packet's CCSDS length field is its UDP payload length - 7" \
  awk '{ if ($5 + 7 != $6 - 8) { print "length mismatch: " $0; bad = 1 } } END { exit bad }' "$out/tshark.txt"
check "tshark sees commands as type 1 and telemetry as type 0" \
  awk -v c=$cmd_port -v t=$tlm_port '($1 == c && $3 != 1) || ($1 == t && $3 != 0) { bad = 1 } END { exit bad }' "$out/tshark.txt"

# Ours, telemetry: rse-ground watch lines "NAME apid=0x... seq=N ...".
sed -n 's/^[A-Z_]* *apid=\(0x[0-9a-fA-F]*\) seq=\([0-9]*\) .*/\1 \2/p' "$out/watch.log" \
  | while read -r apid seq; do printf '%d %d\n' "$apid" "$seq"; done > "$out/ours_tlm.txt"
check "telemetry: rse-ground decoded packets while the capture ran" [ "$(wc -l < "$out/ours_tlm.txt")" -gt 20 ]
# The capture also holds what the rover sent before and after the watcher
# listened: rse-ground's packets must be one unbroken run of tshark's.
contiguous_run() {
  local all ours
  all=" $(tr '\n' ',' < "$1")"
  ours=" $(tr '\n' ',' < "$2")"
  [[ "$all" == *"${ours# }"* ]] && [ -n "${ours# }" ]
}
check "telemetry: tshark's APIDs and sequence counts equal rse-ground's, packet for packet" \
  contiguous_run "$out/tshark_tlm.txt" "$out/ours_tlm.txt"

# Ours, commands: the rover's reading of each command header, from its CMD_ACKs.
sed -n 's/^CMD_ACK .* apid=\([0-9]*\) function_code=[0-9]* ccsds_sequence=\([0-9]*\) .*/\1 \2/p' "$out/watch.log" > "$out/ours_cmd.txt"
check "commands: five command packets on the wire" [ "$(wc -l < "$out/tshark_cmd.txt")" -eq 5 ]
check "commands: tshark's APIDs and sequence counts equal the rover's (CMD_ACK), in order" \
  cmp -s "$out/tshark_cmd.txt" "$out/ours_cmd.txt"
check "commands: the replay was acknowledged as rejected (reason 10)" grep -q "reason=10 " "$out/watch.log"

if [ $fail -gt 0 ]; then
  echo "--- tshark (head)"; head -n 20 "$out/tshark.txt"; echo "--- ours tlm (head)"; head -n 5 "$out/ours_tlm.txt"
  echo "--- ours cmd"; cat "$out/ours_cmd.txt"; echo "--- tshark cmd"; cat "$out/tshark_cmd.txt"
  echo "--- watch (head)"; head -n 5 "$out/watch.log" | cut -c1-300
fi
echo "logs and capture: $out"
finish

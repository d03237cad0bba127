#!/bin/sh
# Runs inside the vcan VM (busybox sh): rse-fsw and rse-sim as separate processes
# on vcan0, checked with can-utils; then our ISO-TP against the kernel's can-isotp.
# Prints pass:/FAIL: lines, then the session's candump -L log between markers for
# the host to decode against the ICD.
# Paths inside the VM; a native run (host with vcan0) passes its own.
B=${RSE_GUEST_BIN:-/opt/rse/bin}
D=${RSE_GUEST_DATA:-/opt/rse/data}
. "$D/vcan_guest_lib.sh"  # check, stop
count() { grep -c "$1" "$2" 2>/dev/null || true; }
# The console prints events at 10 Hz, after the acknowledgement may already have
# reached the ground tool, so a log line is waited for (up to 3 s), not assumed.
logged() {
  k=0
  while [ $k -lt 30 ]; do grep -q "$1" "$2" && return 0; sleep 0.1; k=$((k + 1)); done
  return 1
}

# --- Session: simulator first (its drives boot), then the flight software.
# Neither has a fixed duration (the --duration values are only backstops): the
# session ends on what can be seen, not on a clock that a slow machine (the VM
# emulates its CPU) overruns. Once every ground check has had its answer and the
# simulator has played its scenario's faults (heartbeat loss at 6-8 s, motor
# failure at 10 s: its TRUTH line for 13 s), the flight software is stopped
# (SIGTERM, a clean stop), then the simulator, so flight never sees the whole bus
# fall silent.
candump -L vcan0 > /tmp/session.log &
CANDUMP=$!
$B/rse-sim --can vcan0 --scenario $D/vcan_session.toml --duration 120 > /tmp/sim.log 2>&1 &
SIM=$!
sleep 0.3
# First boot of this rover: --auth-store-create provisions the anti-replay store.
$B/rse-fsw --can vcan0 --no-rt --lab-key --duration 120 --auth-store /tmp/auth.dat --auth-store-create > /tmp/fsw.log 2>&1 &
FSW=$!

i=0
while [ $i -lt 100 ] && [ "$(count 'EVT 432 ' /tmp/fsw.log)" -lt 6 ]; do sleep 0.1; i=$((i + 1)); done
check "all six drives configured by SDO and enabled over SocketCAN" [ "$(count 'EVT 432 ' /tmp/fsw.log)" -ge 6 ]
# --- Ground link: rse-ground commands over ISO-TP (0x6C0 up, 0x6C1 down).
G="$B/rse-ground --can vcan0 --state-dir /tmp/ground-state --timeout 5"
$G send NOOP --auth-seq 7001 > /tmp/g1.out 2>&1; g1=$?
check "rse-ground: authenticated NOOP over ISO-TP, acknowledged in telemetry (exit 0)" [ $g1 -eq 0 ]
check "rse-ground: the acknowledgement says accepted" grep -qi "accepted" /tmp/g1.out
check "rse-fsw: NOOP executed (EVT 500)" logged "EVT 500 INFO  cmd: NOOP (key 1, seq 7001)" /tmp/fsw.log
$G send NOOP --auth-seq 7001 > /tmp/g2.out 2>&1; g2=$?
check "rse-ground: a replayed copy is rejected by the rover (exit 3)" [ $g2 -eq 3 ]
check "rse-ground: the rejection names replayed_sequence" grep -q "replayed_sequence" /tmp/g2.out
check "rse-fsw: replay evented (EVT 530)" logged "EVT 530 ERROR cmd: rejected NOOP: replayed_sequence" /tmp/fsw.log
$G send SET_MODE mode=1 > /tmp/g3.out 2>&1; g3=$?
check "rse-ground: SET_MODE STANDBY accepted with a fresh sequence number" [ $g3 -eq 0 ]
# HK comes at 1 Hz: three of them (an older one may still have been queued when
# the mode changed), or 30 s at most (the guest is emulated: on a loaded host
# 10 s was once too short for three packets; a pass takes about 3 s).
$G watch --count 3 --seconds 30 --only HK > /tmp/g4.out 2>&1
check "rse-ground watch: housekeeping over ISO-TP shows mode 1" grep -q "mode=1" /tmp/g4.out

i=0
while [ $i -lt 600 ] && ! grep -q '^\[ *13\.000\] TRUTH' /tmp/sim.log; do sleep 0.1; i=$((i + 1)); done
check "rse-sim played the scenario for 13 s" grep -q '^\[ *13\.000\] TRUTH' /tmp/sim.log
stop $FSW; fsw_rc=$?
stop $SIM; sim_rc=$?
sleep 0.2
kill $CANDUMP 2>/dev/null
wait $CANDUMP 2>/dev/null

check "rse-fsw stopped cleanly on SIGTERM (exit 0)" sh -c "[ $fsw_rc -eq 0 ] && grep -q 'EVT 203 INFO  app: stop signal received' /tmp/fsw.log"
check "rse-sim stopped cleanly on SIGTERM (exit 0)" sh -c "[ $sim_rc -eq 0 ] && grep -q 'rse-sim: stopped (signal)' /tmp/sim.log"
check "flight reports node 3 lost when its heartbeat stops" grep -q "EVT 402 ERROR canopen: node 3 lost" /tmp/fsw.log
check "flight reports drive RL (node 3) lost" grep -q "EVT 436 ERROR drive RL (node 3): lost" /tmp/fsw.log
check "flight hears node 3 again when its heartbeat returns" grep -q "EVT 403 INFO  canopen: node 3 heard again" /tmp/fsw.log
check "flight reports EMCY 0x5000 from drive RR (node 6)" grep -q "EVT 406 ERROR drive RR (node 6): EMCY 0x5000" /tmp/fsw.log
check "flight declares drive RR failed after its resets" grep -q "EVT 434 CRIT  drive RR (node 6): still faulted" /tmp/fsw.log
check "interlock holds every wheel at zero" grep -q "EVT 601 CRIT  reflexive:" /tmp/fsw.log

# --- What went over the wire (independent view: candump).
L=/tmp/session.log
check "NMT reset communication to all nodes at start (000#8200)" grep -q "vcan0 000#8200$" $L
check "SYNC frames (080, DLC 0)" grep -q "vcan0 080#$" $L
for n in 1 2 3 4 5 6; do
  check "node $n: boot-up (70$n#00)" grep -q "vcan0 70$n#00$" $L
  check "node $n: SDO requests and responses (60$n/58$n)" sh -c "grep -q 'vcan0 60$n#' $L && grep -q 'vcan0 58$n#' $L"
  check "node $n: NMT start (000#010$n)" grep -q "vcan0 000#010$n$" $L
  check "node $n: operational heartbeats (70$n#05)" grep -q "vcan0 70$n#05$" $L
  check "node $n: RPDO1 0x20$n with 6 bytes" grep -qE "vcan0 20$n#[0-9A-F]{12}$" $L
  check "node $n: TPDO1 0x18$n with 8 bytes" grep -qE "vcan0 18$n#[0-9A-F]{16}$" $L
done
check "EMCY 0x5000 from node 6 on the wire (086#0050...)" grep -q "vcan0 086#0050" $L
for n in 20 21 22 23; do
  check "device node 0x$n heartbeats (7$n#)" grep -q "vcan0 7$n#" $L
done

# --- Our ISO-TP against the kernel's can-isotp, 4000 bytes each way, on the
# ground link's ids (0x6C0 uplink, 0x6C1 downlink; outside every CiA 301
# restricted range, docs/icd.md §1.2): ours as the rover, then as the ground.
awk 'BEGIN { for (i = 0; i < 4000; i++) printf "%02X%s", (i * 7 + 3) % 256, (i < 3999 ? " " : "\n") }' > /tmp/p.hex
$B/rse-isotp --can vcan0 --tx 6C1 --rx 6C0 --timeout 10 recv > /tmp/r1.hex &
R=$!
sleep 0.3
isotpsend -s 6C0 -d 6C1 vcan0 < /tmp/p.hex
wait $R
check "kernel isotpsend -> our ISO-TP: 4000 bytes identical" cmp -s /tmp/p.hex /tmp/r1.hex

isotprecv -s 6C1 -d 6C0 vcan0 > /tmp/r2.raw &
R=$!
sleep 0.3
$B/rse-isotp --can vcan0 --tx 6C0 --rx 6C1 --timeout 10 send < /tmp/p.hex
sleep 0.3
kill $R 2>/dev/null
wait $R 2>/dev/null
sed 's/ *$//' /tmp/r2.raw > /tmp/r2.hex
check "our ISO-TP -> kernel isotprecv: 4000 bytes identical" cmp -s /tmp/p.hex /tmp/r2.hex

if [ $fail -gt 0 ]; then
  echo "--- rse-fsw log (tail)"; tail -n 40 /tmp/fsw.log
  echo "--- rse-sim log (tail)"; tail -n 20 /tmp/sim.log
  for g in 1 2 3 4; do echo "--- rse-ground step $g"; cat /tmp/g$g.out; done
else
  # How loaded the session was (overruns, telemetry drops by priority, ISO-TP).
  echo "--- rse-fsw summary"; sed -n '/^rse-fsw summary/,$p' /tmp/fsw.log
fi
echo "=== CANDUMP BEGIN"
cat $L
echo "=== CANDUMP END"
echo "guest: $pass passed, $fail failed"
[ $fail -eq 0 ]

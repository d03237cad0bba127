#!/bin/sh
# Runs inside the vcan VM (busybox sh), or natively on a host with vcan0: the
# mission as three processes on vcan0. rse-sim plays the scenario, rse-fsw
# flies it, and rse-ground commands it only with ground packets over ISO-TP,
# as an operator would: the scenario's COARSE_MAP uploaded, SET_MODE
# AUTONOMOUS, GOTO with the risk bound; a fourth rse-ground records every
# packet received until the mission's outcome. Both rse-fsw and rse-sim run
# with --time-scale N (one mission timeline, N times slower than real time, so
# the emulated CPU keeps the 100 Hz frames); rse-fsw at real-time priority
# (SCHED_FIFO, as on the rover; the guest runs as root).
#
# usage: vcan_mission_guest.sh SCENARIO MAP_TABLE X Y RISK TIME_SCALE MISSION_S
#   MISSION_S: mission seconds the outcome may take (rse-fsw and rse-sim stop
#   there at the latest; the recording waits N times that).
# Prints pass:/FAIL: lines, the flight software's and the simulator's timing,
# then the recording between markers for the host to read.
B=${RSE_GUEST_BIN:-/opt/rse/bin}
D=${RSE_GUEST_DATA:-/opt/rse/data}
W=${RSE_GUEST_WORK:-/tmp/vcan_mission}
SCENARIO=$1 MAP=$2 X=$3 Y=$4 RISK=$5 N=$6 MISSION_S=$7
. "$D/vcan_guest_lib.sh"  # check, stop
uptime_s() { cut -d' ' -f1 /proc/uptime; }
rm -rf "$W" && mkdir -p "$W" && cd "$W" || exit 1
t_start=$(uptime_s)

# Simulator first, so the drives answer when the flight software starts.
$B/rse-sim --can vcan0 --scenario "$D/$SCENARIO" --time-scale "$N" --duration "$MISSION_S" > sim.log 2>&1 &
SIM=$!
sleep 0.5
$B/rse-fsw --can vcan0 --lab-key --auth-store auth.dat --auth-store-create --time-scale "$N" \
  --duration "$MISSION_S" > fsw.log 2>&1 &
FSW=$!

# The recorder: every packet from here to a tail after the outcome.
G="$B/rse-ground --can vcan0 --state-dir $W/ground-state --timeout $((2 * N))"
$G record session.rec --until-outcome --tail $((3 * N)) --seconds $((N * MISSION_S + 60)) --quiet > record.out 2>&1 &
REC=$!
i=0
while [ $i -lt 100 ] && ! grep -q '^recording ' record.out 2>/dev/null; do sleep 0.1; i=$((i + 1)); done

# The operator: contact (the rover sends telemetry over CAN once it has heard
# the ground; a NOOP again until one is acknowledged, as rse-fsw may still be
# starting), the drives up, the map, the mode, the goal. Waits are wall time:
# telemetry comes N times less often.
tries=1
until $B/rse-ground --can vcan0 --state-dir $W/ground-state --timeout 2 send NOOP > contact.out 2>&1; do
  [ $tries -lt 30 ] || break
  tries=$((tries + 1))
  sleep 1
done
check "ground: contact, a NOOP acknowledged (try $tries)" grep -q 'NOOP .* accepted' contact.out
cat > prepare.rsc <<EOF
wait DRIVES.state[0] == 4 within $((30 * N))
wait DRIVES.state[1] == 4 within $((2 * N))
wait DRIVES.state[2] == 4 within $((2 * N))
wait DRIVES.state[3] == 4 within $((2 * N))
wait DRIVES.state[4] == 4 within $((2 * N))
wait DRIVES.state[5] == 4 within $((2 * N))
wait ROVER_STATE.estimate_valid == 1 within $((10 * N))
EOF
cat > go.rsc <<EOF
send SET_MODE mode=AUTONOMOUS
send GOTO x=$X y=$Y risk=$RISK
EOF
$G run prepare.rsc > prepare.out 2>&1; prepare_rc=$?
check "ground: six drives operational (DRIVES), a pose estimate (ROVER_STATE)" [ $prepare_rc -eq 0 ]
$G table load "$D/$MAP" --activate > map.out 2>&1; map_rc=$?
check "ground: the scenario's COARSE_MAP uploaded (TABLE_LOAD chunks), validated, activated" \
  sh -c "[ $map_rc -eq 0 ] && grep -q 'COARSE_MAP loaded, validated and activated' map.out"
$G run go.rsc > go.out 2>&1; go_rc=$?
check "ground: SET_MODE AUTONOMOUS and GOTO x=$X y=$Y risk=$RISK accepted" [ $go_rc -eq 0 ]
t_goto=$(uptime_s)

wait $REC; rec_rc=$?
t_end=$(uptime_s)
check "ground: the recording reached the mission's outcome (record --until-outcome exit 0)" [ $rec_rc -eq 0 ]
stop $FSW; fsw_rc=$?
stop $SIM; sim_rc=$?
check "rse-fsw stopped cleanly (exit 0)" [ $fsw_rc -eq 0 ]
check "rse-sim stopped cleanly (exit 0)" [ $sim_rc -eq 0 ]
check "rse-fsw and rse-sim ran with time scale $N" \
  sh -c "grep -q 'time scale $N: 1 s of mission time every $N s' fsw.log && grep -q 'time scale $N: 1 simulated second' sim.log"

if [ $fail -gt 0 ]; then
  for f in record.out contact.out prepare.out map.out go.out; do echo "--- $f"; cat $f; done
  echo "--- rse-fsw log (tail)"; tail -n 60 fsw.log
  echo "--- rse-sim log (tail)"; tail -n 10 sim.log
fi
echo "--- wall time (guest): commanding $(awk -v a="$t_start" -v b="$t_goto" 'BEGIN { printf "%.1f", b - a }') s, mission to the end of the recording $(awk -v a="$t_goto" -v b="$t_end" 'BEGIN { printf "%.1f", b - a }') s"
echo "--- rse-fsw: real-time posture, frame timing (mission time)"
grep -E 'EVT 120 |^rse-fsw: ' fsw.log | head -n 3
echo "exec events: $(grep -c 'EVT 111 ' fsw.log) frame overruns (111), $(grep -c 'EVT 112 ' fsw.log) skips (112), $(grep -c 'EVT 113 ' fsw.log) task over budget (113)"
sed -n '/^rse-fsw summary/,$p' fsw.log
echo "--- rse-sim"
grep TRUTH sim.log | tail -n 1
grep -E '^rse-sim: (timing|stopped)' sim.log
echo "=== RECORDING BEGIN"
cat session.rec
echo "=== RECORDING END"
echo "guest: $pass passed, $fail failed"
[ $fail -eq 0 ]

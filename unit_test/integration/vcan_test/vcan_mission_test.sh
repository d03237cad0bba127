#!/usr/bin/env bash
# The mission over a real vcan, commanded only from the ground (issue 17; make
# test-vcan, make test): the scenario as three processes on vcan0 (rse-sim,
# rse-fsw, rse-ground over ISO-TP: COARSE_MAP upload, SET_MODE AUTONOMOUS,
# GOTO with the risk bound; rse-ground recording the telemetry), in the VM of
# ../vcan_vm where this kernel has no CAN (natively where it has), must reach
# the outcome the lockstep run (rse-demo, on this host, same scenario and goal)
# reaches. Both vcan processes run --time-scale N (default 5): the emulated CPU
# gets N times the wall time per frame, the mission is the same in mission time
# (docs/operations.md §3.2). Wall time: about N x the mission's seconds + 40 s.
# The run is not lockstep: the rover starts, hears its first position fix and
# gets its goal at other moments of the scenario, so its first estimate, its
# plan (there are near-equal ones either side of a rock) and where the worn
# motor trips differ from run to run. The outcome is compared; the time and
# place of it are printed beside the lockstep run's.
#
# Checked: the guest's steps (ground commands accepted, the recording reached
# the outcome, clean stops); from the recording alone (rse-ground summary):
# the outcome and the call-home reason and words equal the lockstep run's, the
# goal and risk bound the rover took, the final estimated position near this
# run's own simulator truth, plans and legs made, the call homes; that the
# slowness raised no fault (every fault raised is one the lockstep run raised
# or one of a drive the scenario wears or breaks) and
# the rover ran at the time scale asked; that every event missing from the
# recording is one the rover counted as not sent; and, from the recording with
# the map uploaded (rse-ground report), the ten points all in order, in the
# lockstep run's order, report.md and map.svg with every plan. Frame timing is
# printed.
# Ends with "N passed, N failed".
#
# env: RSE_BIN_DIR (default build/x86_64/bin), VCAN_MISSION_SCENARIO (default
# the demo), VCAN_MISSION_GOTO (X,Y,RISK; default 20,0,1e-3),
# VCAN_MISSION_TIME_SCALE (default 5), RSE_FORCE_VM (run in the VM even where
# vcan0 exists).
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)

# One more run, only for the route (above): a run whose only failed checks are
# the outcome's reason and words, the call homes, the plans and legs and the
# ten points (another route, on which the worn motor trips in a turn: mobility
# lost, measured 2026-12-03: 1 of 4 runs) runs again, and the second run's
# checks count. Any other failure (slowness faults, events lost, a guest step,
# a position off its truth) counts at once. The first run's log stays in
# build/vcan_mission/first_run.log, and the retry is said on the console.
route_only() {  # route_only LOG: every FAIL line is one the route explains
  local fails
  fails=$(grep '^FAIL: ' "$1") || return 1
  ! grep -vE '^FAIL: (call-home reason|the flight.s words for it|call homes|plans made|rse-ground report: ten points|the points from telemetry came in|report\.md names all ten points)' \
    <<< "$fails" | grep -q .
}
if [ -z "${RSE_VCAN_MISSION_RUN:-}" ]; then
  first_log="$root/build/vcan_mission_first_run.log"
  mkdir -p "$root/build"
  RSE_VCAN_MISSION_RUN=1 bash "$0" "$@" 2>&1 | tee "$first_log"
  rc=${PIPESTATUS[0]}
  if [ "$rc" -ne 0 ] && route_only "$first_log"; then
    echo "vcan mission: the first run failed only where another route explains it; running it once more (its checks count; the first run's log: build/vcan_mission/first_run.log)"
    mkdir -p "$root/build/vcan_mission"
    RSE_VCAN_MISSION_RUN=2 bash "$0" "$@"
    rc=$?
    mv "$first_log" "$root/build/vcan_mission/first_run.log"
    exit $rc
  fi
  rm -f "$first_log"
  exit "$rc"
fi
bin=${RSE_BIN_DIR:-build/x86_64/bin}
scenario=${VCAN_MISSION_SCENARIO:-sim_stub/scenarios/demo_mission.toml}
goto=${VCAN_MISSION_GOTO:-20,0,1e-3}
scale=${VCAN_MISSION_TIME_SCALE:-5}
out="$root/build/vcan_mission"
mkdir -p "$out"
cd "$root" || exit 1
t0=$(date +%s)
passed=0 failed=0
check() {  # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then passed=$((passed + 1)); echo "pass: $name"
  else failed=$((failed + 1)); echo "FAIL: $name"; fi
}
finish() {
  echo "logs: $out/ (lockstep.log, vm.log, session.rec, summary.txt, facts.txt, report.log, report/); wall time $(( $(date +%s) - t0 )) s"
  echo "$passed passed, $failed failed"
  [ "$failed" -eq 0 ]
  exit
}
IFS=, read -r gx gy grisk <<< "$goto"
fact() { sed -n "s/^$1=//p" "$out/facts.txt" | head -n 1; }
near() { awk -v a="$1" -v b="$2" -v c="$3" -v d="$4" -v tol="$5" 'BEGIN { exit !(sqrt((a - c)^2 + (b - d)^2) <= tol) }'; }

# --- The reference: the same scenario and goal in lockstep (rse-demo).
"$bin/rse-demo" --scenario "$scenario" --goto "$goto" --report "$out/lockstep_report" > "$out/lockstep.log" 2>&1; rc=$?
ref_outcome=$(sed -n 's/^outcome: *//p' "$out/lockstep.log")
check "lockstep reference (rse-demo) ran: $ref_outcome" sh -c "[ $rc -eq 0 ] && [ -n '$ref_outcome' ]"
case "$ref_outcome" in
  "called home at "*) ref_kind=called_home
    ref_time=$(sed -n 's/^called home at \([0-9.]*\) s.*/\1/p' <<< "$ref_outcome")
    ref_reason=$(sed -n 's/^called home at [0-9.]* s, reason \([0-9]*\):.*/\1/p' <<< "$ref_outcome")
    ref_words=$(sed -n 's/^called home at [0-9.]* s, reason [0-9]*: \(.*\) (mode [A-Z]*.*)$/\1/p' <<< "$ref_outcome") ;;
  "goal ("*) ref_kind=goal_reached
    ref_time=$(sed -n 's/.* reached at \([0-9.]*\) s$/\1/p' <<< "$ref_outcome")
    ref_reason=0 ref_words= ;;
  *) echo "FAIL: the lockstep run reached no outcome to compare with ($ref_outcome)"; failed=$((failed + 1)); finish ;;
esac
read -r ref_x ref_y < <(sed -n 's/^truth: *final position (\([-0-9.]*\), \([-0-9.]*\)).*/\1 \2/p' "$out/lockstep.log")
ref_calls=$(sed -n 's/^legs: .*, \([0-9]*\) call homes;.*/\1/p' "$out/lockstep.log")
read -r ref_sent ref_achieved < <(sed -n 's/^legs: *\([0-9]*\) sent, \([0-9]*\) achieved.*/\1 \2/p' "$out/lockstep.log")
ref_plans=$(sed -n 's/^plan: *\([0-9]*\) plans made.*/\1/p' "$out/lockstep.log")
ref_faults=$(grep -o 'EVT 7[0-9][0-9] [A-Z]* *health: fault [0-9]*:' "$out/lockstep.log" \
  | sed 's/.*fault \([0-9]*\):/\1/' | sort -n -u | paste -sd, -)
echo "lockstep: $ref_kind at $ref_time s, reason $ref_reason '$ref_words', final ($ref_x, $ref_y), faults [$ref_faults]"
# The mission in the VM gets the lockstep outcome's time and a minute more.
mission_s=$(awk -v t="$ref_time" 'BEGIN { printf "%d", t + 60 }')

# --- The operator's map: the scenario's COARSE_MAP, compiled by the ground.
"$bin/rse-sim" --coarse-map-source "$scenario" > "$out/coarse_map.toml" \
  && "$bin/rse-ground" table build "$out/coarse_map.toml" -o "$out/coarse_map.tbl" > "$out/map_build.log" 2>&1
check "the scenario's COARSE_MAP compiled for upload (rse-sim --coarse-map-source, rse-ground table build)" test -s "$out/coarse_map.tbl"

# --- The mission over vcan0.
guest_args=("$(basename "$scenario")" coarse_map.tbl "$gx" "$gy" "$grisk" "$scale" "$mission_s")
if [ -e /sys/class/net/vcan0 ] && grep -q '^can_isotp' /proc/modules 2>/dev/null && [ -z "${RSE_FORCE_VM:-}" ]; then
  echo "vcan0 present: running natively (time scale $scale)"
  mkdir -p "$out/data" && cp "$scenario" "$out/coarse_map.tbl" "$here/vcan_guest_lib.sh" "$out/data/"
  RSE_GUEST_BIN="$root/$bin" RSE_GUEST_DATA="$out/data" RSE_GUEST_WORK="$out/work" \
    sh "$here/vcan_mission_guest.sh" "${guest_args[@]}" > "$out/vm.log" 2>&1
else
  echo "running in the VM (time scale $scale, up to $mission_s s of mission time)"
  VM_TIMEOUT=$((scale * mission_s + 240)) "$root/unit_test/integration/vcan_vm/run_in_vm.sh" \
    --bin "$bin/rse-fsw" --bin "$bin/rse-sim" --bin "$bin/rse-ground" \
    --file "$scenario" --file "$out/coarse_map.tbl" --file "$here/vcan_guest_lib.sh" \
    "$here/vcan_mission_guest.sh" "${guest_args[@]}" > "$out/vm.log" 2>&1
fi
vm_rc=$?
awk '/^=== RECORDING BEGIN/ { skip = 1 } !skip { print } /^=== RECORDING END/ { skip = 0 }' "$out/vm.log" \
  | grep -vE '^(SeaBIOS|Booting from ROM)' 
passed=$((passed + $(grep -c '^pass: ' "$out/vm.log")))
failed=$((failed + $(grep -c '^FAIL: ' "$out/vm.log")))
if [ "$vm_rc" -ne 0 ] && ! grep -q '^FAIL: ' "$out/vm.log"; then
  echo "FAIL: the mission run ended with status $vm_rc (see $out/vm.log)"
  failed=$((failed + 1))
fi
awk '/^=== RECORDING END/ { on = 0 } on { print } /^=== RECORDING BEGIN/ { on = 1 }' "$out/vm.log" \
  | tr -d '\r' > "$out/session.rec"

# --- What the ground's recording says (the recording alone).
"$bin/rse-ground" summary "$out/session.rec" > "$out/summary.txt" 2> "$out/summary.err" \
  && "$bin/rse-ground" summary "$out/session.rec" --facts > "$out/facts.txt" 2>> "$out/summary.err"
check "rse-ground summary reads the recording whole ($(fact packets) packets, no bad line)" \
  sh -c "[ -s '$out/facts.txt' ] && [ ! -s '$out/summary.err' ] && [ '$(fact undecoded)' = 0 ]"
sed -n '1,/^events:/p' "$out/summary.txt" | sed '$d'
kind=$(fact outcome)
check "outcome from telemetry is the lockstep run's: $kind (lockstep: $ref_kind)" [ "$kind" = "$ref_kind" ]
check "call-home reason $(fact call_home_reason) (lockstep: $ref_reason)" [ "$(fact call_home_reason)" = "$ref_reason" ]
if [ "$ref_kind" = called_home ]; then
  check "the flight's words for it are the lockstep run's: '$ref_words'" \
    grep -qF -- "$ref_words" <<< "$(fact call_home_event)"
fi
check "the rover took the goal (PLAN): ($(fact goal_x), $(fact goal_y)) at risk bound $(fact risk_bound)" \
  awk -v x="$(fact goal_x)" -v y="$(fact goal_y)" -v r="$(fact risk_bound)" -v gx="$gx" -v gy="$gy" -v gr="$grisk" \
    'BEGIN { exit !((x - gx)^2 + (y - gy)^2 < 1e-6 && r == gr + 0) }'
# The final estimate from ROVER_STATE, within tol metres of (x, y).
final_near() { [ "$(fact final_pose_known)" = 1 ] && near "$(fact final_x)" "$(fact final_y)" "$1" "$2" "$3"; }
read -r sim_x sim_y < <(sed -n 's/.* TRUTH x=\([-0-9.]*\) y=\([-0-9.]*\) .*/\1 \2/p' "$out/vm.log" | tail -n 1)
check "final position from telemetry within 0.5 m of this run's simulator truth ($sim_x, $sim_y)" \
  final_near "${sim_x:-1e9}" "${sim_y:-1e9}" 0.5
# Made and reached at all when the lockstep run made and reached them.
at_least_one_if() { [ "$1" -eq 0 ] || [ "$2" -ge 1 ]; }
check "plans made ($(fact plans); lockstep $ref_plans), legs sent ($(fact legs_sent); $ref_sent) and reached ($(fact legs_achieved); $ref_achieved)" \
  sh -c "$(declare -f at_least_one_if); at_least_one_if $ref_plans $(fact plans) && at_least_one_if $ref_sent $(fact legs_sent) && at_least_one_if $ref_achieved $(fact legs_achieved)"
check "call homes $(fact call_homes) (lockstep: $ref_calls)" [ "$(fact call_homes)" = "$ref_calls" ]
# Faults raised: every id HEALTH.active_faults showed, and every health raise
# event received ("health: fault N: ..."), as the lockstep run's console shows them.
vm_faults=$( { tr ',' '\n' <<< "$(fact faults)"; grep -o 'EVT 7[0-9][0-9] [A-Z]* health: fault [0-9]*:' "$out/summary.txt" \
  | sed 's/.*fault \([0-9]*\):/\1/'; } | grep . | sort -n -u | paste -sd, -)
# A subset, not equal: a run on a bus may end before a fault the lockstep run
# raised (its route and timing differ, e.g. the worn motor never tripping its
# drive before the call home); what the slowness would add is a fault lockstep
# never raised.
# Beyond those, a fault of a wheel the scenario itself wears or breaks is the
# scenario's doing, not the slowness's: the worn motor may trip on overcurrent
# in a turn the bus run makes and the lockstep run does not (CI measured: 12,
# overcurrent on wheel 1, where lockstep saw 2, its heartbeat lost). The
# scenario's [[faults]] number wheels 1..6 (sim_stub/scenarios/README.md), the
# flight's faults 0..5: heartbeat lost 1+w, overcurrent 11+w, overtemperature
# 40+w (fsw/msg/health_msgs.hpp).
scenario_wheel_faults=$(awk '/^\[\[faults\]\]/ { f = 1; next } /^\[/ { f = 0 }
    f && /^wheel *=/ { line = $0; sub(/#.*/, "", line); split(line, a, "="); w = a[2] - 1
                       if (w >= 0 && w < 6) printf "%d\n%d\n%d\n", 1 + w, 11 + w, 40 + w }' "$scenario" | sort -nu | paste -sd, -)
subset_of() { [ -z "$(comm -23 <(tr ',' '\n' <<< "$1" | grep . | sort -u) <(tr ',' '\n' <<< "$2" | grep . | sort -u))" ]; }
check "the slowness raised nothing: faults raised [$vm_faults] are among the lockstep run's [$ref_faults] and the scenario's faulted drives' [$scenario_wheel_faults]" \
  subset_of "$vm_faults" "$ref_faults,$scenario_wheel_faults"
check "the rover ran at time scale $(fact time_scale) (HK.time_scale; asked $scale)" [ "$(fact time_scale)" = "$scale" ]
# Measured, not asserted: a frame may still overrun, or one be skipped, while
# the emulator first translates the planner's code (docs/operations.md §3.2);
# what would matter, a fault, is checked above.
echo "frame timing (HK, mission time): $(fact frames_run) frames run, $(fact frame_overruns) overran, $(fact frames_skipped) skipped; worst start lateness $(fact frame_lateness_max_us) us, busiest frame $(fact frame_busy_max_us) us"
# The CAN downlink sends about one EVENT packet a frame and queues 16 events:
# a burst of events (start-up, a fault response) loses some, and the rover
# counts them (HK.tlm_dropped). What the ground missed must be what the rover
# says it dropped, nothing lost silently on the way.
check "events missing from the recording ($(fact events_lost) of $(( $(fact events) + $(fact events_lost) ))) are no more than the rover counted unsent (HK.tlm_dropped $(fact tlm_dropped), HK.events_lost $(fact event_log_lost))" \
  [ "$(fact events_lost)" -le $(( $(fact tlm_dropped) + $(fact event_log_lost) )) ]

# --- The ten points, the report and the map from the telemetry alone
# (rse-ground report), as an operator on the bus would get them: the same
# points in the same order as the lockstep run's, and the two files.
"$bin/rse-ground" report "$out/session.rec" --map "$out/coarse_map.tbl" --out "$out/report" \
  --name "$(basename "$scenario") over vcan0 (telemetry)" > "$out/report.log" 2> "$out/report.err"; report_rc=$?
grep '^\[.*\] POINT ' "$out/report.log"
ref_points=$(sed -n 's/^\[ *[0-9.]*\] POINT \([0-9]*\) .*/\1/p' "$out/lockstep.log" | paste -sd' ' -)
vm_points=$(sed -n 's/^\[ *[0-9.]*\] POINT \([0-9]*\) .*/\1/p' "$out/report.log" | paste -sd' ' -)
check "rse-ground report: $(sed -n 's/^points: *//p' "$out/report.log") (exit $report_rc)" \
  sh -c "[ $report_rc -eq 0 ] && grep -q '^points: *ten points: all in order' '$out/report.log'"
check "the points from telemetry came in the lockstep run's order: [$vm_points] (lockstep [$ref_points])" \
  sh -c "[ -n '$ref_points' ] && [ '$vm_points' = '$ref_points' ]"
plans_drawn=$(sed -n 's/^plans: *\([0-9]*\) drawn.*/\1/p' "$out/report.log")
check "report.md names all ten points and map.svg draws the rover's $(fact plans) plan(s) from PLAN_PATH ($plans_drawn drawn)" \
  sh -c "[ \$(awk '/^## The ten points/ { on = 1 } /^## Legs/ { on = 0 } on && /^\\| [0-9]+ \\| [0-9.]+ \\| [a-z]/' '$out/report/report.md' | wc -l) -eq 10 ] \\
         && ! grep -q 'NOT SEEN' '$out/report/report.md' \
         && [ '${plans_drawn:-0}' = '$(fact plans)' ] && [ '${plans_drawn:-0}' -ge 1 ] && grep -q '<svg' '$out/report/map.svg'"
ref_line() { sed -n "s/^$1: *//p" "$out/lockstep.log"; }
echo "--- lockstep (rse-demo, simulator truth) beside vcan (telemetry):"
echo "  lockstep outcome: $ref_kind at $ref_time s, final position ($ref_x, $ref_y)"
echo "  vcan     outcome: $kind at $(fact outcome_time) s of flight time, final position ($(fact final_x), $(fact final_y)), $(awk -v a="$(fact final_x)" -v b="$(fact final_y)" -v c="$ref_x" -v d="$ref_y" 'BEGIN { printf "%.2f", sqrt((a - c)^2 + (b - d)^2) }') m from the lockstep's"
echo "  lockstep legs: $(ref_line legs)"
echo "  vcan     legs: $(fact legs_sent) sent, $(fact legs_achieved) achieved, $(fact fail_ups) fail-ups; $(fact replans) replans, $(fact bound_relaxations) bound relaxations, $(fact risk_relaxations) risk relaxations, $(fact call_homes) call homes"
echo "  lockstep plan: $(ref_line plan)"
echo "  vcan     plan: $(fact plans) plans made; the last $(printf %.2f "$(fact plan_length)") m"
finish

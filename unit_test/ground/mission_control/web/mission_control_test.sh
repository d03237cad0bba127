#!/usr/bin/env bash
# The mission control display end to end (issue 19, docs/mission_control.md):
# rse-ground serve on a fresh archive, the demo mission paced (rse-demo --pace)
# sending the flight's telemetry over UDP to it, and Debian's Chromium
# (puppeteer-core) on the page: live plots receive points, the event log
# shows the mission's events, the map draws the plan and the track, drive
# health shows six wheels (display_test.mjs, live). Then the display is
# restarted on the same archive with nothing coming in, and a historical query
# of the mission's interval, made in the page, returns the archived points
# (display_test.mjs --history). Screenshots: build/mission_control/display_live.png
# and display_history.png. Ends with "N passed, N failed" over every check.
#
# env: RSE_BIN_DIR (rse-ground, rse-demo); MC_PACE (default 2: the mission's
# 97 s take about 50 s, longer than the live checks even on a loaded machine).
# Needs make mission-control-deps (node_modules, chromium): make test runs it.
set -u
bin=${RSE_BIN_DIR:?set RSE_BIN_DIR}
pace=${MC_PACE:-2}
out=build/mission_control
work=$out/test
mkdir -p "$work"
rm -f "$work"/archive.sqlite*
passed=0 failed=0
serve_pid="" demo_pid=""

check() {  # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then passed=$((passed + 1)); echo "  pass: $name"
  else failed=$((failed + 1)); echo "  FAIL: $name"; fi
}
finish() {
  [ -n "$demo_pid" ] && kill "$demo_pid" 2>/dev/null
  [ -n "$serve_pid" ] && kill "$serve_pid" 2>/dev/null
  wait 2>/dev/null
  echo "$passed passed, $failed failed"
  exit $((failed > 0 ? 1 : 0))
}
trap finish EXIT
add_counts() {  # the "N passed, N failed" line a display test printed last
  local line
  line=$(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$1" | tail -1)
  if [ -z "$line" ]; then failed=$((failed + 1)); echo "  FAIL: $1 printed no summary"; return; fi
  passed=$((passed + $(echo "$line" | cut -d' ' -f1)))
  failed=$((failed + $(echo "$line" | cut -d' ' -f3)))
}
ms_now() { date +%s%3N; }

web=ground/mission_control/web
if [ ! -d "$web/node_modules/openmct" ] || [ ! -d "$web/node_modules/puppeteer-core" ] || ! command -v chromium >/dev/null; then
  echo "  FAIL: the display's packages or chromium are missing (make mission-control-deps)"
  failed=$((failed + 1))
  exit 1
fi
# A free UDP port for the telemetry (the kernel's pick, released at once).
tlm_port=$(node -e "const s=require('dgram').createSocket('udp4');s.bind(0,'127.0.0.1',()=>{console.log(s.address().port);s.close();})")

# start_serve LOG: rse-ground serve on an ephemeral HTTP port; sets serve_pid and url.
start_serve() {
  "$bin/rse-ground" --tlm-port "127.0.0.1:$tlm_port" serve --http 127.0.0.1:0 \
    --archive "$work/archive.sqlite" >"$1" 2>&1 &
  serve_pid=$!
  url=""
  for _ in $(seq 100); do
    url=$(sed -n 's|^serving \(http://127.0.0.1:[0-9]*/\).*|\1|p' "$1")
    [ -n "$url" ] && break
    sleep 0.1
  done
  [ -n "$url" ]
}
stop_serve() {
  kill -TERM "$serve_pid" 2>/dev/null
  wait "$serve_pid"
  local rc=$?
  serve_pid=""
  return $rc
}

echo "mission control: live, rse-demo --pace $pace over UDP 127.0.0.1:$tlm_port"
check "rse-ground serve starts and names its URL" start_serve "$work/serve_live.log"
t0=$(ms_now)
"$bin/rse-demo" --pace "$pace" --udp-telemetry "127.0.0.1:$tlm_port" --no-report --any-outcome \
  >"$work/demo.log" 2>&1 &
demo_pid=$!
node unit_test/ground/mission_control/web/display_test.mjs --url "$url" --live \
  --screenshot "$out/display_live.png" 2>&1 | tee "$work/display_live.log"
add_counts "$work/display_live.log"
wait "$demo_pid"
demo_rc=$?
demo_pid=""
t1=$(ms_now)
check "the paced demo mission ran to its end (exit $demo_rc)" test "$demo_rc" -eq 0
check "the live screenshot was saved" test -s "$out/display_live.png"
check "rse-ground serve stops cleanly on SIGTERM" stop_serve
check "every packet received was archived" \
  grep -qE '^serve: ([1-9][0-9]*) packets received, \1 archived, 0 not decoded, 0 archive errors' "$work/serve_live.log"

echo "mission control: history, after a restart of the display, nothing coming in"
check "rse-ground serve restarts on the same archive" start_serve "$work/serve_history.log"
node unit_test/ground/mission_control/web/display_test.mjs --url "$url" --history --interval "$t0:$t1" \
  --screenshot "$out/display_history.png" 2>&1 | tee "$work/display_history.log"
add_counts "$work/display_history.log"
check "the history screenshot was saved" test -s "$out/display_history.png"
check "the restarted rse-ground serve stops cleanly" stop_serve
check "the restarted display received nothing: the history came from the archive" grep -qE '^serve: 0 packets received' "$work/serve_history.log"

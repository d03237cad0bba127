#!/bin/sh
# smoke_test.sh — runs INSIDE the run_in_vm.sh guest (busybox sh, POSIX only).
# Proves the harness: vcan0 is up, a raw frame goes cansend -> candump, a 4000-byte
# PDU goes isotpsend -> isotprecv through the kernel ISO-TP stack (candump sees FF,
# FC and CFs), and binaries passed with --bin run. Prints one "pass:"/"FAIL:" line
# per check and exits 1 if any check failed.
#
# usage (host): run_in_vm.sh --bin /bin/true [--bin can_hello] smoke_test.sh
# A --bin named can_hello (built by vm_smoke_test.sh) is expected to send one
# CAN_RAW frame 321#C0FFEE on vcan0 from its own socket(PF_CAN) code.

PASSES=0
FAILS=0
ok()  { echo "pass: $*"; PASSES=$((PASSES + 1)); }
bad() { echo "FAIL: $*"; FAILS=$((FAILS + 1)); }
W=/tmp/smoke
mkdir -p "$W"

# Count the CAN receivers bound on vcan0 (every rcvlist_* in /proc/net/can).
receivers() {
    cat /proc/net/can/rcvlist_* 2>/dev/null | awk '$1 == "vcan0" { n++ } END { print n + 0 }'
}
# Wait until more than $1 receivers are bound on vcan0 (max ~10 s).
wait_receivers() {
    i=0
    while [ "$(receivers)" -le "$1" ]; do
        i=$((i + 1))
        [ $i -le 100 ] || return 1
        sleep 0.1
    done
}
# Stop a background process and reap it.
stop() { kill -INT "$1" 2>/dev/null; wait "$1" 2>/dev/null; }

# --- 1. vcan0 exists and is UP ---------------------------------------------------
if [ -d /sys/class/net/vcan0 ]; then
    flags=$(cat /sys/class/net/vcan0/flags)
    type=$(cat /sys/class/net/vcan0/type)
    if [ $((flags & 1)) -eq 1 ] && [ "$type" = 280 ] \
       && ip link show vcan0 | grep -q '<[^>]*UP[,>]'; then
        ok "vcan0 exists, type CAN (280), UP (flags $flags)"
    else
        bad "vcan0 not UP or not CAN: flags=$flags type=$type"
        ip link show vcan0
    fi
else
    bad "vcan0 does not exist"
    ip link show
fi

# --- 2. raw frame: cansend -> candump -L -------------------------------------------
base=$(receivers)
candump -L vcan0 > "$W/raw.log" 2>&1 &
dump=$!
if wait_receivers "$base"; then
    if cansend vcan0 123#DEADBEEF; then
        i=0
        while ! grep -q 'vcan0 123#DEADBEEF' "$W/raw.log" && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
    else
        bad "cansend vcan0 123#DEADBEEF failed"
    fi
    stop "$dump"
    if grep -q 'vcan0 123#DEADBEEF' "$W/raw.log"; then
        ok "candump -L saw: $(grep 'vcan0 123#DEADBEEF' "$W/raw.log" | head -n 1)"
    else
        bad "candump -L did not see 123#DEADBEEF; it logged:"
        cat "$W/raw.log"
    fi
else
    stop "$dump"
    bad "candump never bound a receiver on vcan0"
    cat "$W/raw.log"
fi

# --- 3. ISO-TP: 4000-byte PDU isotpsend -> isotprecv, FF/FC/CF on the bus ----------
N=4000
awk -v n=$N 'BEGIN { for (i = 0; i < n; i++) printf "%02X%s", i % 256, (i < n - 1 ? " " : "\n") }' \
    > "$W/payload.txt"
base=$(receivers)
candump -L vcan0 > "$W/isotp.log" 2>&1 &
dump=$!
timeout 30 isotprecv -s 7E8 -d 7E0 vcan0 > "$W/recv.txt" 2> "$W/recv.err" &
recv=$!
# candump adds 1 receiver, isotprecv 1 (its rx id 7E0)
if wait_receivers $((base + 1)); then
    t0=$(cut -d' ' -f1 /proc/uptime)
    if timeout 30 isotpsend -s 7E0 -d 7E8 vcan0 < "$W/payload.txt" 2> "$W/send.err"; then
        sent=1
    else
        sent=0
        bad "isotpsend failed: $(cat "$W/send.err")"
    fi
    wait "$recv"
    rrc=$?
    t1=$(cut -d' ' -f1 /proc/uptime)
    sleep 0.2
    stop "$dump"
    # one hex byte per line on both sides, so spacing and case do not matter
    tr -s ' \n' '\n\n' < "$W/payload.txt" | grep . | tr a-f A-F > "$W/want.hex"
    tr -s ' \n' '\n\n' < "$W/recv.txt" | grep . | tr a-f A-F > "$W/got.hex"
    got=$(wc -l < "$W/got.hex")
    if [ "$sent" = 1 ] && [ $rrc -eq 0 ] && [ "$got" -eq $N ] && cmp -s "$W/want.hex" "$W/got.hex"; then
        ok "isotprecv got all $N bytes, content identical (send+receive $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }') s guest time)"
    else
        bad "isotprecv: rc=$rrc, $got of $N bytes, content $(cmp -s "$W/want.hex" "$W/got.hex" && echo same || echo differs); stderr: $(cat "$W/recv.err")"
        head -c 200 "$W/recv.txt"; echo
    fi
    # 4000 = 0xFA0: First Frame PCI 1F A0 on 7E0; Flow Control (PCI 3x) from 7E8;
    # (4000 - 6) / 7 -> 571 Consecutive Frames (PCI 2x) on 7E0.
    ff=$(grep -c 'vcan0 7E0#1FA0' "$W/isotp.log")
    fc=$(grep -c 'vcan0 7E8#3' "$W/isotp.log")
    cf=$(grep -c 'vcan0 7E0#2' "$W/isotp.log")
    if [ "$ff" -eq 1 ] && [ "$fc" -ge 1 ] && [ "$cf" -eq 571 ]; then
        ok "candump saw ISO-TP First Frame ($(grep -m1 'vcan0 7E0#1FA0' "$W/isotp.log" | cut -d' ' -f3)), $fc Flow Control ($(grep -m1 'vcan0 7E8#3' "$W/isotp.log" | cut -d' ' -f3)), $cf Consecutive Frames"
    else
        bad "candump ISO-TP frames: FF=$ff (want 1) FC=$fc (want >=1) CF=$cf (want 571)"
        head -n 5 "$W/isotp.log"
    fi
else
    stop "$dump"; stop "$recv"
    bad "candump/isotprecv never bound their receivers on vcan0"
    cat "$W/isotp.log" "$W/recv.err"
fi

# --- 4. --bin: caller's binaries run in the guest ----------------------------------
if [ -x /opt/rse/bin/true ] && /opt/rse/bin/true; then
    ok "--bin /bin/true runs as /opt/rse/bin/true (dynamic, with its libraries)"
else
    bad "/opt/rse/bin/true missing or failed (pass --bin /bin/true)"
fi
if [ -x /opt/rse/bin/can_hello ]; then
    base=$(receivers)
    candump -L vcan0 > "$W/hello.log" 2>&1 &
    dump=$!
    if wait_receivers "$base" && out=$(/opt/rse/bin/can_hello vcan0 2>&1); then
        i=0
        while ! grep -q 'vcan0 321#C0FFEE' "$W/hello.log" && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
        stop "$dump"
        if grep -q 'vcan0 321#C0FFEE' "$W/hello.log"; then
            ok "--bin can_hello (compiled on the host) sent 321#C0FFEE over its own PF_CAN socket: $out"
        else
            bad "can_hello ran ($out) but candump did not see 321#C0FFEE"
            cat "$W/hello.log"
        fi
    else
        stop "$dump"
        bad "can_hello failed: $out"
    fi
fi

echo "smoke: $PASSES passed, $FAILS failed"
[ "$FAILS" -eq 0 ]

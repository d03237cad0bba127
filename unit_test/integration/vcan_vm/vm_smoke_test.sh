#!/bin/bash
# vm_smoke_test.sh — host side: proves run_in_vm.sh by booting the CAN VM with
# smoke_test.sh (vcan0 up, cansend -> candump, 4000-byte ISO-TP isotpsend ->
# isotprecv, --bin binaries). Ends with one line "N passed, N failed" and exits
# non-zero if anything failed. Run as root from anywhere in the repo.
set -uo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO_ROOT=$(cd "$HERE/../../.." && pwd)
cd "$REPO_ROOT" || exit 1
OUT_DIR=build/vcan_vm
mkdir -p "$OUT_DIR"

# A tiny C program with its own socket(PF_CAN) code, to prove that --bin carries a
# dynamically linked host binary (and its libraries) into the guest and that it can
# use SocketCAN there. It needs a C compiler (gcc comes with 'make deps').
BINS=(--bin /bin/true)
EXPECTED=5
CC=${CC:-cc}
if command -v "$CC" >/dev/null 2>&1; then
    cat > "$OUT_DIR/can_hello.c" <<'CSRC'
/* can_hello: send one CAN_RAW frame 321#C0FFEE on the interface given (vcan0). */
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

int main(int argc, char **argv)
{
    const char *ifname = argc > 1 ? argv[1] : "vcan0";
    struct sockaddr_can addr;
    struct can_frame frame;
    int s = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (s < 0) { perror("socket(PF_CAN)"); return 1; }
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = (int)if_nametoindex(ifname);
    if (addr.can_ifindex == 0) { perror(ifname); return 1; }
    if (bind(s, (struct sockaddr *)&addr, sizeof addr) != 0) { perror("bind"); return 1; }
    memset(&frame, 0, sizeof frame);
    frame.can_id = 0x321;
    frame.can_dlc = 3;
    frame.data[0] = 0xC0; frame.data[1] = 0xFF; frame.data[2] = 0xEE;
    if (write(s, &frame, sizeof frame) != (ssize_t)sizeof frame) { perror("write"); return 1; }
    printf("can_hello: sent 321#C0FFEE on %s (ifindex %d)\n", ifname, addr.can_ifindex);
    close(s);
    return 0;
}
CSRC
    if "$CC" -O2 -Wall -Wextra -Werror -o "$OUT_DIR/can_hello" "$OUT_DIR/can_hello.c"; then
        BINS+=(--bin "$OUT_DIR/can_hello")
        EXPECTED=6
    else
        echo "FAIL: compiling $OUT_DIR/can_hello.c"
        echo "0 passed, 1 failed"
        exit 1
    fi
else
    echo "note: no C compiler ($CC): the can_hello --bin check is left out (run 'make deps')"
fi

LOG="$OUT_DIR/vm_smoke_test.log"
"$HERE/run_in_vm.sh" "${BINS[@]}" "$HERE/smoke_test.sh" | tee "$LOG"
rc=${PIPESTATUS[0]}

passed=$(grep -c '^pass:' "$LOG")
failed=$(grep -c '^FAIL:' "$LOG")
if [ $((passed + failed)) -lt "$EXPECTED" ]; then
    echo "FAIL: only $((passed + failed)) of $EXPECTED checks reported (harness exit $rc)"
    failed=$((failed + EXPECTED - passed - failed))
fi
if [ "$rc" -ne 0 ] && [ "$failed" -eq 0 ]; then
    echo "FAIL: run_in_vm.sh exited $rc"
    failed=1
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$rc" -eq 0 ]

// Frames per second through the kernel's SocketCAN path: two CAN_RAW sockets on
// one interface (vcan0 inside the VM), one writing, one reading, in bursts the
// socket buffers can hold. Run by make bench inside the vcan VM
// (unit_test/bench/vm_bench.sh); where the kernel has no CAN it says so and
// exits 0.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "hal/can/socketcan_bus.hpp"

using namespace rse;

int main(int argc, char** argv) {
    const char* iface = argc > 1 ? argv[1] : "vcan0";
    hal::SocketCanBus tx, rx;
    if (!core::isOk(tx.open(iface)) || !core::isOk(rx.open(iface))) {
        std::printf("SocketCAN on %s unavailable here (%s): not measured\n", iface, std::strerror(tx.lastErrno()));
        return 0;
    }
    const int total = 200000;
    const int burst = 32;
    hal::CanFrame f;
    f.id = 0x181;
    f.dlc = 8;
    hal::CanFrame got;
    core::MonotonicClock clock;
    int sent = 0, received = 0, refused = 0;
    const core::TimeNs begin = clock.now();
    while (received < total) {
        for (int i = 0; i < burst && sent < total; ++i) {
            f.data[0] = static_cast<std::uint8_t>(sent);
            if (core::isOk(tx.send(f))) {
                ++sent;
            } else {
                ++refused;
                break;
            }
        }
        while (core::isOk(rx.receive(&got))) {
            ++received;
        }
        if (clock.now() - begin > 60 * core::kNsPerSec) {
            break;
        }
    }
    const double seconds = static_cast<double>(clock.now() - begin) * 1e-9;
    std::printf("== SocketCAN %s: %d frames written and read in %.3f s = %.0f frames/s (%d sends refused: queue full)\n",
                iface, received, seconds, received / seconds, refused);
    std::printf("   (measured inside the emulated VM: a function check and a lower bound, not hardware speed)\n");
    return received == total ? 0 : 1;
}

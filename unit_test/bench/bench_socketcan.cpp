// Frames per second through the kernel's SocketCAN path: two CAN_RAW sockets on
// one interface (vcan0 inside the VM), one writing, one reading, in bursts the
// socket buffers can hold. Run by make bench inside the vcan VM
// (unit_test/bench/vm_bench.sh); where the kernel has no CAN it says so and
// exits 0. Targets (unit_test/bench/bench_targets.hpp): every frame written is
// read back, in order, and the path carries at least a saturated 1 Mbit/s bus
// (kBusFramesPerSecond), even under emulation.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "hal/can/socketcan_bus.hpp"
#include "unit_test/bench/bench_targets.hpp"

using namespace rse;

// 8-byte data frames with standard ids are at most 135 bits on the wire (with
// worst-case stuffing, 111 without): 1 Mbit/s carries at most ~9 000 a second.
constexpr double kBusFramesPerSecond = 9000.0;

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
    int sent = 0, received = 0, refused = 0, outOfOrder = 0;
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
            outOfOrder += got.data[0] == static_cast<std::uint8_t>(received) ? 0 : 1;
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
    bench::Targets targets;
    const bool allRead = received == total && outOfOrder == 0;
    const double rate = received / seconds;
    std::printf("  %s every frame read back in order (%d of %d, %d out of order)\n",
                targets.check(allRead) ? "PASS" : "FAIL", received, total, outOfOrder);
    std::printf("  %s frames/s >= a saturated 1 Mbit/s bus, %.0f (%.0f)\n",
                targets.check(rate >= kBusFramesPerSecond) ? "PASS" : "FAIL", kBusFramesPerSecond, rate);
    return targets.finish();
}

// make bench: CAN figures.
//  1. Bus load at 1 Mbit/s computed from the rover's frame schedule (docs/icd.md
//     §1.2), every frame at its worst-case length with bit stuffing (classic CAN,
//     11-bit id: 47 + 8n bits of frame and interframe space, plus at most
//     floor((34 + 8n - 1) / 4) stuff bits). Target < 40 %.
//  2. Frames per second through the in-memory bus (one sender, one receiver).
//  3. Per-cycle CPU cost of the flight CAN I/O task (CANopen master with six
//     drives, the four devices and the ground link) in lockstep with rse-sim,
//     over 60 s of driving: host CPU time per run, mean and max.
// SocketCAN frames per second are measured inside the vcan VM by
// bench_socketcan (make bench runs it there).
#include <cstdio>
#include <cstring>

#include "sim_stub/lockstep/lockstep_rig.hpp"

#include "fsw/io/can_io_task.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/executive.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "unit_test/bench/bench_targets.hpp"

using namespace rse;

namespace {

double worstCaseBits(int dataBytes) {
    const int stuff = (34 + 8 * dataBytes - 1) / 4;
    return 47.0 + 8.0 * dataBytes + stuff;
}

struct ScheduledFrame {
    const char* what;
    int count;        // frames of this kind per period
    int dataBytes;
    double rateHz;    // periods per second
};

}  // namespace

int main() {
    rse::bench::Targets targets;
    const int drives = static_cast<int>(msg::kWheelCount);
    const int heartbeatNodes = drives + 6;  // + IMU, power, hazard, position fix, grinder, camera
    const ScheduledFrame schedule[] = {
        {"RPDO1 to each drive", drives, 6, 100.0},
        {"SYNC", 1, 0, 100.0},
        {"TPDO1 from each drive", drives, 8, 100.0},
        {"IMU rates", 1, 8, 100.0},
        {"power monitor", 1, 8, 10.0},
        {"hazard reports (4 obstacles in view, 5 Hz)", 4, 8, 5.0},
        {"position fix (2 frames)", 2, 8, 1.0},
        {"instrument status reports (grinder, camera)", 2, 8, 10.0},
        {"heartbeats", heartbeatNodes, 1, 10.0},
    };
    std::printf("== CAN bus load at 1 Mbit/s from the frame schedule (worst-case stuffing)\n");
    std::printf("   %-44s %7s %6s %9s %9s\n", "frames", "count", "bytes", "rate_Hz", "kbit/s");
    double total = 0.0;
    for (const ScheduledFrame& f : schedule) {
        const double bitsPerSecond = f.count * worstCaseBits(f.dataBytes) * f.rateHz;
        total += bitsPerSecond;
        std::printf("   %-44s %7d %6d %9.0f %9.1f\n", f.what, f.count, f.dataBytes, f.rateHz, bitsPerSecond / 1000.0);
    }
    const double load = total / 1.0e6;
    std::printf("   total %.1f kbit/s = %.1f %% of 1 Mbit/s; target < 40 %% -> %s\n", total / 1000.0, 100.0 * load,
                targets.check(load < 0.40) ? "met" : "MISSED");
    std::printf("   (ground ISO-TP traffic comes on top, at the lowest priority but heartbeats)\n");
    {
        // One long ground-link message: a first frame carries 6 bytes, each
        // consecutive frame 7 (hal/can/isotp.hpp), every frame 8 bytes long.
        const int messageBytes = 4000;
        const int frames = 1 + (messageBytes - 6 + 6) / 7;
        const double bits = frames * worstCaseBits(8);
        std::printf("   a %d-byte ISO-TP message: %d frames of %.0f bits = %.1f kbit, %.0f ms of the bus at 1 Mbit/s\n",
                    messageBytes, frames, worstCaseBits(8), bits / 1000.0, bits / 1000.0);
    }

    core::VirtualClock clock;
    hal::MemoryCanBus wire(clock);
    hal::MemoryCanEndpoint* tx = wire.attach("tx");
    hal::MemoryCanEndpoint* rx = wire.attach("rx");
    core::MonotonicClock wall;
    const int frames = 2000000;
    hal::CanFrame f;
    f.id = 0x181;
    f.dlc = 8;
    hal::CanFrame got;
    const core::TimeNs begin = wall.now();
    for (int i = 0; i < frames; ++i) {
        f.data[0] = static_cast<std::uint8_t>(i);
        (void)tx->send(f);
        (void)rx->receive(&got);
    }
    const double seconds = static_cast<double>(wall.now() - begin) / 1e9;
    std::printf("\n== in-memory bus: %d frames sent and received in %.3f s = %.2f M frames/s (%.0f ns per frame)\n",
                frames, seconds, frames / seconds / 1e6, seconds * 1e9 / frames);
    if (rx->stats().rxFrames != static_cast<std::uint32_t>(frames)) {
        return 1;
    }

    static sim::LockstepRig rig("sim_stub/scenarios/straight_10m.toml");
    if (!core::isOk(rig.init())) {
        return 1;
    }
    (void)rig.runUntil([&] { return rig.allDrivesOperational(); }, 2 * core::kNsPerSec);
    rig.commandAllWheels(1.0);
    rig.fsw().executive().resetCounters();
    rig.runFor(60 * core::kNsPerSec);
    const core::Executive& exec = rig.fsw().executive();
    const std::size_t row = exec.findTask("can_io");  // not row 0 (tables): the schedule's order
    if (row == exec.taskCount()) {
        std::fprintf(stderr, "no executive row called can_io\n");
        return 1;
    }
    const core::TaskStats* io = exec.taskStats(row);
    std::printf("\n== CAN I/O task (CANopen master, 6 drives + 4 devices + ground link), lockstep, 60 s driving\n");
    std::printf("   %u cycles: host CPU mean %.2f us, max %.2f us per cycle (budget %u us)\n",
                static_cast<unsigned>(io->runs), static_cast<double>(io->hostMean()) / 1e3,
                static_cast<double>(io->hostMax) / 1e3,
                static_cast<unsigned>(exec.entry(row)->budgetUs));
    std::printf("   frames on the bus in that time: %u (%.0f per cycle)\n",
                static_cast<unsigned>(rig.wire().stats().framesCarried),
                static_cast<double>(rig.wire().stats().framesCarried) / io->runs);
    return targets.finish();
}

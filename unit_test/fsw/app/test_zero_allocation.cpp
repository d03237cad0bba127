// House rule: after initialisation nothing in fsw/ or hal/ touches the heap.
// These tests run the real rse-fsw composition (FswApp, every task in its
// rate-group table) on the virtual clock and count heap allocations.
#include <Eigen/Core>
#include <cstdio>
#include <vector>

#include "fsw/app/fsw_app.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

constexpr int kCycles = 10000;

// A console stream that allocates nothing when written: /dev/null with a
// static buffer (stdio would otherwise allocate one on first write).
std::FILE* quietConsole() {
    static char buffer[8192];
    static std::FILE* stream = nullptr;
    if (stream == nullptr) {
        stream = std::fopen("/dev/null", "w");
        std::setvbuf(stream, buffer, _IOFBF, sizeof buffer);
    }
    return stream;
}

}  // namespace

TEST_GROUP(ZeroAllocation){};

TEST(ZeroAllocation, RealExecutiveWithAllTasksAllocatesNothingAfterInit) {
    static core::VirtualClock clock;
    static hal::MemoryCanBus can(clock);
    static app::FswApp fsw(clock, *can.attach("fsw"));
    CHECK(core::Status::kOk == fsw.useLabKey());  // a lab bench: asked for explicitly
    CHECK(core::Status::kOk == fsw.init(quietConsole()));

    rse::test::AllocationWatch watch;
    fsw.run(nullptr, kCycles);
    const auto allocations = watch.count();

    LONGS_EQUAL(0, allocations);
    // ...and the system really ran: every frame, housekeeping each second, the
    // console consuming it (otherwise "no allocation" would prove nothing).
    LONGS_EQUAL(kCycles, fsw.executive().stats().framesRun);
    LONGS_EQUAL(kCycles / 100, fsw.housekeeping().published());
    LONGS_EQUAL(kCycles / 100, fsw.console().housekeepingSeen());
    CHECK(fsw.console().eventsWritten() > 0);
    LONGS_EQUAL(0, fsw.bus().stats().dropped);

    // Instrument commands (no instrument on this bus: each is checked, refused
    // as offline or invalid, counted, evented and published) allocate nothing either.
    rse::test::AllocationWatch instrumentWatch;
    for (std::uint16_t id = 1; id <= 50; ++id) {
        msg::InstrumentCommandMsg cmd{};
        cmd.instrument = id % 2 == 0 ? msg::Instrument::kGrinder : msg::Instrument::kCamera;
        cmd.action = id % 3 == 0 ? msg::InstrumentAction::kSample : msg::InstrumentAction::kImage;
        cmd.targetId = static_cast<std::uint8_t>(id);
        cmd.commandId = id;
        cmd.maxDurationS = 30.0;
        CHECK(core::Status::kOk == fsw.bus().publish(cmd));
        fsw.run(nullptr, 20);
    }
    LONGS_EQUAL(0, instrumentWatch.count());
    LONGS_EQUAL(50, fsw.canIo().instrument(0).status().commandsNotSent + fsw.canIo().instrument(1).status().commandsNotSent);
}

// The guard itself must be able to fail: these show it sees allocations made by
// a task inside the executive, by operator new, and by dynamic Eigen types.
TEST_GROUP(AllocationGuard){};

TEST(AllocationGuard, CountsAnAllocationMadeByATaskInTheExecutive) {
    class AllocatingTask final : public core::Task {
    public:
        void run(const core::FrameContext&) override {
            std::vector<int> grows;
            grows.push_back(1);
            sum += grows.front();
        }
        int sum = 0;
    } task;
    static core::VirtualClock clock;
    static core::EventLog events(clock);
    static core::Executive exec(clock, events);
    const core::RateGroupEntry table[] = {{"allocating", &task, 1, 0, 1000}};
    CHECK(core::Status::kOk == exec.init(core::ExecutiveConfig{}, table, 1));

    rse::test::AllocationWatch watch;
    exec.run(nullptr, 10);
    const auto allocations = watch.count();
    LONGS_EQUAL(10, allocations);
    LONGS_EQUAL(10, task.sum);
}

TEST(AllocationGuard, CountsDynamicEigenButNotFixedSizeEigen) {
    {
        rse::test::AllocationWatch fixedOnly;  // forbids Eigen heap use: would abort here
        Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
        Eigen::Matrix3d b = a * 2.0 + a.transpose();
        LONGS_EQUAL(0, fixedOnly.count());
        DOUBLES_EQUAL(3.0, b(1, 1), 0.0);
    }
    rse::test::AllocationWatch counting(false);
    Eigen::MatrixXd dynamic = Eigen::MatrixXd::Zero(8, 8);
    const auto allocations = counting.count();
    CHECK(allocations >= 1);
    DOUBLES_EQUAL(0.0, dynamic.sum(), 0.0);
}

// The watchdog task: it feeds the watchdog only while every task is live (the
// health task's fault status fresh, no task stalled). In the real FswApp:
// unit_test/fsw/app/test_watchdog_in_the_app.cpp; the Linux device it feeds:
// unit_test/hal/watchdog/test_watchdog_device.cpp.
#include "fsw/io/io_events.hpp"
#include "fsw/io/watchdog_task.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "hal/watchdog/watchdog.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

struct FakeWatchdog final : hal::Watchdog {
    unsigned feeds = 0;
    core::Status feed() override {
        ++feeds;
        return core::Status::kOk;
    }
};

}  // namespace

TEST_GROUP(WatchdogTask) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    io::WatchdogTask task{bus, events};
    FakeWatchdog dog;
    std::uint64_t frame = 0;
    void setup() override {
        CHECK(core::isOk(task.init()));
        task.attach(&dog);
    }
    // 100 ms per run (the task's 10 Hz); a fault status first when given.
    void step(const msg::FaultStatusMsg* status) {
        if (status != nullptr) {
            (void)bus.publish(*status);
        }
        core::FrameContext f{};
        f.frame = frame++;
        f.actualStart = clock.now();
        task.run(f);
        clock.advance(100 * core::kNsPerMs);
    }
};

TEST(WatchdogTask, FedWhileTheFaultStatusIsFreshAndNoTaskStalled) {
    msg::FaultStatusMsg ok{};
    ok.activeMask = std::uint64_t{1} << msg::fault::kBatteryLow;  // other faults do not matter
    for (int i = 0; i < 10; ++i) {
        step(&ok);
    }
    LONGS_EQUAL(10, dog.feeds);
    msg::FaultStatusMsg stalled = ok;
    stalled.activeMask |= std::uint64_t{1} << (msg::fault::kTaskStalled + 4);
    step(&stalled);
    step(&stalled);
    LONGS_EQUAL(10, dog.feeds);
    CHECK_FALSE(task.feeding());
    LONGS_EQUAL(1, test::drainEventsWithId(events, io::events::kWatchdogWithheld));
    step(&ok);
    LONGS_EQUAL(11, dog.feeds);
    LONGS_EQUAL(1, test::drainEventsWithId(events, io::events::kWatchdogFeeding));
}

TEST(WatchdogTask, AStaleFaultStatusStopsTheFeeding) {
    msg::FaultStatusMsg ok{};
    step(&ok);
    for (int i = 0; i < 20; ++i) {  // 2 s without a status: still fed (fresh means under 2 s old)
        step(nullptr);
    }
    const unsigned fed = dog.feeds;
    LONGS_EQUAL(21, fed);
    step(nullptr);
    step(nullptr);
    LONGS_EQUAL(fed, dog.feeds);
    CHECK(task.withheld() >= 2);
}

TEST(WatchdogTask, NeverFedBeforeTheFirstFaultStatus) {
    step(nullptr);
    LONGS_EQUAL(0, dog.feeds);
}

TEST(WatchdogTask, AFaultStatusThatDoesNotDecodeIsCountedAndVouchesForNothing) {
    const std::uint8_t truncated[5] = {};
    CHECK(core::isOk(bus.publish(msg::ids::kFaultStatus, truncated, sizeof truncated)));
    step(nullptr);
    LONGS_EQUAL(1, task.malformed());
    LONGS_EQUAL(1, test::drainEventsWithId(events, io::events::kBusMessageMalformed));
    CHECK_FALSE(task.feeding());
    LONGS_EQUAL(0, dog.feeds);
}

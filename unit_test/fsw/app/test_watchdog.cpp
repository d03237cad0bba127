// The watchdog: fed only while every task is live (the health task's fault
// status fresh, no task stalled), in the real FswApp and alone; the Linux
// device fed by writes and disarmed by the magic close.
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>

#include "fsw/app/app_events.hpp"
#include "fsw/app/fsw_app.hpp"
#include "fsw/app/watchdog_task.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/watchdog/watchdog_device.hpp"
#include "hal/watchdog/watchdog_events.hpp"
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
    app::WatchdogTask task{bus, events};
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
    LONGS_EQUAL(1, test::drainEventsWithId(events, app::events::kWatchdogWithheld));
    step(&ok);
    LONGS_EQUAL(11, dog.feeds);
    LONGS_EQUAL(1, test::drainEventsWithId(events, app::events::kWatchdogFeeding));
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

TEST_GROUP(WatchdogInTheApp) {
    core::VirtualClock clock;
    hal::MemoryCanBus can{clock};
    app::FswApp fsw{clock, *can.attach("fsw")};
    FakeWatchdog dog;
};

TEST(WatchdogInTheApp, AStalledTaskStopsTheFeedsUntilFaultProtectionRestartsIt) {
    fsw.attachWatchdog(&dog);
    CHECK(core::Status::kOk == fsw.useLabKey());  // a lab bench: asked for explicitly
    CHECK(core::Status::kOk == fsw.init(nullptr));
    fsw.run(nullptr, 300);
    CHECK(dog.feeds >= 29);  // 10 Hz from the first fault status on
    // The console row (index 11) stops: the health task sees it stall, the
    // watchdog is not fed, fault protection runs the row again, feeding resumes.
    CHECK(core::isOk(fsw.executive().setTaskEnabled(11, false)));
    unsigned before = dog.feeds;
    bool stopped = false;
    for (int i = 0; i < 100 && !stopped; ++i) {
        fsw.run(nullptr, 10);
        stopped = !fsw.watchdog().feeding();
        before = stopped ? before : dog.feeds;
    }
    CHECK(stopped);
    fsw.run(nullptr, 300);
    CHECK(fsw.watchdog().feeding());
    CHECK(dog.feeds > before);
    CHECK(fsw.commandHandler().taskRestarts() >= 1);
}

TEST_GROUP(WatchdogDevice){};

TEST(WatchdogDevice, FeedsAreWritesAndAStopIsTheMagicClose) {
    core::VirtualClock clock;
    core::EventLog events(clock);
    char path[] = "/tmp/rse_watchdog_XXXXXX";
    const int fd = mkstemp(path);
    CHECK(fd >= 0);
    close(fd);
    {
        hal::WatchdogDevice dog(events);
        CHECK(core::isOk(dog.open(path, 20)));  // a plain file refuses the timeout ioctl: evented, kept open
        CHECK(core::isOk(dog.feed()));
        CHECK(core::isOk(dog.feed()));
        LONGS_EQUAL(2, dog.feeds());
        dog.disarm();
        CHECK_FALSE(dog.isOpen());
        CHECK(core::Status::kUnavailable == dog.feed());
    }
    std::ifstream in(path, std::ios::binary);
    const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::remove(path);
    LONGS_EQUAL(3, written.size());
    LONGS_EQUAL('V', written[2]);
    LONGS_EQUAL(1, test::drainEventsWithId(events, hal::events::kWatchdogDisarmed));
}

TEST(WatchdogDevice, AMissingDeviceIsRefusedAndEvented) {
    core::VirtualClock clock;
    core::EventLog events(clock);
    hal::WatchdogDevice dog(events);
    CHECK(core::Status::kUnavailable == dog.open("/nonexistent/watchdog", 10));
    CHECK_FALSE(dog.isOpen());
    LONGS_EQUAL(1, test::drainEventsWithId(events, hal::events::kWatchdogOpenFailed));
}

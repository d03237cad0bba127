// The watchdog in the real FswApp: a stalled task stops the feeds until fault
// protection restarts its row (through the executive's commands). The task
// alone: unit_test/fsw/io/test_watchdog.cpp.
#include "fsw/app/fsw_app.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/watchdog/watchdog.hpp"

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
    CHECK(fsw.executiveCommands().taskRestarts() >= 1);
}

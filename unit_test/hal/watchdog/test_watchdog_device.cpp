// The Linux watchdog device (hal/watchdog/watchdog_device.hpp): fed by writes,
// disarmed by the magic close ('V', then close); a device that cannot be
// opened, or a feed that cannot be written, refused, counted and evented. A
// plain file stands for the device (its ioctls fail: the timeout is unknown).
// Who feeds it: unit_test/fsw/io/test_watchdog.cpp (WatchdogTask, with a fake).
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "hal/watchdog/watchdog_device.hpp"
#include "hal/watchdog/watchdog_events.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

TEST_GROUP(WatchdogDevice) {
    core::VirtualClock clock;
    core::EventLog events{clock};
};

TEST(WatchdogDevice, FeedsAreWritesAndAStopIsTheMagicClose) {
    char path[] = "/tmp/rse_watchdog_XXXXXX";
    const int fd = mkstemp(path);
    CHECK(fd >= 0);
    close(fd);
    {
        hal::WatchdogDevice dog(events);
        CHECK(core::isOk(dog.open(path, 20)));  // a plain file refuses the timeout ioctl: evented, kept open
        CHECK_TRUE(dog.isOpen());
        LONGS_EQUAL(-1, dog.timeoutS());  // nor does it say its own
        CHECK(core::Status::kInvalidArgument == dog.open(path, 20));  // already open
        CHECK(core::isOk(dog.feed()));
        CHECK(core::isOk(dog.feed()));
        LONGS_EQUAL(2, dog.feeds());
        LONGS_EQUAL(0, dog.feedFailures());
        dog.disarm();
        CHECK_FALSE(dog.isOpen());
        CHECK(core::Status::kUnavailable == dog.feed());
        dog.disarm();  // not open: nothing written, nothing evented
    }  // the destructor disarms only an open device
    std::ifstream in(path, std::ios::binary);
    const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::remove(path);
    // Two feeds ('\0' each), then the magic 'V'.
    LONGS_EQUAL(3, written.size());
    LONGS_EQUAL('\0', written[0]);
    LONGS_EQUAL('\0', written[1]);
    LONGS_EQUAL('V', written[2]);
    LONGS_EQUAL(1, test::drainEventsWithId(events, hal::events::kWatchdogDisarmed));
}

TEST(WatchdogDevice, OpeningArmsAndSaysSoAndARefusedTimeoutIsEvented) {
    char path[] = "/tmp/rse_watchdog_XXXXXX";
    const int fd = mkstemp(path);
    CHECK(fd >= 0);
    close(fd);
    hal::WatchdogDevice dog(events);
    CHECK(core::isOk(dog.open(path, 20)));
    std::remove(path);
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(hal::events::kWatchdogOpenFailed, e.id);  // the 20 s refused: the device's own applies
    CHECK(core::Severity::kWarning == e.severity);
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(hal::events::kWatchdogOpened, e.id);
    CHECK(core::Severity::kInfo == e.severity);
    CHECK_TEXT(std::string(e.text).find("armed, timeout -1 s") != std::string::npos, e.text);
}

TEST(WatchdogDevice, AMissingDeviceIsRefusedAndEvented) {
    hal::WatchdogDevice dog(events);
    CHECK(core::Status::kUnavailable == dog.open("/nonexistent/watchdog", 10));
    CHECK_FALSE(dog.isOpen());
    CHECK(dog.lastErrno() != 0);
    LONGS_EQUAL(1, test::drainEventsWithId(events, hal::events::kWatchdogOpenFailed));
    CHECK(core::Status::kInvalidArgument == dog.open(nullptr, 10));
}

// /dev/full opens for writing and refuses every write (ENOSPC): each feed is
// refused and counted, and evented on the 1st, 2nd, 4th ... failure.
TEST(WatchdogDevice, AFeedThatCannotBeWrittenIsRefusedCountedAndEventedThrottled) {
    hal::WatchdogDevice dog(events);
    CHECK(core::isOk(dog.open("/dev/full", 0)));  // 0: no timeout asked for
    (void)test::drainEventsWithId(events, hal::events::kWatchdogOpened);
    for (int i = 0; i < 5; ++i) {
        CHECK(core::Status::kUnavailable == dog.feed());
    }
    LONGS_EQUAL(0, dog.feeds());
    LONGS_EQUAL(5, dog.feedFailures());
    LONGS_EQUAL(ENOSPC, dog.lastErrno());
    LONGS_EQUAL(3, test::drainEventsWithId(events, hal::events::kWatchdogFeedFailed));  // 1st, 2nd, 4th
}

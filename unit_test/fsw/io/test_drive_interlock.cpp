#include "fsw/io/drive_interlock.hpp"
#include "fsw/io/io_events.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

msg::DriveStatusMsg healthy() {
    msg::DriveStatusMsg s{};
    for (msg::WheelStatus& w : s.wheels) {
        w.health = msg::DriveHealth::kOperational;
    }
    return s;
}

}  // namespace

TEST_GROUP(DriveInterlock) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    io::DriveInterlock interlock{events};
    const double command[msg::kWheelCount] = {1.0, 2.0, 3.0, -1.0, -2.0, -3.0};
    double out[msg::kWheelCount] = {};
};

TEST(DriveInterlock, PassesTheCommandWhileEveryDriveIsHealthy) {
    interlock.apply(healthy(), command, out);
    CHECK_FALSE(interlock.tripped());
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        DOUBLES_EQUAL(command[w], out[w], 0.0);
    }
    LONGS_EQUAL(0, test::drainEventsWithId(events, io::events::kInterlockTripped));
}

TEST(DriveInterlock, AnUnhealthyDriveSendsEveryWheelToZeroAndLatches) {
    for (const msg::DriveHealth bad : {msg::DriveHealth::kFaulted, msg::DriveHealth::kFailed, msg::DriveHealth::kLost}) {
        io::DriveInterlock fresh{events};
        msg::DriveStatusMsg s = healthy();
        s.wheels[4].health = bad;
        fresh.apply(s, command, out);
        CHECK(fresh.tripped());
        for (double v : out) {
            DOUBLES_EQUAL(0.0, v, 0.0);
        }
        // Latched: the drive healthy again changes nothing until a reset.
        fresh.apply(healthy(), command, out);
        CHECK(fresh.tripped());
        DOUBLES_EQUAL(0.0, out[0], 0.0);
        LONGS_EQUAL(1, fresh.trips());
    }
    LONGS_EQUAL(3, test::drainEventsWithId(events, io::events::kInterlockTripped));
}

TEST(DriveInterlock, ResetIsRefusedWhileADriveIsStillUnhealthy) {
    msg::DriveStatusMsg s = healthy();
    s.wheels[1].health = msg::DriveHealth::kFaulted;
    interlock.apply(s, command, out);
    CHECK_FALSE(interlock.resetIfHealthy(s));
    CHECK(interlock.tripped());
    LONGS_EQUAL(1, test::drainEventsWithId(events, io::events::kInterlockResetRefused));
}

TEST(DriveInterlock, ResetReleasesTheHoldOnceEveryDriveIsHealthy) {
    msg::DriveStatusMsg s = healthy();
    s.wheels[0].health = msg::DriveHealth::kLost;
    interlock.apply(s, command, out);
    CHECK(interlock.resetIfHealthy(healthy()));
    CHECK_FALSE(interlock.tripped());
    LONGS_EQUAL(1, test::drainEventsWithId(events, io::events::kInterlockReset));
    interlock.apply(healthy(), command, out);
    DOUBLES_EQUAL(command[2], out[2], 0.0);
}

// The deliberative layer's view of the drives (drive_health.hpp): failed and
// unknown drives, how long a declaration must last, the mean power factor,
// and when the interlock means mobility is lost.
#include <cstring>

#include "fsw/deliberative/drive_health.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::DriveHealthView;
using msg::DriveHealth;
using msg::DriveMode;

namespace {

constexpr core::TimeNs kSecond = core::kNsPerSec;

// Every drive nominal at factor 1 but `wheel`, declared `mode` at `factor`.
msg::DriveModesMsg modes(std::size_t wheel = msg::kWheelCount, DriveMode mode = DriveMode::kNominal,
                         float factor = 1.0F) {
    msg::DriveModesMsg m{};
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        m.drives[w].declared = w == wheel ? mode : DriveMode::kNominal;
        m.drives[w].powerFactor = w == wheel ? factor : 1.0F;
    }
    return m;
}

// The interlock latched (or not), wheel `bad` in `health`, the others operational.
msg::DriveStatusMsg status(bool interlock, std::size_t bad = msg::kWheelCount,
                           DriveHealth health = DriveHealth::kFailed) {
    msg::DriveStatusMsg s{};
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        s.wheels[w].health = w == bad ? health : DriveHealth::kOperational;
    }
    s.interlockTripped = interlock ? 1 : 0;
    return s;
}

}  // namespace

TEST_GROUP(DriveHealthView){};

TEST(DriveHealthView, BeforeAnyDriveModesNoDriveIsFailedAndTheFactorIsOne) {
    DriveHealthView view;
    LONGS_EQUAL(0, view.failedDrives(true));
    DOUBLES_EQUAL(1.0, view.meanPowerFactor(3.0), 0.0);
    CHECK_FALSE(view.interlockTripped());
    CHECK_FALSE(view.mobilityLost());
}

TEST(DriveHealthView, FailedAndUnknownDrivesAreMaskedByWheelUnknownOnlyWhenAsked) {
    DriveHealthView view;
    msg::DriveModesMsg m = modes(1, DriveMode::kFailed);
    m.drives[4].declared = DriveMode::kUnknown;
    m.drives[2].declared = DriveMode::kDegraded;
    view.takeDriveModes(m, 5 * kSecond);
    LONGS_EQUAL(0x02, view.failedDrives(false));
    LONGS_EQUAL(0x12, view.failedDrives(true));
}

TEST(DriveHealthView, TheMeanPowerFactorTakesAFailedDriveAtTheTablesFactor) {
    DriveHealthView view;
    view.takeDriveModes(modes(0, DriveMode::kFailed, 1.0F), kSecond);
    DOUBLES_EQUAL((5.0 + 3.0) / 6.0, view.meanPowerFactor(3.0), 1e-12);
    view.takeDriveModes(modes(0, DriveMode::kDegraded, 1.6F), kSecond);
    DOUBLES_EQUAL((5.0 + 1.6) / 6.0, view.meanPowerFactor(3.0), 1e-6);
}

// A resettable fault reads as failed for an update or two: the declaration
// must last confirmS without a break before it is "confirmed".
TEST(DriveHealthView, ADeclarationIsConfirmedOnlyOnceItHasLastedTheConfirmationTime) {
    DriveHealthView view;
    view.takeDriveModes(modes(3, DriveMode::kFailed), 10 * kSecond);
    LONGS_EQUAL(0, view.confirmedFailedDrives(11 * kSecond, 2.0));
    view.takeDriveModes(modes(3, DriveMode::kFailed), 11 * kSecond);  // still: since 10 s
    LONGS_EQUAL(0x08, view.confirmedFailedDrives(12 * kSecond, 2.0));
    // A break restarts the clock.
    view.takeDriveModes(modes(), 12 * kSecond);
    LONGS_EQUAL(0, view.confirmedFailedDrives(20 * kSecond, 2.0));
    view.takeDriveModes(modes(3, DriveMode::kUnknown), 13 * kSecond);
    LONGS_EQUAL(0, view.confirmedFailedDrives(14 * kSecond, 2.0));
    LONGS_EQUAL(0x08, view.confirmedFailedDrives(15 * kSecond, 2.0));
    // A confirmation time of 0 confirms at once; a declaration at time 0 is
    // dated 1 ns (0 stands for "not declared").
    DriveHealthView atZero;
    atZero.takeDriveModes(modes(0, DriveMode::kFailed), 0);
    LONGS_EQUAL(0x01, atZero.confirmedFailedDrives(1, 0.0));
}

TEST(DriveHealthView, OnlyALatchedInterlockCanLoseMobility) {
    DriveHealthView view;
    view.takeDriveStatus(status(false, 2));
    CHECK_FALSE(view.mobilityLost());
    view.takeDriveStatus(status(true));
    CHECK_TRUE(view.interlockTripped());
    CHECK_TRUE(view.mobilityLost());  // latched with no drive declared failed
}

TEST(DriveHealthView, AnInterlockLatchedOnlyOnDrivesDeclaredFailedIsNotMobilityLost) {
    DriveHealthView view;
    view.takeDriveModes(modes(2, DriveMode::kFailed), kSecond);
    view.takeDriveStatus(status(true, 2, DriveHealth::kFaulted));
    CHECK_FALSE(view.mobilityLost());
    // Another unhealthy drive nobody declared failed: lost.
    msg::DriveStatusMsg two = status(true, 2, DriveHealth::kFaulted);
    two.wheels[5].health = DriveHealth::kLost;
    view.takeDriveStatus(two);
    CHECK_TRUE(view.mobilityLost());
}

// Nothing says an unknown drive's wheel has stopped.
TEST(DriveHealthView, ADriveOnlyUnknownTrippingTheInterlockIsMobilityLost) {
    DriveHealthView view;
    view.takeDriveModes(modes(2, DriveMode::kUnknown), kSecond);
    view.takeDriveStatus(status(true, 2, DriveHealth::kFailed));
    CHECK_TRUE(view.mobilityLost());
}

TEST(DriveHealthView, WheelNamesListTheMaskedWheelsWithinTheBuffer) {
    char names[32];
    deliberative::wheelNames(0x00, names, sizeof names);
    STRCMP_EQUAL("", names);
    deliberative::wheelNames(0x01, names, sizeof names);
    STRCMP_EQUAL(msg::wheelName(0), names);
    deliberative::wheelNames(0x21, names, sizeof names);
    char expected[32];
    std::strcpy(expected, msg::wheelName(0));
    std::strcat(expected, " ");
    std::strcat(expected, msg::wheelName(5));
    STRCMP_EQUAL(expected, names);
    char tiny[6];
    deliberative::wheelNames(0x3F, tiny, sizeof tiny);
    CHECK(std::strlen(tiny) < sizeof tiny);
}

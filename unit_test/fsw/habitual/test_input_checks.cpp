// What the habitual task takes from the bus (fsw/habitual/input_checks.hpp):
// the checks a message passes before it counts, and why a leg is refused (the
// first failed check, in a fixed order).
#include <cmath>
#include <limits>

#include "fsw/habitual/input_checks.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "unit_test/fsw/habitual/habitual_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using habitual::legRefusal;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

msg::LegCommandMsg goodLeg() {
    msg::LegCommandMsg l{};
    l.legId = 2;
    l.goalXM = 10.0;
    l.goalYM = 0.0;
    l.maxPathLengthM = 20.0;
    l.maxEnergyJ = 5000.0;
    l.maxPowerW = 0.0;
    l.arriveWithinM = 0.0;
    return l;
}

}  // namespace

TEST_GROUP(InputChecks) {
    tables::CoarseMapTable coarse = test::defaultTable<tables::CoarseMapTable>();
};

TEST(InputChecks, APoseMustBeFinite) {
    msg::PoseEstimateMsg p{};
    CHECK_TRUE(habitual::poseFinite(p));  // not initialised is still a pose
    p.yawRateRadS = kNan;
    CHECK_FALSE(habitual::poseFinite(p));
    p = msg::PoseEstimateMsg{};
    p.xM = INFINITY;
    CHECK_FALSE(habitual::poseFinite(p));
}

TEST(InputChecks, ModeHazardsFollowerAndDriveModesMustBeKnownAndInRange) {
    msg::ModeMsg mode{};
    mode.mode = msg::mode::kCount - 1;
    CHECK_TRUE(habitual::modeUsable(mode));
    mode.mode = msg::mode::kCount;
    CHECK_FALSE(habitual::modeUsable(mode));

    msg::HazardMsg hazards{};
    hazards.count = msg::kMaxHazardsInMsg;
    CHECK_TRUE(habitual::hazardsUsable(hazards));
    hazards.count = msg::kMaxHazardsInMsg + 1;
    CHECK_FALSE(habitual::hazardsUsable(hazards));

    msg::FollowerStatusMsg status{};
    status.state = msg::FollowerState::kBackingOff;
    status.reason = msg::FollowReason::kContact;
    CHECK_TRUE(habitual::followerStatusUsable(status));
    status.reason = static_cast<msg::FollowReason>(static_cast<std::uint8_t>(msg::FollowReason::kContact) + 1);
    CHECK_FALSE(habitual::followerStatusUsable(status));
    status.reason = msg::FollowReason::kNone;
    status.state = static_cast<msg::FollowerState>(static_cast<std::uint8_t>(msg::FollowerState::kBackingOff) + 1);
    CHECK_FALSE(habitual::followerStatusUsable(status));

    msg::ContactMsg contact{};
    contact.directionSign = 1.0;
    CHECK_TRUE(habitual::contactUsable(contact));
    contact.directionSign = 0.5;  // neither way
    CHECK_FALSE(habitual::contactUsable(contact));
    contact.directionSign = -1.0;
    contact.xM = std::nan("");
    CHECK_FALSE(habitual::contactUsable(contact));
    contact.xM = 2.0e6;
    CHECK_FALSE(habitual::contactUsable(contact));

    msg::DriveModesMsg modes{};
    for (msg::DriveModeBelief& d : modes.drives) {
        d.powerFactor = 1.0F;
    }
    CHECK_TRUE(habitual::driveModesUsable(modes));
    modes.drives[3].powerFactor = habitual::kLargestPowerFactor;
    CHECK_TRUE(habitual::driveModesUsable(modes));
    modes.drives[3].powerFactor = habitual::kLargestPowerFactor * 1.01F;
    CHECK_FALSE(habitual::driveModesUsable(modes));
    modes.drives[3].powerFactor = -0.1F;
    CHECK_FALSE(habitual::driveModesUsable(modes));
    modes.drives[3].powerFactor = std::numeric_limits<float>::quiet_NaN();
    CHECK_FALSE(habitual::driveModesUsable(modes));
    modes.drives[3].powerFactor = 1.0F;
    modes.drives[0].declared = static_cast<msg::DriveMode>(msg::kDriveModeCount);
    CHECK_FALSE(habitual::driveModesUsable(modes));
}

TEST(InputChecks, AGoodLegIsTaken) {
    CHECK(legRefusal(goodLeg(), true, 1, coarse) == nullptr);
    msg::LegCommandMsg region = goodLeg();
    region.arriveWithinM = static_cast<double>(msg::kMaxGoalRadiusM);
    region.maxPowerW = 300.0;
    CHECK(legRefusal(region, true, 1, coarse) == nullptr);
}

TEST(InputChecks, ALegIsRefusedForTheFirstCheckItFails) {
    STRCMP_EQUAL("not in AUTONOMOUS mode", legRefusal(goodLeg(), false, 1, coarse));
    STRCMP_EQUAL("leg id not new", legRefusal(goodLeg(), true, 2, coarse));
    msg::LegCommandMsg l = goodLeg();
    l.goalYM = kNan;
    l.maxEnergyJ = -1.0;
    STRCMP_EQUAL("goal not finite", legRefusal(l, true, 1, coarse));
    l = goodLeg();
    l.goalXM = 31.0;  // the site ends at x 30
    STRCMP_EQUAL("goal off the coarse map", legRefusal(l, true, 1, coarse));
    l = goodLeg();
    l.maxPathLengthM = 0.0;
    STRCMP_EQUAL("path length bound not positive and finite", legRefusal(l, true, 1, coarse));
    l = goodLeg();
    l.maxEnergyJ = INFINITY;
    STRCMP_EQUAL("energy bound not positive and finite", legRefusal(l, true, 1, coarse));
    l = goodLeg();
    l.maxPowerW = -1.0;
    STRCMP_EQUAL("power bound negative or not finite", legRefusal(l, true, 1, coarse));
    l = goodLeg();
    l.arriveWithinM = static_cast<double>(msg::kMaxGoalRadiusM) + 0.1;
    STRCMP_EQUAL("arrival radius negative, too large or not finite", legRefusal(l, true, 1, coarse));
    l.arriveWithinM = kNan;
    STRCMP_EQUAL("arrival radius negative, too large or not finite", legRefusal(l, true, 1, coarse));
}

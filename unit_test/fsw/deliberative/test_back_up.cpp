// The back-up manoeuvre (back_up.hpp): the driven track, the target along it
// clear of seen hazards, the goal's limit, and the track cut back when reached.
#include <cmath>

#include "fsw/core/clock.hpp"
#include "fsw/deliberative/back_up.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "unit_test/fsw/deliberative/event_record.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::BackUpManoeuvre;
using deliberative::kTrackPoints;
using deliberative::kTrackStepM;
using deliberative::LegEndClearance;
namespace ev = rse::deliberative::events;

namespace {

msg::PoseEstimateMsg poseAt(double x, double y) {
    msg::PoseEstimateMsg p{};
    p.xM = x;
    p.yM = y;
    p.initialised = 1;
    return p;
}

tables::CoarseMapTable openSite() {
    tables::CoarseMapTable map{};
    map.x_min_m = -50.0F;
    map.x_max_m = 50.0F;
    map.y_min_m = -50.0F;
    map.y_max_m = 50.0F;
    return map;
}

}  // namespace

TEST_GROUP(BackUpManoeuvre) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    test::EventRecord seen{events};
    BackUpManoeuvre backUp{events};
    tables::CoarseMapTable map = openSite();
    msg::KnownHazardsMsg hazards{};
    LegEndClearance clear{map, 0.6, hazards};

    // Drives from (0, 0) along +x to (toX, 0), recorded every 0.1 m.
    void driveTo(double toX) {
        for (int i = 0; i * 0.1 <= toX + 1e-9; ++i) {
            backUp.record(poseAt(i * 0.1, 0.0), true);
        }
    }
};

TEST(BackUpManoeuvre, TheTrackKeepsAPointEveryStepOfTheLastPoints) {
    backUp.record(poseAt(0.0, 0.0), false);  // no pose yet
    LONGS_EQUAL(0, backUp.trackCount());
    msg::PoseEstimateMsg uninitialised = poseAt(0.0, 0.0);
    uninitialised.initialised = 0;
    backUp.record(uninitialised, true);
    backUp.record(poseAt(NAN, 0.0), true);
    LONGS_EQUAL(0, backUp.trackCount());
    driveTo(2.0);
    // 0, 0.3, 0.6, ... : the first point a step or more from the last.
    CHECK(backUp.trackCount() >= 6 && backUp.trackCount() <= 9);
    driveTo(40.0);
    LONGS_EQUAL(kTrackPoints, backUp.trackCount());
}

TEST(BackUpManoeuvre, TheTargetIsTheDistanceBackAlongTheTrack) {
    driveTo(10.0);
    msg::PlanLeg target{};
    std::size_t keep = 0;
    CHECK_TRUE(backUp.target(poseAt(10.0, 0.0), 2.0, clear, &target, &keep));
    DOUBLES_EQUAL(8.0, target.xM, 1e-9);
    DOUBLES_EQUAL(0.0, target.yM, 1e-9);
    CHECK(keep < backUp.trackCount());
    // No track: no target.
    BackUpManoeuvre fresh(events);
    CHECK_FALSE(fresh.target(poseAt(10.0, 0.0), 2.0, clear, &target, &keep));
}

TEST(BackUpManoeuvre, ATargetInsideASeenHazardMovesOnBackInStepsUpToTwiceTheDistance) {
    driveTo(10.0);
    hazards.count = 1;
    hazards.hazards[0].xM = 8.0F;
    hazards.hazards[0].yM = 0.0F;
    hazards.hazards[0].radiusM = 0.3F;
    hazards.hazards[0].obstacleId = 1;
    msg::PlanLeg target{};
    std::size_t keep = 0;
    CHECK_TRUE(backUp.target(poseAt(10.0, 0.0), 2.0, clear, &target, &keep));
    const double reach = 0.3 + 0.6 + deliberative::kLegEndMarginM;
    CHECK(target.xM <= 8.0 - reach);
    CHECK(target.xM > 8.0 - reach - kTrackStepM - 1e-9);
    // A hazard covering everything within twice the distance: none.
    hazards.hazards[0].radiusM = 3.0F;
    hazards.hazards[0].xM = 7.0F;
    CHECK_FALSE(backUp.target(poseAt(10.0, 0.0), 2.0, clear, &target, &keep));
}

TEST(BackUpManoeuvre, StartingCountsAgainstTheGoalsLimitAndReachingCutsTheTrack) {
    driveTo(10.0);
    const std::size_t before = backUp.trackCount();
    CHECK_TRUE(backUp.start(poseAt(10.0, 0.0), 2.0, 2, 3, clear));
    CHECK_TRUE(backUp.active());
    LONGS_EQUAL(1, backUp.goalBackUps());
    LONGS_EQUAL(1, backUp.backUps());
    DOUBLES_EQUAL(8.0, backUp.leg()->xM, 1e-9);
    LONGS_EQUAL(1, seen.count(ev::kBackingUp));
    CHECK_TRUE(seen.textHas(ev::kBackingUp, "no path after 3 replans: backing up 2.0 m"));
    CHECK_TRUE(seen.textHas(ev::kBackingUp, "1 of 2"));
    // Not recorded while backing up.
    backUp.record(poseAt(9.0, 0.0), true);
    LONGS_EQUAL(before, backUp.trackCount());

    backUp.reached(poseAt(8.0, 0.0), true, 2, 4);
    CHECK_FALSE(backUp.active());
    CHECK(backUp.trackCount() < before);
    LONGS_EQUAL(1, seen.count(ev::kBackedUp));
    CHECK_TRUE(seen.textHas(ev::kBackedUp, "(1 of 2): replanning goal 4"));
    // The next back-up goes on back from there.
    msg::PlanLeg target{};
    std::size_t keep = 0;
    CHECK_TRUE(backUp.target(poseAt(8.0, 0.0), 2.0, clear, &target, &keep));
    DOUBLES_EQUAL(6.0, target.xM, 0.3);

    CHECK_TRUE(backUp.start(poseAt(8.0, 0.0), 2.0, 2, 3, clear));
    backUp.cancel();
    CHECK_FALSE(backUp.active());
    CHECK_FALSE(backUp.start(poseAt(8.0, 0.0), 2.0, 2, 3, clear));  // the goal's limit
    backUp.nextGoal();
    CHECK_TRUE(backUp.start(poseAt(8.0, 0.0), 2.0, 2, 3, clear));
    LONGS_EQUAL(3, backUp.backUps());
}

TEST(BackUpManoeuvre, NoBackUpWithADistanceOfZeroOrALimitOfZero) {
    driveTo(10.0);
    CHECK_FALSE(backUp.start(poseAt(10.0, 0.0), 0.0, 3, 0, clear));
    CHECK_FALSE(backUp.start(poseAt(10.0, 0.0), 2.0, 0, 0, clear));
    CHECK_FALSE(backUp.active());
    LONGS_EQUAL(0, seen.count(ev::kBackingUp));
}

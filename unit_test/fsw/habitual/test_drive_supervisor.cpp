// Supervision of the trajectory being driven (fsw/habitual/drive_supervisor.hpp):
// odometry in steps that filter pose jitter, the remaining path from the
// nearest point (never back), a remembered hazard on it, new power factors
// against the leg's bounds, and the follower's news. Energy with e_m = 60 J/m,
// e_r = 40 J/rad, margin 20 %.
#include <cmath>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/habitual/drive_supervisor.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/rover_model/power_model.hpp"
#include "unit_test/fsw/habitual/habitual_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using habitual::DriveSupervisor;
using habitual::FactorVerdict;
using habitual::FollowerVerdict;
namespace ev = habitual::events;

namespace {

msg::PoseEstimateMsg pose(double x, double y, double heading = 0.0) {
    msg::PoseEstimateMsg p{};
    p.xM = x;
    p.yM = y;
    p.headingRad = heading;
    p.initialised = 1;
    return p;
}

msg::TrajectoryMsg trajectory(std::uint32_t id, std::initializer_list<Point2> points) {
    msg::TrajectoryMsg t{};
    t.trajectoryId = id;
    for (const Point2& p : points) {
        t.points[t.count++] = msg::TrajectoryPoint{p.x, p.y};
    }
    return t;
}

msg::FollowerStatusMsg follower(std::uint32_t id, msg::FollowerState state,
                                msg::FollowReason reason = msg::FollowReason::kNone) {
    msg::FollowerStatusMsg s{};
    s.trajectoryId = id;
    s.state = state;
    s.reason = reason;
    return s;
}

}  // namespace

TEST_GROUP(DriveSupervisor) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    test::EventReader seen{events};
    tables::HabitualTable table = test::defaultTable<tables::HabitualTable>();
    DriveSupervisor supervisor{events, table};

    void setup() override {
        table.drive_energy_j_per_m = 60.0F;
        table.turn_energy_j_per_rad = 40.0F;
        table.power_margin_frac = 0.2F;
        table.distance_margin_frac = 0.1F;
        supervisor.beginLeg();
    }
};

TEST(DriveSupervisor, OdometryCountsStepsOfFiveCentimetresAndTurnsOfFiftyMilliradians) {
    supervisor.updateOdometry(pose(1.0, 1.0), 1.0);  // the anchor: nothing driven
    DOUBLES_EQUAL(0.0, supervisor.drivenLengthM(), 0.0);
    supervisor.updateOdometry(pose(1.03, 1.0), 1.0);  // jitter below the step
    DOUBLES_EQUAL(0.0, supervisor.drivenLengthM(), 0.0);
    supervisor.updateOdometry(pose(1.06, 1.0), 1.0);  // 6 cm from the anchor
    DOUBLES_EQUAL(0.06, supervisor.drivenLengthM(), 1e-9);
    DOUBLES_EQUAL(0.06 * 60.0, supervisor.drivenEnergyJ(), 1e-4);
    supervisor.updateOdometry(pose(1.06, 1.0, 0.1), 2.0);  // a turn in place, at factor 2
    DOUBLES_EQUAL(0.06, supervisor.drivenLengthM(), 1e-9);
    DOUBLES_EQUAL(0.06 * 60.0 + 2.0 * 0.1 * 40.0, supervisor.drivenEnergyJ(), 1e-4);
    msg::PoseEstimateMsg lost = pose(9.0, 9.0);
    lost.initialised = 0;
    supervisor.updateOdometry(lost, 1.0);  // an uninitialised pose is no motion
    DOUBLES_EQUAL(0.06, supervisor.drivenLengthM(), 1e-9);
    supervisor.beginLeg();
    DOUBLES_EQUAL(0.0, supervisor.drivenLengthM(), 0.0);
    DOUBLES_EQUAL(0.0, supervisor.drivenEnergyJ(), 0.0);
    supervisor.updateOdometry(pose(5.0, 5.0), 1.0);  // anchored afresh: the jump is not driven
    DOUBLES_EQUAL(0.0, supervisor.drivenLengthM(), 0.0);
}

TEST(DriveSupervisor, TheRemainingPathStartsAtTheNearestPointAndNeverGoesBack) {
    const msg::TrajectoryMsg t = trajectory(1, {{0.0, 0.0}, {10.0, 0.0}, {10.0, 10.0}});
    supervisor.followPlan(1.0);
    Point2 out[msg::kMaxTrajectoryPoints];
    std::size_t n = supervisor.remainingPath(t, Point2{5.0, 0.2}, out);
    LONGS_EQUAL(3, n);
    DOUBLES_EQUAL(5.0, out[0].x, 1e-9);
    DOUBLES_EQUAL(0.0, out[0].y, 1e-9);
    DOUBLES_EQUAL(10.0, out[2].y, 0.0);
    n = supervisor.remainingPath(t, Point2{9.8, 5.0}, out);  // on the second segment
    LONGS_EQUAL(2, n);
    DOUBLES_EQUAL(10.0, out[0].x, 1e-9);
    DOUBLES_EQUAL(5.0, out[0].y, 1e-9);
    n = supervisor.remainingPath(t, Point2{5.0, 0.0}, out);  // back near the first: still the second
    LONGS_EQUAL(2, n);
    DOUBLES_EQUAL(0.0, out[0].y, 1e-9);
    const msg::TrajectoryMsg stop = trajectory(2, {});
    LONGS_EQUAL(0, supervisor.remainingPath(stop, Point2{0.0, 0.0}, out));
}

TEST(DriveSupervisor, ARememberedHazardOnTheRemainingPathBlocksItAndIsNamed) {
    const tables::CoarseMapTable coarse = test::defaultTable<tables::CoarseMapTable>();
    habitual::HazardMemory memory{events, coarse};
    msg::HazardMsg hazards{};
    hazards.count = 1;
    hazards.sightings[0] = test::sighting(3, 2.6, 0.0, 0.4);  // disc centre (15, 0) from (12, 0)
    memory.remember(hazards, Point2{12.0, 0.0}, 0.0);
    msg::LegCommandMsg leg{};
    memory.refreshCheckMap(0.6, leg);
    seen.take();
    const msg::TrajectoryMsg t = trajectory(1, {{10.0, 0.0}, {20.0, 0.0}});
    CHECK_TRUE(supervisor.pathBlocked(t, Point2{11.0, 0.0}, memory, 7));
    LONGS_EQUAL(1, supervisor.counters().pathBlocked);
    seen.take();
    CHECK_TRUE(seen.says(ev::kPathBlocked, "habitual: leg 7: hazard 3 at (15.00, 0.00) r 0.89 m on the path: stop, replan"));
    cmdtlm::event_data::PATH_BLOCKED blocked;  // what the ground reads
    CHECK_TRUE(seen.data(ev::kPathBlocked, &blocked));
    DOUBLES_EQUAL(7.0, blocked.leg_id, 0.0);
    DOUBLES_EQUAL(3.0, blocked.hazard, 0.0);
    DOUBLES_EQUAL(15.0, blocked.x, 1e-9);
    DOUBLES_EQUAL(0.0, blocked.y, 1e-9);
    CHECK(blocked.radius > 0.88 && blocked.radius < 0.90);
    // Past it the rest is free.
    CHECK_FALSE(supervisor.pathBlocked(t, Point2{17.0, 0.0}, memory, 7));
    LONGS_EQUAL(1, supervisor.counters().pathBlocked);
}

TEST(DriveSupervisor, NewPowerFactorsReEvaluateTheRemainingPath) {
    habitual::CandidateEvaluator evaluator{table};
    msg::LegCommandMsg leg{};
    leg.legId = 5;
    leg.maxPathLengthM = 30.0;
    leg.maxEnergyJ = 1000.0;  // 800 J allowed: 10 m needs 600 J at factor 1
    evaluator.beginLeg(leg);
    const msg::TrajectoryMsg t = trajectory(1, {{0.0, 0.0}, {10.0, 0.0}});
    supervisor.followPlan(1.0);
    habitual::FactorCheck check = supervisor.checkPowerFactors(t, pose(0.0, 0.0), evaluator, {0.0, 0.0, 1.0}, 5);
    CHECK(FactorVerdict::kUnchanged == check.verdict);  // the factor the plan was predicted with
    check = supervisor.checkPowerFactors(t, pose(0.0, 0.0), evaluator, {0.0, 0.0, 1.2}, 5);
    CHECK(FactorVerdict::kHolds == check.verdict);
    DOUBLES_EQUAL(720.0, check.evaluation.energyJ, 1e-6);
    check = supervisor.checkPowerFactors(t, pose(2.0, 0.0), evaluator, {2.0, 150.0, 1.5}, 5);
    CHECK(FactorVerdict::kEnergy == check.verdict);  // 8 m left at 90 J/m: 720 J > (1000 - 150) * 0.8 = 680 J
    DOUBLES_EQUAL(720.0, check.evaluation.energyJ, 1e-6);
    CHECK(msg::LegConstraint::kEnergy == check.asEnergy.violated);
    DOUBLES_EQUAL(40.0, check.asEnergy.excess, 1e-4);
    LONGS_EQUAL(2, supervisor.remainingCount());
    DOUBLES_EQUAL(2.0, supervisor.remaining()[0].x, 1e-9);
    LONGS_EQUAL(1, supervisor.counters().energyViolations);
    seen.take();
    CHECK_TRUE(seen.says(ev::kEnergyViolated, "habitual: leg 5 power factor 1.50: 720 J left > allowed 680 J: repair"));
}

TEST(DriveSupervisor, NewPowerFactorsAboveThePowerBoundFailUp) {
    habitual::CandidateEvaluator evaluator{table};
    msg::LegCommandMsg leg{};
    leg.legId = 5;
    leg.maxPathLengthM = 30.0;
    leg.maxEnergyJ = 5000.0;
    leg.maxPowerW = 20.0;  // 16 W allowed; straight driving draws 15 W per unit factor
    evaluator.beginLeg(leg);
    const msg::TrajectoryMsg t = trajectory(1, {{0.0, 0.0}, {10.0, 0.0}});
    supervisor.followPlan(1.0);
    const habitual::FactorCheck check =
        supervisor.checkPowerFactors(t, pose(0.0, 0.0), evaluator, {0.0, 0.0, 1.2}, 5);
    CHECK(FactorVerdict::kPower == check.verdict);
    CHECK(msg::LegConstraint::kPower == check.evaluation.violated);
    LONGS_EQUAL(0, supervisor.counters().energyViolations);
}

TEST(DriveSupervisor, TheFollowerReachingTheEndEndsTheLegOrTheBackOut) {
    const msg::TrajectoryMsg t = trajectory(4, {{0.0, 0.0}, {10.0, 0.0}});
    CHECK(FollowerVerdict::kReached == supervisor.judgeFollower(follower(4, msg::FollowerState::kReached), t, false, 1));
    CHECK(FollowerVerdict::kEscapeDone ==
          supervisor.judgeFollower(follower(4, msg::FollowerState::kReached), t, true, 1));
    // About another trajectory, or no news.
    CHECK(FollowerVerdict::kNothing == supervisor.judgeFollower(follower(3, msg::FollowerState::kReached), t, false, 1));
    CHECK(FollowerVerdict::kNothing ==
          supervisor.judgeFollower(follower(4, msg::FollowerState::kFollowing), t, false, 1));
    const msg::TrajectoryMsg stop = trajectory(5, {});
    CHECK(FollowerVerdict::kNothing ==
          supervisor.judgeFollower(follower(5, msg::FollowerState::kReached), stop, false, 1));
}

TEST(DriveSupervisor, TheFollowerGivingUpIsReplannedOncePerLegThenFailedUp) {
    const msg::TrajectoryMsg t = trajectory(4, {{0.0, 0.0}, {10.0, 0.0}});
    const msg::FollowerStatusMsg gaveUp =
        follower(4, msg::FollowerState::kCannotFollow, msg::FollowReason::kCrossTrackError);
    CHECK(FollowerVerdict::kReplan == supervisor.judgeFollower(gaveUp, t, false, 6));
    seen.take();
    CHECK_TRUE(seen.says(ev::kCannotFollow, "habitual: leg 6: follower gave up (cross-track error): replanning once"));
    CHECK(FollowerVerdict::kFailUp == supervisor.judgeFollower(gaveUp, t, false, 6));
    seen.take();
    CHECK_TRUE(seen.says(ev::kCannotFollow, "(cross-track error): fail-up"));
    LONGS_EQUAL(2, supervisor.counters().cannotFollow);
    // A new leg gets its replan again; held drives fail up at once.
    supervisor.beginLeg();
    const msg::FollowerStatusMsg held = follower(4, msg::FollowerState::kCannotFollow, msg::FollowReason::kDrivesHeld);
    CHECK(FollowerVerdict::kFailUp == supervisor.judgeFollower(held, t, false, 7));
    CHECK(FollowerVerdict::kReplan == supervisor.judgeFollower(gaveUp, t, false, 7));
}

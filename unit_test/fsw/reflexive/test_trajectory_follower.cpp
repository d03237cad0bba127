// The follower's control law alone (no bus): pure-pursuit geometry, the speed,
// turn-rate, wheel and acceleration limits, progress that never goes backwards,
// arrival, giving up, stopping.
#include <cmath>
#include <cstddef>

#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/reflexive/trajectory_follower.hpp"
#include "fsw/tables/table_types.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using msg::FollowerState;
using msg::FollowReason;
using msg::TrajectoryPoint;
using reflexive::FollowerOutput;
using reflexive::FollowerPose;
using reflexive::TrajectoryFollower;

namespace {

constexpr double kDt = 0.01;

// The values of tables/follower.toml and tables/rover_geometry.toml.
tables::FollowerTable defaultFollower() {
    tables::FollowerTable t{};
    t.lookahead_m = 0.8F;
    t.arrival_tolerance_m = 0.15F;
    t.max_cross_track_m = 1.0F;
    t.turn_in_place_rad = 0.8F;
    t.pose_timeout_ms = 200;
    return t;
}

tables::RoverGeometryTable defaultGeometry() {
    tables::RoverGeometryTable g{};
    g.wheel_radius_m = 0.10F;
    g.track_width_m = 0.60F;
    g.wheelbase_m = 0.70F;
    g.footprint_radius_m = 0.60F;
    g.skid_factor = 1.5F;
    g.max_wheel_speed_rad_s = 5.0F;
    g.max_body_speed_m_s = 0.30F;
    g.max_body_rate_rad_s = 0.50F;
    g.max_accel_m_s2 = 0.20F;
    g.max_manual_drive_s = 60;
    return g;
}

double f(float x) { return static_cast<double>(x); }

}  // namespace

TEST_GROUP(TrajectoryFollower) {
    TrajectoryFollower follower;
    tables::FollowerTable table = defaultFollower();
    tables::RoverGeometryTable geometry = defaultGeometry();

    FollowerOutput stepAt(double x, double y, double heading, double dt = kDt) {
        const FollowerPose pose{x, y, heading};
        return follower.step(&pose, table, geometry, dt);
    }
    // Steps at a fixed pose until the slew limits have let (v, w) reach their targets.
    FollowerOutput settleAt(double x, double y, double heading) {
        FollowerOutput out{};
        for (int i = 0; i < 500; ++i) {
            out = stepAt(x, y, heading);
        }
        return out;
    }
    void followStraight(double length, double speed = 0.3) {
        const TrajectoryPoint pts[2] = {{0.0, 0.0}, {length, 0.0}};
        CHECK_TRUE(follower.follow(pts, 2, speed));
    }
};

TEST(TrajectoryFollower, CurvatureIsTwoSinAlphaOverTheLookaheadDistance) {
    followStraight(10.0);
    const FollowerOutput out = settleAt(2.0, 0.3, 0.0);
    // Closest point (2, 0); look-ahead point 0.8 m further: (2.8, 0).
    const double ld = std::hypot(0.8, 0.3);
    const double alpha = std::atan2(-0.3, 0.8);
    const double k = 2.0 * std::sin(alpha) / ld;
    CHECK_TRUE(FollowerState::kFollowing == out.state);
    DOUBLES_EQUAL(0.3, out.speedMS, 1e-6);  // cruise: no limit binds
    DOUBLES_EQUAL(0.3 * k, out.turnRateRadS, 1e-6);
    DOUBLES_EQUAL(0.3, out.crossTrackErrorM, 1e-12);
    DOUBLES_EQUAL(8.0, out.remainingM, 1e-12);
    LONGS_EQUAL(1, out.targetIndex);
    CHECK_FALSE(out.turningInPlace);
}

TEST(TrajectoryFollower, TheTurnRateLimitSlowsTheRoverAndKeepsTheCurvature) {
    table.lookahead_m = 0.5F;
    table.turn_in_place_rad = 1.5F;
    followStraight(10.0);
    const FollowerOutput out = settleAt(2.0, 0.4, 0.0);
    const double ld = std::hypot(0.5, 0.4);
    const double k = 2.0 * std::sin(std::atan2(-0.4, 0.5)) / ld;
    const double rateMax = f(geometry.max_body_rate_rad_s);
    CHECK_TRUE(rateMax / std::fabs(k) < 0.3);  // the case is one where the rate binds
    DOUBLES_EQUAL(-rateMax, out.turnRateRadS, 1e-9);
    DOUBLES_EQUAL(rateMax / std::fabs(k), out.speedMS, 1e-9);
    DOUBLES_EQUAL(k, out.turnRateRadS / out.speedMS, 1e-9);
}

TEST(TrajectoryFollower, TheTrajectorySpeedAndTheBodyLimitCapTheSpeed) {
    followStraight(10.0, 0.12);
    DOUBLES_EQUAL(0.12, settleAt(1.0, 0.0, 0.0).speedMS, 1e-12);
    followStraight(10.0, 5.0);  // more than the rover may do
    DOUBLES_EQUAL(f(geometry.max_body_speed_m_s), settleAt(1.0, 0.0, 0.0).speedMS, 1e-12);
    geometry.max_body_speed_m_s = 0.2F;  // read every step
    DOUBLES_EQUAL(0.2, settleAt(1.0, 0.0, 0.0).speedMS, 1e-7);
}

TEST(TrajectoryFollower, NearTheEndTheSpeedAllowsAStopWithinTheMaxDeceleration) {
    followStraight(10.0);
    const FollowerOutput out = settleAt(9.8, 0.0, 0.0);  // 0.2 m left, outside the 0.15 m tolerance
    CHECK_TRUE(FollowerState::kFollowing == out.state);
    DOUBLES_EQUAL(std::sqrt(2.0 * f(geometry.max_accel_m_s2) * 0.2), out.speedMS, 1e-6);
    CHECK_TRUE(out.speedMS < 0.3);
}

TEST(TrajectoryFollower, SpeedAndTurnRateSlewAtTheAccelerationLimits) {
    followStraight(10.0);
    const double dv = f(geometry.max_accel_m_s2) * kDt;
    const double dw = f(geometry.max_accel_m_s2) / (0.5 * f(geometry.track_width_m)) * kDt;
    double v = 0.0;
    for (int i = 0; i < 10; ++i) {
        const FollowerOutput out = stepAt(0.0, 0.0, 0.0);
        DOUBLES_EQUAL(v + dv, out.speedMS, 1e-12);
        v = out.speedMS;
    }
    // A path to the left: the turn rate may only grow by dw per step.
    const TrajectoryPoint left[2] = {{0.0, 0.0}, {0.0, 10.0}};
    CHECK_TRUE(follower.follow(left, 2, 0.3));
    const FollowerOutput out = stepAt(0.0, 0.0, 0.0);
    CHECK_TRUE(out.turningInPlace);  // 90 degrees off
    DOUBLES_EQUAL(v - dv, out.speedMS, 1e-12);  // kept across the change of trajectory, then slewed
    DOUBLES_EQUAL(dw, out.turnRateRadS, 1e-12);
    // A late step earns at most kMaxFollowerStepS of slew.
    const FollowerOutput late = stepAt(0.0, 0.0, 0.0, 5.0);
    DOUBLES_EQUAL(std::fmin(0.5, dw + dw / kDt * reflexive::kMaxFollowerStepS), late.turnRateRadS, 1e-12);
    // A bad dt moves nothing.
    const FollowerOutput same = stepAt(0.0, 0.0, 0.0, std::nan(""));
    DOUBLES_EQUAL(late.turnRateRadS, same.turnRateRadS, 0.0);
    DOUBLES_EQUAL(late.speedMS, same.speedMS, 0.0);
}

TEST(TrajectoryFollower, APathBehindTurnsInPlaceTowardsTheLookaheadPoint) {
    const TrajectoryPoint pts[2] = {{0.0, 0.0}, {-5.0, 0.1}};
    CHECK_TRUE(follower.follow(pts, 2, 0.3));
    const FollowerOutput out = settleAt(0.0, 0.0, 0.0);
    CHECK_TRUE(out.turningInPlace);
    DOUBLES_EQUAL(0.0, out.speedMS, 0.0);
    DOUBLES_EQUAL(f(geometry.max_body_rate_rad_s), out.turnRateRadS, 1e-12);  // left: the point is at +y
    LONGS_EQUAL(1, follower.turnsInPlace());
}

TEST(TrajectoryFollower, TurnInPlaceDirectionFollowsTheSignOfAlpha) {
    const TrajectoryPoint pts[2] = {{0.0, 0.0}, {0.0, 5.0}};  // north
    CHECK_TRUE(follower.follow(pts, 2, 0.3));
    // Heading east: the point is 90 degrees to the left.
    CHECK_TRUE(settleAt(0.0, 0.0, 0.0).turnRateRadS > 0.0);
    LONGS_EQUAL(1, follower.turnsInPlace());
    // Within the threshold (0.5 rad to the left) it drives on.
    const FollowerOutput on = settleAt(0.0, 0.0, 1.5707963 - 0.5);
    CHECK_FALSE(on.turningInPlace);
    CHECK_TRUE(on.speedMS > 0.0);
    CHECK_TRUE(on.turnRateRadS > 0.0);
    // Heading 2.9 rad: the point is 1.33 rad to the right.
    const FollowerOutput out = settleAt(0.0, 0.0, 2.9);
    CHECK_TRUE(out.turningInPlace);
    DOUBLES_EQUAL(-f(geometry.max_body_rate_rad_s), out.turnRateRadS, 1e-12);
    DOUBLES_EQUAL(0.0, out.speedMS, 0.0);
    LONGS_EQUAL(2, follower.turnsInPlace());
}

TEST(TrajectoryFollower, ProgressNeverGoesBackwards) {
    // A U: east, north, back west 1 m above the first leg.
    const TrajectoryPoint pts[4] = {{0.0, 0.0}, {4.0, 0.0}, {4.0, 1.0}, {0.0, 1.0}};
    CHECK_TRUE(follower.follow(pts, 4, 0.3));
    FollowerOutput out = stepAt(1.0, 0.1, 0.0);
    LONGS_EQUAL(1, out.targetIndex);
    // Nearer the last leg than the first, but that leg lies beyond the search window.
    out = stepAt(1.0, 0.9, 0.0);
    LONGS_EQUAL(1, out.targetIndex);
    DOUBLES_EQUAL(0.9, out.crossTrackErrorM, 1e-12);
    // Along the U to its last leg...
    for (double y = 0.0; y <= 1.0; y += 0.1) {
        out = stepAt(4.0, y, 1.57);
    }
    out = stepAt(3.0, 1.0, 3.14);
    LONGS_EQUAL(3, out.targetIndex);
    DOUBLES_EQUAL(3.0, out.remainingM, 1e-12);
    // ...from where the first leg is never taken again.
    out = stepAt(1.0, 0.1, 3.14);
    LONGS_EQUAL(3, out.targetIndex);
    DOUBLES_EQUAL(0.9, out.crossTrackErrorM, 1e-12);
    DOUBLES_EQUAL(1.0, out.remainingM, 1e-12);
}

TEST(TrajectoryFollower, ArrivalCommandsZeroThroughTheDecelerationLimit) {
    followStraight(2.0);
    double v = settleAt(1.0, 0.0, 0.0).speedMS;
    DOUBLES_EQUAL(0.3, v, 1e-12);
    FollowerOutput out = stepAt(1.9, 0.0, 0.0);  // 0.1 m from the end
    CHECK_TRUE(FollowerState::kReached == out.state);
    CHECK_TRUE(FollowReason::kNone == out.reason);
    DOUBLES_EQUAL(0.1, out.toEndM, 1e-12);
    const double dv = f(geometry.max_accel_m_s2) * kDt;
    DOUBLES_EQUAL(v - dv, out.speedMS, 1e-12);
    int steps = 1;
    while (follower.moving() && steps < 1000) {
        out = stepAt(1.9, 0.0, 0.0);
        ++steps;
    }
    CHECK_TRUE(FollowerState::kReached == out.state);
    LONGS_EQUAL(static_cast<long>(std::ceil(0.3 / dv - 1e-9)), steps);
}

TEST(TrajectoryFollower, PassingNearTheEndOfALoopIsNotArrival) {
    // A loop that ends 0.1 m from where it starts.
    const TrajectoryPoint pts[5] = {{0.0, 0.0}, {3.0, 0.0}, {3.0, 3.0}, {0.0, 3.0}, {0.0, 0.1}};
    CHECK_TRUE(follower.follow(pts, 5, 0.3));
    const FollowerOutput out = stepAt(0.05, 0.0, 0.0);
    CHECK_TRUE(FollowerState::kFollowing == out.state);
    CHECK_TRUE(out.speedMS > 0.0);
}

TEST(TrajectoryFollower, CrossTrackBeyondTheTableGivesUpWithZeroAtOnce) {
    followStraight(10.0);
    (void)settleAt(1.0, 0.0, 0.0);
    const FollowerOutput out = stepAt(2.0, 1.01, 0.0);
    CHECK_TRUE(FollowerState::kCannotFollow == out.state);
    CHECK_TRUE(FollowReason::kCrossTrackError == out.reason);
    DOUBLES_EQUAL(0.0, out.speedMS, 0.0);
    DOUBLES_EQUAL(0.0, out.turnRateRadS, 0.0);
    DOUBLES_EQUAL(1.01, out.crossTrackErrorM, 1e-12);
    // It stays given up, at zero, until a new trajectory.
    CHECK_TRUE(FollowerState::kCannotFollow == stepAt(2.0, 0.0, 0.0).state);
    followStraight(10.0);
    CHECK_TRUE(FollowerState::kFollowing == stepAt(2.0, 0.0, 0.0).state);
}

TEST(TrajectoryFollower, NoPoseWhileFollowingGivesUpAsPoseStale) {
    followStraight(10.0);
    (void)settleAt(1.0, 0.0, 0.0);
    const FollowerOutput out = follower.step(nullptr, table, geometry, kDt);
    CHECK_TRUE(FollowerState::kCannotFollow == out.state);
    CHECK_TRUE(FollowReason::kPoseStale == out.reason);
    DOUBLES_EQUAL(0.0, out.speedMS, 0.0);
}

TEST(TrajectoryFollower, StopDeceleratesWithinVOverAThenIdles) {
    followStraight(20.0);
    (void)settleAt(1.0, 0.0, 0.0);
    follower.stop();
    const double dv = f(geometry.max_accel_m_s2) * kDt;
    int steps = 0;
    FollowerOutput out{};
    double v = 0.3;
    do {
        out = follower.step(nullptr, table, geometry, kDt);  // a stop needs no pose
        ++steps;
        CHECK_TRUE(v - out.speedMS <= dv + 1e-12);
        v = out.speedMS;
    } while (out.state == FollowerState::kStopping && steps < 1000);
    CHECK_TRUE(FollowerState::kIdle == out.state);
    DOUBLES_EQUAL(0.0, out.speedMS, 0.0);
    LONGS_EQUAL(static_cast<long>(std::ceil(0.3 / dv - 1e-9)), steps);
}

TEST(TrajectoryFollower, HaltNowZeroesAStopAtOnceAndGivesUpAFollow) {
    followStraight(20.0);
    (void)settleAt(1.0, 0.0, 0.0);
    follower.stop();
    (void)follower.step(nullptr, table, geometry, kDt);
    CHECK_TRUE(follower.moving());
    follower.haltNow(FollowReason::kDrivesHeld);
    CHECK_FALSE(follower.moving());
    CHECK_TRUE(FollowerState::kIdle == follower.state());
    followStraight(20.0);
    (void)settleAt(1.0, 0.0, 0.0);
    follower.haltNow(FollowReason::kNotAutonomous);
    CHECK_FALSE(follower.moving());
    CHECK_TRUE(FollowerState::kCannotFollow == follower.state());
    CHECK_TRUE(FollowReason::kNotAutonomous == follower.reason());
}

TEST(TrajectoryFollower, NoWheelExceedsItsLimitWhateverTheTables) {
    geometry.max_wheel_speed_rad_s = 2.0F;  // rim 0.2 m/s: below the body speed limit
    geometry.max_accel_m_s2 = 2.0F;
    followStraight(10.0);
    const double radius = f(geometry.wheel_radius_m);
    const double half = 0.5 * f(geometry.track_width_m);
    for (double y = -0.5; y <= 0.5; y += 0.05) {
        const FollowerOutput out = settleAt(2.0, y, 0.3);
        const double left = (out.speedMS - out.turnRateRadS * half) / radius;
        const double right = (out.speedMS + out.turnRateRadS * half) / radius;
        CHECK_TRUE(std::fabs(left) <= 2.0 + 1e-9);
        CHECK_TRUE(std::fabs(right) <= 2.0 + 1e-9);
        CHECK_TRUE(std::fabs(out.turnRateRadS) <= f(geometry.max_body_rate_rad_s) + 1e-9);
    }
}

TEST(TrajectoryFollower, ASinglePointTrajectoryDrivesToThePoint) {
    const TrajectoryPoint pt[1] = {{1.0, 0.0}};
    CHECK_TRUE(follower.follow(pt, 1, 0.3));
    FollowerOutput out = settleAt(0.5, 0.0, 0.0);
    CHECK_TRUE(FollowerState::kFollowing == out.state);
    CHECK_TRUE(out.speedMS > 0.0);
    DOUBLES_EQUAL(0.5, out.crossTrackErrorM, 1e-12);
    LONGS_EQUAL(0, out.targetIndex);
    out = stepAt(0.9, 0.0, 0.0);
    CHECK_TRUE(FollowerState::kReached == out.state);
}

TEST(TrajectoryFollower, RepeatedPointsGiveNoNaN) {
    const TrajectoryPoint pts[4] = {{0.0, 0.0}, {0.0, 0.0}, {2.0, 0.0}, {2.0, 0.0}};
    CHECK_TRUE(follower.follow(pts, 4, 0.3));
    for (int i = 0; i < 50; ++i) {
        const FollowerOutput out = stepAt(0.01 * i, 0.01, 0.0);
        CHECK_TRUE(std::isfinite(out.speedMS) && std::isfinite(out.turnRateRadS));
        CHECK_TRUE(std::isfinite(out.crossTrackErrorM) && std::isfinite(out.remainingM));
    }
}

TEST(TrajectoryFollower, FollowRefusesWhatTheTaskWouldRefuse) {
    followStraight(10.0);
    const TrajectoryPoint bad[2] = {{0.0, 0.0}, {std::nan(""), 1.0}};
    CHECK_FALSE(follower.follow(bad, 2, 0.3));
    const TrajectoryPoint ok[2] = {{0.0, 0.0}, {1.0, 1.0}};
    CHECK_FALSE(follower.follow(ok, 0, 0.3));
    CHECK_FALSE(follower.follow(ok, msg::kMaxTrajectoryPoints + 1, 0.3));
    CHECK_FALSE(follower.follow(ok, 2, -0.1));
    CHECK_FALSE(follower.follow(ok, 2, INFINITY));
    CHECK_FALSE(follower.follow(nullptr, 2, 0.3));
    const FollowerOutput out = stepAt(1.0, 0.0, 0.0);
    DOUBLES_EQUAL(9.0, out.remainingM, 1e-12);  // still the first path
}

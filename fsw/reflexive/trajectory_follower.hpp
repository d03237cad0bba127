// The reflexive trajectory follower's control law: pure pursuit on a polyline,
// with the rover geometry table's speed, turn-rate, wheel-speed and acceleration
// limits. A plain class with no bus, so it can be tested (and reasoned about)
// alone; TrajectoryTask (trajectory_task.hpp) feeds it from the bus.
//
// Each step while following, with the pose (x, y, heading):
//  1. Progress: the closest point on the path, searched from the current
//     segment onwards (never backwards) over the segments that start within
//     lookahead_m + max_cross_track_m of path length past the previous closest
//     point, so a path that comes back near itself is not cut short. Its
//     distance is the cross-track error; the path length after it is the
//     remaining length.
//  2. Arrival: within arrival_tolerance_m of the last point (and the remaining
//     length at most lookahead_m + arrival_tolerance_m, so passing near the end
//     of a path that loops back does not count) -> kReached once; the target
//     becomes (0, 0), reached through the acceleration limits below.
//  3. Give-up: cross-track error above max_cross_track_m -> kCannotFollow
//     (kCrossTrackError); no pose -> kCannotFollow (kPoseStale). A give-up
//     commands (0, 0) at once, without the acceleration limits.
//  4. Pure pursuit: the look-ahead point lies lookahead_m of path length past
//     the closest point (the last point when the path ends sooner); alpha is
//     its bearing from the rover's heading, L_d its distance, and the curvature
//     is k = 2 sin(alpha) / L_d.
//       |alpha| > turn_in_place_rad: turn in place, v = 0 and
//         w = sign(alpha) * min(max_body_rate_rad_s, max_wheel_speed_rad_s r / (track/2)).
//       otherwise v = min(trajectory speed, max_body_speed_m_s,
//                         sqrt(2 max_accel_m_s2 remaining),      (stop at the end)
//                         max_body_rate_rad_s / |k|,              (keeps the curvature)
//                         max_wheel_speed_rad_s r / (1 + |k| track/2)),
//                 w = v k.
//  5. Slew: v moves towards its target by at most max_accel_m_s2 * dt, w by at
//     most max_accel_m_s2 / (track/2) * dt, so no wheel rim accelerates faster
//     than max_accel_m_s2. Then (v, w) are scaled together so that no wheel
//     exceeds max_wheel_speed_rad_s, and each is clipped to its body limit (the
//     limits win over the slew if a table lowers them in flight).
//
// Stopping (stop()): target (0, 0) through the slew limits, kStopping, then
// kIdle in the step where both reach zero: body speed v reaches zero within
// v / max_accel_m_s2 (rounded up to whole steps), turn rate w within
// |w| (track/2) / max_accel_m_s2. After kReached the same deceleration applies.
//
// Tables are passed in every step, never cached. No heap, every loop bounded by
// kMaxTrajectoryPoints.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::reflexive {

struct FollowerPose {
    double xM;
    double yM;
    double headingRad;
};

// What one step decided: the body command after every limit, and where the
// rover is on the path (the fields of FollowerStatusMsg).
struct FollowerOutput {
    double speedMS = 0.0;
    double turnRateRadS = 0.0;
    msg::FollowerState state = msg::FollowerState::kIdle;
    msg::FollowReason reason = msg::FollowReason::kNone;
    std::uint8_t targetIndex = 0;   // the segment followed ends at points[targetIndex]
    double crossTrackErrorM = 0.0;
    double remainingM = 0.0;
    double toEndM = 0.0;            // straight-line distance to the last point
    bool turningInPlace = false;
};

// Longest time step the slew limits are applied over: a late frame does not
// earn the rover a larger jump than this.
constexpr double kMaxFollowerStepS = 0.1;

class TrajectoryFollower {
public:
    // Starts following points[0..count-1] at up to speedMS. The caller has
    // checked 1 <= count <= kMaxTrajectoryPoints, finite points, finite
    // speedMS >= 0 (anything else leaves the follower unchanged and returns
    // false). The commanded (v, w) are kept: the slew limits hold across a
    // change of trajectory.
    bool follow(const msg::TrajectoryPoint* points, std::size_t count, double speedMS);
    // Decelerates to zero within the acceleration limits (kStopping, then kIdle).
    void stop();
    // Gives up on the trajectory: (0, 0) at once, kCannotFollow with the reason.
    void giveUp(msg::FollowReason reason);
    // Zero at once whatever the state, for when the wheels are no longer ours
    // to drive (drives held, mode left): following gives up with the reason,
    // stopping ends in kIdle, kReached stays kReached.
    void haltNow(msg::FollowReason reason);

    // One control step over dtS seconds. pose is nullptr when there is no valid,
    // fresh pose estimate (while following that gives up with kPoseStale).
    FollowerOutput step(const FollowerPose* pose, const tables::FollowerTable& follower,
                        const tables::RoverGeometryTable& geometry, double dtS);

    msg::FollowerState state() const { return state_; }
    msg::FollowReason reason() const { return reason_; }
    double speedMS() const { return v_; }
    double turnRateRadS() const { return w_; }
    bool moving() const { return v_ != 0.0 || w_ != 0.0; }
    const FollowerOutput& latest() const { return out_; }
    std::size_t pointCount() const { return count_; }
    std::uint32_t turnsInPlace() const { return turnsInPlace_; }  // entries into turning in place

private:
    struct PathPoint {
        double xM;
        double yM;
        double sM;  // path length from points[0]
    };

    // Updates the progress (segment_, sProj_) and the output's cross-track,
    // remaining and target index; returns the distance to the last point.
    double track(const FollowerPose& pose, const tables::FollowerTable& follower);
    // The point lookahead path metres past the closest point (clamped to the end).
    void lookaheadPoint(double lookaheadM, double* x, double* y) const;
    void pursue(const FollowerPose& pose, const tables::FollowerTable& follower,
                const tables::RoverGeometryTable& geometry, double* vTarget, double* wTarget);
    void slewTowards(double vTarget, double wTarget, const tables::RoverGeometryTable& geometry, double dtS);

    PathPoint path_[msg::kMaxTrajectoryPoints] = {};
    std::size_t count_ = 0;
    std::size_t segment_ = 0;  // index of the first point of the segment followed
    double sProj_ = 0.0;       // path length at the closest point
    double speedLimit_ = 0.0;  // the trajectory's speed
    double v_ = 0.0;           // commanded, after the limits
    double w_ = 0.0;
    msg::FollowerState state_ = msg::FollowerState::kIdle;
    msg::FollowReason reason_ = msg::FollowReason::kNone;
    bool turningInPlace_ = false;
    std::uint32_t turnsInPlace_ = 0;
    FollowerOutput out_{};
};

}  // namespace rse::reflexive

#include "fsw/reflexive/trajectory_follower.hpp"

#include <cmath>
#include <limits>

namespace rse::reflexive {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Below this a look-ahead distance gives no bearing: the rover is on the point.
constexpr double kTinyM = 1e-9;

double clamp(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

double wrapAngle(double a) { return std::remainder(a, 2.0 * kPi); }

}  // namespace

bool TrajectoryFollower::follow(const msg::TrajectoryPoint* points, std::size_t count, double speedMS) {
    if (points == nullptr || count == 0 || count > msg::kMaxTrajectoryPoints || !std::isfinite(speedMS) ||
        speedMS < 0.0) {
        return false;
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (!std::isfinite(points[i].xM) || !std::isfinite(points[i].yM)) {
            return false;
        }
    }
    double s = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        if (i > 0) {
            s += std::hypot(points[i].xM - points[i - 1].xM, points[i].yM - points[i - 1].yM);
        }
        path_[i] = PathPoint{points[i].xM, points[i].yM, s};
    }
    count_ = count;
    segment_ = 0;
    sProj_ = 0.0;
    speedLimit_ = speedMS;
    state_ = msg::FollowerState::kFollowing;
    reason_ = msg::FollowReason::kNone;
    turningInPlace_ = false;
    out_.targetIndex = static_cast<std::uint8_t>(count > 1 ? 1 : 0);
    out_.crossTrackErrorM = 0.0;
    out_.remainingM = s;
    out_.toEndM = 0.0;
    return true;
}

void TrajectoryFollower::stop() {
    count_ = 0;
    state_ = msg::FollowerState::kStopping;
    reason_ = msg::FollowReason::kNone;
    turningInPlace_ = false;
    out_.targetIndex = 0;
    out_.crossTrackErrorM = 0.0;
    out_.remainingM = 0.0;
    out_.toEndM = 0.0;
}

void TrajectoryFollower::giveUp(msg::FollowReason reason) {
    v_ = 0.0;
    w_ = 0.0;
    state_ = msg::FollowerState::kCannotFollow;
    reason_ = reason;
    turningInPlace_ = false;
}

void TrajectoryFollower::haltNow(msg::FollowReason reason) {
    if (state_ == msg::FollowerState::kFollowing) {
        giveUp(reason);
        return;
    }
    v_ = 0.0;
    w_ = 0.0;
    if (state_ == msg::FollowerState::kStopping) {
        state_ = msg::FollowerState::kIdle;
    }
}

double TrajectoryFollower::track(const FollowerPose& pose, const tables::FollowerTable& follower) {
    const PathPoint& last = path_[count_ - 1];
    const double toLast = std::hypot(pose.xM - last.xM, pose.yM - last.yM);
    out_.toEndM = toLast;
    if (count_ == 1) {  // the path is the point: what is left is the way there
        out_.targetIndex = 0;
        out_.crossTrackErrorM = toLast;
        out_.remainingM = toLast;
        return toLast;
    }
    const double window =
        sProj_ + static_cast<double>(follower.lookahead_m) + static_cast<double>(follower.max_cross_track_m);
    double best = std::numeric_limits<double>::infinity();
    std::size_t bestSegment = segment_;
    double bestS = sProj_;
    for (std::size_t k = segment_; k + 1 < count_; ++k) {
        const PathPoint& a = path_[k];
        const PathPoint& b = path_[k + 1];
        if (k > segment_ && a.sM > window) {
            break;
        }
        const double ex = b.xM - a.xM;
        const double ey = b.yM - a.yM;
        const double len2 = ex * ex + ey * ey;
        const double t = len2 > 0.0 ? clamp(((pose.xM - a.xM) * ex + (pose.yM - a.yM) * ey) / len2, 0.0, 1.0) : 0.0;
        const double d = std::hypot(pose.xM - (a.xM + t * ex), pose.yM - (a.yM + t * ey));
        if (d < best) {
            best = d;
            bestSegment = k;
            bestS = a.sM + t * (b.sM - a.sM);
        }
    }
    segment_ = bestSegment;
    sProj_ = bestS;
    out_.targetIndex = static_cast<std::uint8_t>(segment_ + 1);
    out_.crossTrackErrorM = best;
    out_.remainingM = std::fmax(0.0, last.sM - sProj_);
    return toLast;
}

void TrajectoryFollower::lookaheadPoint(double lookaheadM, double* x, double* y) const {
    const PathPoint& last = path_[count_ - 1];
    const double s = std::fmin(sProj_ + lookaheadM, last.sM);
    *x = last.xM;
    *y = last.yM;
    for (std::size_t k = segment_; k + 1 < count_; ++k) {
        const PathPoint& a = path_[k];
        const PathPoint& b = path_[k + 1];
        if (b.sM >= s) {
            const double len = b.sM - a.sM;
            const double t = len > 0.0 ? clamp((s - a.sM) / len, 0.0, 1.0) : 1.0;
            *x = a.xM + t * (b.xM - a.xM);
            *y = a.yM + t * (b.yM - a.yM);
            return;
        }
    }
}

void TrajectoryFollower::pursue(const FollowerPose& pose, const tables::FollowerTable& follower,
                                const tables::RoverGeometryTable& geometry, double* vTarget, double* wTarget) {
    double lx = 0.0;
    double ly = 0.0;
    lookaheadPoint(static_cast<double>(follower.lookahead_m), &lx, &ly);
    const double ld = std::hypot(lx - pose.xM, ly - pose.yM);
    const double alpha = ld > kTinyM ? wrapAngle(std::atan2(ly - pose.yM, lx - pose.xM) - pose.headingRad) : 0.0;
    const double radius = static_cast<double>(geometry.wheel_radius_m);
    const double halfTrack = 0.5 * static_cast<double>(geometry.track_width_m);
    const double rimMax = static_cast<double>(geometry.max_wheel_speed_rad_s) * radius;  // m/s at the rim
    const double rateMax = static_cast<double>(geometry.max_body_rate_rad_s);

    if (std::fabs(alpha) > static_cast<double>(follower.turn_in_place_rad)) {
        if (!turningInPlace_) {
            ++turnsInPlace_;
        }
        turningInPlace_ = true;
        const double w = std::fmin(rateMax, rimMax / halfTrack);
        *vTarget = 0.0;
        *wTarget = alpha > 0.0 ? w : -w;
        return;
    }
    turningInPlace_ = false;
    const double k = ld > kTinyM ? 2.0 * std::sin(alpha) / ld : 0.0;
    double v = std::fmin(speedLimit_, static_cast<double>(geometry.max_body_speed_m_s));
    v = std::fmin(v, std::sqrt(2.0 * static_cast<double>(geometry.max_accel_m_s2) * out_.remainingM));
    if (std::fabs(k) * v > rateMax) {
        v = rateMax / std::fabs(k);
    }
    v = std::fmin(v, rimMax / (1.0 + std::fabs(k) * halfTrack));
    v = std::fmax(v, 0.0);
    *vTarget = v;
    *wTarget = v * k;
}

void TrajectoryFollower::slewTowards(double vTarget, double wTarget, const tables::RoverGeometryTable& geometry,
                                     double dtS) {
    const double dt = dtS > 0.0 ? std::fmin(dtS, kMaxFollowerStepS) : 0.0;  // NaN gives 0
    const double accel = static_cast<double>(geometry.max_accel_m_s2);
    const double halfTrack = 0.5 * static_cast<double>(geometry.track_width_m);
    const double dvMax = accel * dt;
    const double dwMax = accel / halfTrack * dt;
    v_ += clamp(vTarget - v_, -dvMax, dvMax);
    w_ += clamp(wTarget - w_, -dwMax, dwMax);
    const double rim = (std::fabs(v_) + std::fabs(w_) * halfTrack) / static_cast<double>(geometry.wheel_radius_m);
    const double wheelMax = static_cast<double>(geometry.max_wheel_speed_rad_s);
    if (rim > wheelMax) {
        v_ *= wheelMax / rim;
        w_ *= wheelMax / rim;
    }
    const double vMax = static_cast<double>(geometry.max_body_speed_m_s);
    const double rateMax = static_cast<double>(geometry.max_body_rate_rad_s);
    v_ = clamp(v_, -vMax, vMax);
    w_ = clamp(w_, -rateMax, rateMax);
}

FollowerOutput TrajectoryFollower::step(const FollowerPose* pose, const tables::FollowerTable& follower,
                                        const tables::RoverGeometryTable& geometry, double dtS) {
    switch (state_) {
        case msg::FollowerState::kFollowing: {
            if (pose == nullptr) {
                giveUp(msg::FollowReason::kPoseStale);
                break;
            }
            const double toLast = track(*pose, follower);
            const double tolerance = static_cast<double>(follower.arrival_tolerance_m);
            if (toLast <= tolerance && out_.remainingM <= static_cast<double>(follower.lookahead_m) + tolerance) {
                state_ = msg::FollowerState::kReached;
                turningInPlace_ = false;
                slewTowards(0.0, 0.0, geometry, dtS);
            } else if (out_.crossTrackErrorM > static_cast<double>(follower.max_cross_track_m)) {
                giveUp(msg::FollowReason::kCrossTrackError);
            } else {
                double vTarget = 0.0;
                double wTarget = 0.0;
                pursue(*pose, follower, geometry, &vTarget, &wTarget);
                slewTowards(vTarget, wTarget, geometry, dtS);
            }
            break;
        }
        case msg::FollowerState::kReached:
            if (pose != nullptr) {
                (void)track(*pose, follower);
            }
            slewTowards(0.0, 0.0, geometry, dtS);
            break;
        case msg::FollowerState::kStopping:
            slewTowards(0.0, 0.0, geometry, dtS);
            if (!moving()) {
                state_ = msg::FollowerState::kIdle;
            }
            break;
        case msg::FollowerState::kIdle:
        case msg::FollowerState::kCannotFollow:
        case msg::FollowerState::kBackingOff:  // the task's contact reflex, never the follower's own state
            v_ = 0.0;
            w_ = 0.0;
            break;
    }
    out_.speedMS = v_;
    out_.turnRateRadS = w_;
    out_.state = state_;
    out_.reason = reason_;
    out_.turningInPlace = turningInPlace_;
    return out_;
}

}  // namespace rse::reflexive

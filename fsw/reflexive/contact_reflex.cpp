#include "fsw/reflexive/contact_reflex.hpp"

#include <cmath>

namespace rse::reflexive {

const char* toString(BackoffEnd end) {
    switch (end) {
        case BackoffEnd::kNone:
            return "none";
        case BackoffEnd::kDistance:
            return "backed off";
        case BackoffEnd::kTimeout:
            return "timed out";
        case BackoffEnd::kContact:
            return "another contact";
        case BackoffEnd::kReleased:
            return "wheels released";
        case BackoffEnd::kSuperseded:
            return "superseded";
    }
    return "?";
}

ContactReading ContactReflex::observe(const msg::DriveStatusMsg& drives, const tables::FollowerTable& table) {
    ContactReading r;
    const double pushA = static_cast<double>(table.contact_current_a);
    const double stallRatio = static_cast<double>(table.contact_stall_ratio);
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        const msg::WheelStatus& w = drives.wheels[i];
        const double target = w.targetRadS;
        // The steady-command count, whatever the wheel's state.
        const double tolerance = kSteadyTargetTolerance * std::fabs(steadyTarget_[i]);
        if (std::isfinite(target) && std::fabs(target - steadyTarget_[i]) <= tolerance) {
            steadyFrames_[i] = steadyFrames_[i] < kSteadyFrames ? static_cast<std::uint8_t>(steadyFrames_[i] + 1U)
                                                                 : kSteadyFrames;
        } else {
            steadyTarget_[i] = std::isfinite(target) ? target : 0.0;
            steadyFrames_[i] = 0;
        }
        const bool fresh = drives.timeNs - w.feedbackTimeNs <= kFeedbackMaxAgeNs && w.feedbackCount > 0;
        if (!(std::fabs(target) >= kActiveWheelRadS) || !fresh || w.health != msg::DriveHealth::kOperational) {
            continue;
        }
        if (!std::isfinite(w.currentA) || !std::isfinite(w.velocityRadS)) {
            ++r.notFinite;   // counted by the task: a reading that says nothing is not "no contact"
            continue;
        }
        const double current = std::fabs(w.currentA);
        const bool pushing = current >= pushA;
        // Along the command: a wheel turning backwards counts as not turning.
        const double along = w.velocityRadS * (target > 0.0 ? 1.0 : -1.0);
        const bool stalled = steadyFrames_[i] >= kSteadyFrames && along < stallRatio * std::fabs(target);
        if (pushing || stalled) {
            ++r.wheelsPushing;
            r.maxCurrentA = current > r.maxCurrentA ? current : r.maxCurrentA;
        }
    }
    r.contact = r.wheelsPushing >= table.contact_wheels;
    latest_ = r;
    return r;
}

void ContactReflex::startBackoff(double xM, double yM, double directionSign, core::TimeNs now) {
    state_ = BackoffState::kBacking;
    fromX_ = xM;
    fromY_ = yM;
    sign_ = directionSign < 0.0 ? 1.0 : -1.0;
    backedM_ = 0.0;
    speed_ = 0.0;
    start_ = now;
}

BackoffEnd ContactReflex::abortBackoff(BackoffEnd why) {
    if (state_ == BackoffState::kNone) {
        return BackoffEnd::kNone;
    }
    state_ = BackoffState::kNone;
    return why;
}

double ContactReflex::backoffStep(bool poseKnown, double xM, double yM, core::TimeNs now, double dtS,
                                  double maxAccelMS2, double maxSpeedMS, const tables::FollowerTable& table,
                                  BackoffEnd* ended) {
    *ended = BackoffEnd::kNone;
    if (state_ != BackoffState::kBacking) {
        return 0.0;
    }
    if (!poseKnown) {
        *ended = abortBackoff(BackoffEnd::kReleased);
        return 0.0;
    }
    backedM_ = std::hypot(xM - fromX_, yM - fromY_);
    const double distance = static_cast<double>(table.contact_backoff_m);
    const double tableSpeed = static_cast<double>(table.contact_backoff_speed_m_s);
    const double speed = tableSpeed < maxSpeedMS ? tableSpeed : maxSpeedMS;
    if (!(speed > 0.0)) {
        *ended = abortBackoff(BackoffEnd::kTimeout);  // no speed to back off at
        return 0.0;
    }
    const double limitS = kBackoffTimeFactor * distance / speed + 1.0;
    if (backedM_ >= distance) {
        *ended = abortBackoff(BackoffEnd::kDistance);
        return 0.0;
    }
    if (static_cast<double>(now - start_) / static_cast<double>(core::kNsPerSec) > limitS) {
        *ended = abortBackoff(BackoffEnd::kTimeout);
        return 0.0;
    }
    if (now == start_) {
        return 0.0;  // the contact's own run: the wheels to zero
    }
    const double step = maxAccelMS2 * dtS;
    const double target = sign_ * speed;
    speed_ = std::fabs(target - speed_) <= step ? target : speed_ + (target > speed_ ? step : -step);
    return speed_;
}

}  // namespace rse::reflexive

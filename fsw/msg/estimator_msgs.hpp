// The state estimate every layer decides from (fsw/estimator/pose_estimator_task.hpp).
// Site frame: metres, x east, y north, heading counter-clockwise from +x, wrapped
// to (-pi, pi].
#pragma once

#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

struct PoseEstimateMsg {
    static constexpr core::MsgId kMsgId = ids::kPoseEstimate;
    std::int64_t timeNs;          // time the estimate is valid at
    double xM;
    double yM;
    double headingRad;
    double speedMS;               // body forward speed used in the last prediction (wheel odometry)
    double yawRateRadS;           // body yaw rate used in the last prediction (bias-corrected)
    double gyroBiasRadS;          // estimated IMU yaw-rate bias
    double covariance[9];         // (x, y, heading), row major: m^2, m rad, rad^2
    double gyroBiasVariance;      // (rad/s)^2
    double positionSigmaM;        // sqrt of the largest eigenvalue of the (x, y) covariance block
    std::uint32_t fixesAccepted;
    std::uint32_t fixesRejected;  // by the Mahalanobis gate (outliers)
    std::uint32_t fixesInvalid;   // malformed (non-finite, sigma not positive)
    std::uint32_t imuStaleCount;  // predictions that used the wheel yaw rate because the IMU was stale
    std::uint32_t consecutiveFixRejections;  // fixes refused by the gate since the last one taken
    std::uint32_t reanchors;      // times the filter was re-anchored on a fix after fix_reject_limit refusals
    std::uint8_t initialised;     // 0 until the first accepted position fix
    std::uint8_t yawFromImu;      // 1: the last prediction used the IMU, 0: the wheels
    // 1 from the fix_reject_limit'th fix refused in a row until, after the
    // re-anchoring, a fix passes the gate again: the estimate disagrees with
    // the fixes, so its covariance cannot be trusted (health raises fault 19).
    std::uint8_t inconsistent;
    std::uint8_t pad[5];
};

}  // namespace rse::msg

// Event ids raised by the pose estimator (range 700-719; the estimator folder
// owns 700-799). Texts start with "estimator: ". Documented in docs/architecture.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::estimator::events {

// "(throttled)": evented on the 1st, 2nd, 4th, 8th ... occurrence, every one counted.
constexpr core::EventId kPoseInitialised = 700;     // INFO: first valid fix, pose and sigmas
constexpr core::EventId kFixRejectedByGate = 701;   // WARN: Mahalanobis d2 beyond the gate (throttled)
constexpr core::EventId kFixInvalid = 702;          // WARN: non-finite value or sigma <= 0 (throttled)
constexpr core::EventId kYawFromWheels = 703;       // WARN: IMU stale, yaw rate from the wheels
constexpr core::EventId kYawFromImu = 704;          // INFO: IMU fresh again, yaw rate from the IMU
constexpr core::EventId kOdometryStale = 705;       // WARN: no fresh wheel feedback, speed taken as 0 (throttled)
constexpr core::EventId kEstimatorMalformed = 706;  // ERROR: bus message that does not decode (throttled)
constexpr core::EventId kPredictionRefused = 707;   // ERROR: time went backwards or a non-finite input (throttled)
constexpr core::EventId kInputNotFinite = 708;      // WARN: non-finite wheel velocity or IMU rate ignored (throttled)
constexpr core::EventId kImuSampleInvalid = 709;    // WARN: IMU sample flagged invalid, ignored (throttled)
constexpr core::EventId kFixSuperseded = 710;       // INFO: two fixes in one frame, the older dropped (throttled)
constexpr core::EventId kFixesInconsistent = 711;   // ERROR: fix_reject_limit fixes refused in a row: estimate inconsistent
constexpr core::EventId kPoseReanchored = 712;      // WARN: estimate re-anchored on a fix (jump, bias kept, its sigma reset)
constexpr core::EventId kFixesConsistent = 713;     // INFO: a fix passed the gate after the re-anchoring: consistent again

}  // namespace rse::estimator::events

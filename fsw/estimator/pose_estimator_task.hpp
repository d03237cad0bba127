// The pose estimator task (every 10 ms minor frame, right after CAN I/O so it
// sees this frame's inputs): feeds the pose EKF (pose_ekf.hpp) and publishes
// PoseEstimateMsg every run.
//
// Each run, with now = the frame's actual start:
//  1. Drains its pipe (core::InputPipe, at most kEstimatorPipeDepth messages):
//     keeps the latest DriveStatusMsg, the latest IMU sample that is valid with
//     a finite rate, and the latest PositionFixMsg (an older one in the same
//     run is counted as superseded). A message that does not decode (counted by
//     the pipe, event 706), a non-finite value and an invalid IMU sample are
//     counted and evented (throttled), never used.
//  2. Once initialised, predicts from the previous prediction time to now:
//     - speed v = r (meanLeft + meanRight) / 2 over the wheels with fresh
//       feedback (feedbackCount > 0 and feedbackTimeNs at most
//       kWheelFeedbackMaxAgeNs old). Wheels 0-2 are the left side, 3-5 the
//       right. A side without a fresh wheel takes the other side's mean; with
//       no fresh wheel at all v = 0 (odometry stale: counted, event 705).
//       A failed (locked) wheel reports 0 and stays in its side's mean: the
//       rover really is slower. Wheels are excluded only for staleness.
//     - yaw rate from the latest IMU sample when it is at most imu_timeout_ms
//       old (bias-corrected in the filter), otherwise from the wheels:
//       r (meanRight - meanLeft) / (skid_factor track_width) with the wheel
//       noise density (counted per prediction; events 703/704 on each switch).
//  3. Applies a pending fix at now (the fix carries its CAN receive time, in
//     this frame): sigmaXY = max(fix sigma, position_fix_sigma_floor_m),
//     heading sigma fix_heading_sigma_rad. The first valid fix initialises
//     the filter (bias 0 +- initial_gyro_bias_sigma_rad_s, event 700); later
//     ones pass the fix_gate_chi2 Mahalanobis gate or are rejected (event
//     701), never moving the estimate.
//     Refused fixes in a row are counted; the fix_reject_limit'th marks the
//     estimate inconsistent (event 711): the fixes refute it, so its
//     covariance is too small for its real error (a gyro bias step the bias
//     walk cannot follow, slip beyond the model) and every later fix would be
//     refused too. The next valid fix then re-anchors the filter (event 712):
//     position and heading from the fix as at initialisation, the bias
//     estimate kept but its sigma back to initial_gyro_bias_sigma_rad_s so the
//     following fixes re-estimate it. The estimate stays inconsistent until a
//     fix passes the gate again (event 713). A burst of outliers shorter than
//     the limit is refused and never moves the estimate; a source that stays
//     offset longer than the limit is believed over the filter, with the
//     pose-uncertainty fault raised meanwhile.
//  4. Publishes PoseEstimateMsg (before initialisation: initialised = 0, zero
//     pose, 1e6 on the covariance diagonal).
// The estimator noise and rover geometry tables are read every run.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/estimator/pose_ekf.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::estimator {

constexpr std::uint16_t kEstimatorPipeDepth = 8;
constexpr core::TimeNs kWheelFeedbackMaxAgeNs = 50 * core::kNsPerMs;
// Published while no fix has initialised the filter: "no idea where we are".
constexpr double kUninitialisedVariance = 1e6;

// The EKF's process noise as the ESTIMATOR_NOISE table gives it.
PoseProcessNoise processNoiseFrom(const tables::EstimatorNoiseTable& table);

struct PoseEstimatorCounters {
    std::uint32_t runs = 0;
    std::uint32_t predictions = 0;
    std::uint32_t predictionsRefused = 0;  // time went backwards, or the filter refused the inputs
    std::uint32_t fixesAccepted = 0;       // the initialising fix included
    std::uint32_t fixesRejected = 0;       // by the Mahalanobis gate
    std::uint32_t fixesInvalid = 0;        // non-finite, sigma <= 0, or refused by the filter
    std::uint32_t fixesSuperseded = 0;     // a newer fix came in the same run
    std::uint32_t imuStale = 0;            // predictions that used the wheel yaw rate
    std::uint32_t yawSourceSwitches = 0;
    std::uint32_t odometryStale = 0;       // predictions without any fresh wheel (v = 0)
    std::uint32_t malformed = 0;           // bus messages that did not decode (the input pipe's count)
    std::uint32_t notFinite = 0;           // non-finite wheel velocities or IMU rates ignored
    std::uint32_t imuInvalid = 0;          // IMU samples flagged invalid
    std::uint32_t consecutiveRejections = 0;  // fixes refused by the gate since the last one taken
    std::uint32_t inconsistencies = 0;     // times fix_reject_limit refusals in a row were reached
    std::uint32_t reanchors = 0;           // fixes the filter was re-anchored on
};

class PoseEstimatorTask final : public core::Task {
public:
    PoseEstimatorTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables);

    // Creates the pipe "estimator" and routes DriveStatusMsg, ImuMsg and PositionFixMsg to their takers.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    const PoseEkf& filter() const { return filter_; }
    const msg::PoseEstimateMsg& latest() const { return latest_; }
    const PoseEstimatorCounters& counters() const { return counters_; }
    bool yawFromImu() const { return yawFromImu_; }
    bool inconsistent() const { return inconsistent_; }

private:
    struct Odometry {
        double speedMS = 0.0;
        double wheelYawRateRadS = 0.0;
        bool stale = true;  // no wheel with fresh feedback
    };

    void takeDriveStatus(const msg::DriveStatusMsg& status);
    void takeImu(const msg::ImuMsg& sample);
    void takeFix(const msg::PositionFixMsg& fix);
    Odometry odometry(core::TimeNs now) const;
    void predictTo(core::TimeNs now);
    void applyFix();
    void noteFixRefused(const msg::PositionFixMsg& fix, double mahalanobis2);
    void reanchorOn(const msg::PositionFixMsg& fix, double sigmaXy, double sigmaTheta);
    void publish(core::TimeNs now);
    void countNotFinite(const char* what);

    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    core::InputPipe input_;
    PoseEkf filter_;

    msg::DriveStatusMsg drive_{};
    bool haveDrive_ = false;
    msg::ImuMsg imu_{};
    bool haveImu_ = false;
    msg::PositionFixMsg fix_{};
    bool fixPending_ = false;

    core::TimeNs lastPredictNs_ = 0;
    bool haveTime_ = false;
    bool yawFromImu_ = true;  // assumed until the first prediction says otherwise
    double speedMS_ = 0.0;    // inputs of the last prediction, published
    double yawRateRadS_ = 0.0;
    bool inconsistent_ = false;    // the fixes refuted the estimate (see step 3)
    bool reanchorDue_ = false;     // the next valid fix re-anchors the filter

    PoseEstimatorCounters counters_;
    msg::PoseEstimateMsg latest_{};
};

}  // namespace rse::estimator

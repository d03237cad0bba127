#include "fsw/estimator/pose_estimator_task.hpp"

#include <cmath>

#include "fsw/estimator/pose_estimator_events.hpp"

namespace rse::estimator {

namespace {

constexpr std::size_t kLeftWheels = msg::kWheelCount / 2;  // 0-2 left, 3-5 right (docs/icd.md §1.1)
constexpr double kSecPerNs = 1e-9;
constexpr double kMsPerNs = 1e-6;

double toSeconds(core::TimeNs ns) { return static_cast<double>(ns) * kSecPerNs; }

}  // namespace

PoseProcessNoise processNoiseFrom(const tables::EstimatorNoiseTable& t) {
    PoseProcessNoise noise;
    noise.speedNoiseDensity = static_cast<double>(t.speed_noise_density);
    noise.speedNoiseFracDensity = static_cast<double>(t.speed_noise_frac_density);
    noise.imuYawRateNoiseDensity = static_cast<double>(t.imu_yaw_rate_noise_density);
    noise.wheelYawRateNoiseDensity = static_cast<double>(t.wheel_yaw_rate_noise_density);
    noise.gyroBiasWalk = static_cast<double>(t.gyro_bias_walk_rad_s2);
    return noise;
}

PoseEstimatorTask::PoseEstimatorTask(core::SoftwareBus& bus, core::EventLog& events,
                                     const tables::TableService& tables)
    : bus_(bus),
      events_(events),
      tables_(tables),
      input_(bus, events, core::InputPipeConfig{"estimator", kEstimatorPipeDepth, events::kEstimatorMalformed,
                                                "estimator"}) {}

core::Status PoseEstimatorTask::init() {
    core::Status status = input_.create();
    if (core::isOk(status)) {
        status = input_.route<&PoseEstimatorTask::takeDriveStatus>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&PoseEstimatorTask::takeImu>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&PoseEstimatorTask::takeFix>(this);
    }
    return status;
}

void PoseEstimatorTask::run(const core::FrameContext& frame) {
    const core::TimeNs now = frame.actualStart;
    ++counters_.runs;
    input_.drain();
    counters_.malformed = input_.malformed();
    if (!haveTime_) {
        haveTime_ = true;
        lastPredictNs_ = now;
    } else if (filter_.initialised()) {
        predictTo(now);
    } else {
        lastPredictNs_ = now;  // nothing to predict yet; the first fix starts from now
    }
    applyFix();
    publish(now);
}

void PoseEstimatorTask::takeDriveStatus(const msg::DriveStatusMsg& status) {
    for (const msg::WheelStatus& wheel : status.wheels) {
        if (!std::isfinite(wheel.velocityRadS)) {
            countNotFinite("wheel velocity");  // that wheel is left out of the odometry
        }
    }
    drive_ = status;
    haveDrive_ = true;
}

void PoseEstimatorTask::takeImu(const msg::ImuMsg& sample) {
    if (sample.valid != 1) {
        ++counters_.imuInvalid;
        if (core::isReportableOccurrence(counters_.imuInvalid)) {
            events_.report(events::kImuSampleInvalid, core::Severity::kWarning,
                           "estimator: IMU sample flagged invalid, ignored (%u so far)",
                           static_cast<unsigned>(counters_.imuInvalid));
        }
        return;
    }
    if (!std::isfinite(sample.yawRateRadS)) {
        countNotFinite("IMU yaw rate");
        return;
    }
    imu_ = sample;
    haveImu_ = true;
}

void PoseEstimatorTask::takeFix(const msg::PositionFixMsg& fix) {
    if (fixPending_) {
        ++counters_.fixesSuperseded;
        if (core::isReportableOccurrence(counters_.fixesSuperseded)) {
            events_.report(events::kFixSuperseded, core::Severity::kInfo,
                           "estimator: two fixes in one frame, the older dropped (%u so far)",
                           static_cast<unsigned>(counters_.fixesSuperseded));
        }
    }
    fix_ = fix;
    fixPending_ = true;
}

void PoseEstimatorTask::countNotFinite(const char* what) {
    ++counters_.notFinite;
    if (core::isReportableOccurrence(counters_.notFinite)) {
        events_.report(events::kInputNotFinite, core::Severity::kWarning,
                       "estimator: non-finite %s ignored (%u so far)", what,
                       static_cast<unsigned>(counters_.notFinite));
    }
}

PoseEstimatorTask::Odometry PoseEstimatorTask::odometry(core::TimeNs now) const {
    Odometry out;
    double sum[2] = {0.0, 0.0};
    unsigned count[2] = {0U, 0U};
    for (std::size_t w = 0; haveDrive_ && w < msg::kWheelCount; ++w) {
        const msg::WheelStatus& wheel = drive_.wheels[w];
        // Health is deliberately not looked at: a locked wheel reports 0 and the
        // rover really is slower on that side.
        const bool fresh = wheel.feedbackCount > 0 && now - wheel.feedbackTimeNs <= kWheelFeedbackMaxAgeNs &&
                           std::isfinite(wheel.velocityRadS);
        if (fresh) {
            const std::size_t side = w < kLeftWheels ? 0 : 1;
            sum[side] += wheel.velocityRadS;
            ++count[side];
        }
    }
    if (count[0] == 0 && count[1] == 0) {
        return out;
    }
    const double meanLeft = count[0] > 0 ? sum[0] / count[0] : sum[1] / count[1];
    const double meanRight = count[1] > 0 ? sum[1] / count[1] : meanLeft;
    const tables::RoverGeometryTable& geometry = tables_.roverGeometry();
    const double radius = static_cast<double>(geometry.wheel_radius_m);
    const double track = static_cast<double>(geometry.track_width_m);
    const double skid = static_cast<double>(geometry.skid_factor);
    out.speedMS = radius * (meanLeft + meanRight) * 0.5;
    out.wheelYawRateRadS = radius * (meanRight - meanLeft) / (skid * track);
    out.stale = false;
    return out;
}

void PoseEstimatorTask::predictTo(core::TimeNs now) {
    const core::TimeNs dtNs = now - lastPredictNs_;
    if (dtNs == 0) {
        return;  // run twice in one instant: nothing elapsed
    }
    const tables::EstimatorNoiseTable& noiseTable = tables_.estimatorNoise();
    const core::TimeNs imuTimeoutNs = static_cast<core::TimeNs>(noiseTable.imu_timeout_ms) * core::kNsPerMs;
    const bool imuFresh = haveImu_ && now - imu_.timeNs <= imuTimeoutNs;

    const Odometry odo = odometry(now);
    if (odo.stale) {
        ++counters_.odometryStale;
        if (core::isReportableOccurrence(counters_.odometryStale)) {
            events_.report(events::kOdometryStale, core::Severity::kWarning,
                           "estimator: no fresh wheel feedback, speed taken as 0 (%u frames so far)",
                           static_cast<unsigned>(counters_.odometryStale));
        }
    }
    if (imuFresh != yawFromImu_) {
        yawFromImu_ = imuFresh;
        ++counters_.yawSourceSwitches;
        if (imuFresh) {
            events_.report(events::kYawFromImu, core::Severity::kInfo,
                           "estimator: IMU fresh again, yaw rate from the IMU");
        } else if (haveImu_) {
            events_.report(events::kYawFromWheels, core::Severity::kWarning,
                           "estimator: IMU stale (last sample %.0f ms old), yaw rate from the wheels",
                           static_cast<double>(now - imu_.timeNs) * kMsPerNs);
        } else {
            events_.report(events::kYawFromWheels, core::Severity::kWarning,
                           "estimator: no IMU sample yet, yaw rate from the wheels");
        }
    }

    const double omegaMeasured = imuFresh ? imu_.yawRateRadS : odo.wheelYawRateRadS;
    const double omegaUsed = imuFresh ? omegaMeasured - filter_.gyroBias() : omegaMeasured;
    const core::Status status =
        filter_.predict(toSeconds(dtNs), odo.speedMS, omegaMeasured, imuFresh, processNoiseFrom(noiseTable));
    // A refused step still moves the time on: after a backwards clock jump,
    // holding on to the old time would refuse every later step too.
    lastPredictNs_ = now;
    if (!core::isOk(status)) {
        ++counters_.predictionsRefused;
        if (core::isReportableOccurrence(counters_.predictionsRefused)) {
            events_.report(events::kPredictionRefused, core::Severity::kError,
                           "estimator: prediction refused (%s, dt %.3f s) (%u so far)", core::toString(status),
                           toSeconds(dtNs), static_cast<unsigned>(counters_.predictionsRefused));
        }
        return;
    }
    ++counters_.predictions;
    if (!imuFresh) {
        ++counters_.imuStale;
    }
    speedMS_ = odo.speedMS;
    yawRateRadS_ = omegaUsed;
}

void PoseEstimatorTask::applyFix() {
    if (!fixPending_) {
        return;
    }
    fixPending_ = false;
    const tables::EstimatorNoiseTable& t = tables_.estimatorNoise();
    const msg::PositionFixMsg& fix = fix_;
    const bool finiteFix = std::isfinite(fix.xM) && std::isfinite(fix.yM) && std::isfinite(fix.headingRad) &&
                           std::isfinite(fix.sigmaM);
    core::Status status = core::Status::kInvalidArgument;
    FixUpdateResult result{};
    const double floor = static_cast<double>(t.position_fix_sigma_floor_m);
    const double sigmaXy = finiteFix ? std::fmax(fix.sigmaM, floor) : 0.0;
    const double sigmaTheta = static_cast<double>(t.fix_heading_sigma_rad);
    if (finiteFix && fix.sigmaM > 0.0) {
        if (!filter_.initialised()) {
            status = filter_.init(fix.xM, fix.yM, fix.headingRad, sigmaXy, sigmaTheta,
                                  static_cast<double>(t.initial_gyro_bias_sigma_rad_s));
            result.accepted = core::isOk(status);
            if (result.accepted) {
                events_.report(events::kPoseInitialised, core::Severity::kInfo,
                               "estimator: initialised at x %.2f y %.2f m heading %.3f rad (sigma %.3f m %.4f rad)",
                               filter_.x(), filter_.y(), filter_.heading(), sigmaXy, sigmaTheta);
            }
        } else if (reanchorDue_) {
            reanchorOn(fix, sigmaXy, sigmaTheta);
            return;
        } else {
            status = filter_.updateFix(fix.xM, fix.yM, fix.headingRad, sigmaXy, sigmaTheta,
                                       static_cast<double>(t.fix_gate_chi2), &result);
        }
    }
    if (!core::isOk(status)) {
        ++counters_.fixesInvalid;
        if (core::isReportableOccurrence(counters_.fixesInvalid)) {
            events_.report(events::kFixInvalid, core::Severity::kWarning,
                           "estimator: invalid fix ignored (x %g y %g hdg %g sigma %g) (%u so far)", fix.xM, fix.yM,
                           fix.headingRad, fix.sigmaM, static_cast<unsigned>(counters_.fixesInvalid));
        }
        return;
    }
    if (!result.accepted) {
        noteFixRefused(fix, result.mahalanobis2);
        return;
    }
    ++counters_.fixesAccepted;
    counters_.consecutiveRejections = 0;
    if (inconsistent_ && !reanchorDue_) {
        inconsistent_ = false;
        events_.report(events::kFixesConsistent, core::Severity::kInfo,
                       "estimator: fix passed the gate after the re-anchoring (d2 %.1f): estimate consistent again",
                       result.mahalanobis2);
    }
}

void PoseEstimatorTask::noteFixRefused(const msg::PositionFixMsg& fix, double mahalanobis2) {
    const tables::EstimatorNoiseTable& t = tables_.estimatorNoise();
    ++counters_.fixesRejected;
    ++counters_.consecutiveRejections;
    if (core::isReportableOccurrence(counters_.fixesRejected)) {
        events_.report(events::kFixRejectedByGate, core::Severity::kWarning,
                       "estimator: fix (%.2f, %.2f) rejected: d2 %.1f > gate %.1f (%u so far)", fix.xM, fix.yM,
                       mahalanobis2, static_cast<double>(t.fix_gate_chi2),
                       static_cast<unsigned>(counters_.fixesRejected));
    }
    // Not ==: a limit lowered by a table load below the count so far still applies.
    if (counters_.consecutiveRejections < t.fix_reject_limit || reanchorDue_) {
        return;
    }
    reanchorDue_ = true;
    ++counters_.inconsistencies;
    inconsistent_ = true;
    events_.report(events::kFixesInconsistent, core::Severity::kError,
                   "estimator: %u fixes refused in a row (last d2 %.1f): estimate inconsistent, re-anchoring",
                   static_cast<unsigned>(counters_.consecutiveRejections), mahalanobis2);
}

void PoseEstimatorTask::reanchorOn(const msg::PositionFixMsg& fix, double sigmaXy, double sigmaTheta) {
    const tables::EstimatorNoiseTable& t = tables_.estimatorNoise();
    const double fromX = filter_.x();
    const double fromY = filter_.y();
    const double fromHeading = filter_.heading();
    const core::Status status = filter_.reanchor(fix.xM, fix.yM, fix.headingRad, sigmaXy, sigmaTheta,
                                                 static_cast<double>(t.initial_gyro_bias_sigma_rad_s));
    if (!core::isOk(status)) {
        ++counters_.fixesInvalid;  // the fix passed the checks above, so only the table can make this happen
        events_.report(events::kFixInvalid, core::Severity::kWarning, "estimator: re-anchoring refused (%s)",
                       core::toString(status));
        return;
    }
    reanchorDue_ = false;
    counters_.consecutiveRejections = 0;
    ++counters_.reanchors;
    ++counters_.fixesAccepted;
    events_.report(events::kPoseReanchored, core::Severity::kWarning,
                   "estimator: re-anchored at (%.2f, %.2f): moved %.2f m, %.3f rad; bias %.4f rad/s kept",
                   fix.xM, fix.yM, std::hypot(fix.xM - fromX, fix.yM - fromY),
                   wrapAngle(fix.headingRad - fromHeading), filter_.gyroBias());
}

void PoseEstimatorTask::publish(core::TimeNs now) {
    msg::PoseEstimateMsg& m = latest_;
    m = msg::PoseEstimateMsg{};
    m.timeNs = now;
    if (filter_.initialised()) {
        const PoseState& s = filter_.state();
        const PoseCovariance& p = filter_.covariance();
        m.xM = s(kPoseX);
        m.yM = s(kPoseY);
        m.headingRad = s(kPoseTheta);
        m.gyroBiasRadS = s(kPoseBias);
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                m.covariance[r * 3 + c] = p(r, c);
            }
        }
        m.gyroBiasVariance = p(kPoseBias, kPoseBias);
        m.positionSigmaM = filter_.positionSigma();
        m.speedMS = speedMS_;
        m.yawRateRadS = yawRateRadS_;
        m.initialised = 1;
    } else {
        m.covariance[0] = kUninitialisedVariance;
        m.covariance[4] = kUninitialisedVariance;
        m.covariance[8] = kUninitialisedVariance;
        m.gyroBiasVariance = kUninitialisedVariance;
        m.positionSigmaM = std::sqrt(kUninitialisedVariance);
    }
    m.fixesAccepted = counters_.fixesAccepted;
    m.fixesRejected = counters_.fixesRejected;
    m.fixesInvalid = counters_.fixesInvalid;
    m.imuStaleCount = counters_.imuStale;
    m.yawFromImu = yawFromImu_ ? 1 : 0;
    m.consecutiveFixRejections = counters_.consecutiveRejections;
    m.reanchors = counters_.reanchors;
    m.inconsistent = inconsistent_ ? 1 : 0;
    (void)bus_.publish(m);
}

}  // namespace rse::estimator

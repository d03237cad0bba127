#include "fsw/estimator/drive_mode_estimator.hpp"

#include <cmath>

namespace rse::estimator {

namespace {

constexpr std::size_t kNominal = static_cast<std::size_t>(msg::DriveMode::kNominal);
constexpr std::size_t kDegraded = static_cast<std::size_t>(msg::DriveMode::kDegraded);
constexpr std::size_t kFailed = static_cast<std::size_t>(msg::DriveMode::kFailed);
constexpr std::size_t kUnknown = static_cast<std::size_t>(msg::DriveMode::kUnknown);

constexpr double kUninformative = 0.5;  // unknown: every value of a binary reading alike

// One row of the transition matrix: the leaving probabilities as given, what is
// left stays; a row whose leaving probabilities sum beyond 1 (each may be 0.5) is
// scaled down so it still sums to 1.
void transitionRow(std::size_t from, const DriveHealthModel& m, double (&row)[msg::kDriveModeCount]) {
    for (double& p : row) {
        p = 0.0;
    }
    const double unknown = static_cast<double>(m.p_unknown);
    switch (from) {
        case kNominal:
            row[kDegraded] = static_cast<double>(m.p_degrade);
            row[kFailed] = static_cast<double>(m.p_fail_nominal);
            row[kUnknown] = unknown;
            break;
        case kDegraded:
            row[kNominal] = static_cast<double>(m.p_recover);
            row[kFailed] = static_cast<double>(m.p_fail_degraded);
            row[kUnknown] = unknown;
            break;
        case kFailed:
            row[kUnknown] = unknown;
            break;
        default:
            row[kNominal] = static_cast<double>(m.p_leave_unknown);
            break;
    }
    double leaving = 0.0;
    for (double p : row) {
        leaving += p;
    }
    row[from] = leaving < 1.0 ? 1.0 - leaving : 0.0;
    const double total = leaving + row[from];
    if (total > 0.0) {
        for (double& p : row) {
            p /= total;
        }
    } else {
        row[from] = 1.0;
    }
}

double probabilityOfYes(std::size_t mode, double nominal, double degraded, double failed) {
    switch (mode) {
        case kNominal:
            return nominal;
        case kDegraded:
            return degraded;
        case kFailed:
            return failed;
        default:
            return kUninformative;
    }
}

bool isFiniteWheel(const msg::WheelStatus& w) {
    return std::isfinite(w.targetRadS) && std::isfinite(w.velocityRadS) && std::isfinite(w.currentA) &&
           msg::isKnownDriveHealth(w.health);
}

// CiA 301 / 402 error code family 0x23xx: "current, device output side" (0x2310
// over-current, as the drives raise it).
bool isOverCurrentCode(std::uint16_t emcyCode) { return (emcyCode & 0xFF00U) == 0x2300U; }

bool reportsFault(msg::DriveHealth h) { return h == msg::DriveHealth::kFaulted || h == msg::DriveHealth::kFailed; }

// States in which the drive's CiA 402 state machine runs, so a fault would show.
bool couldReportFault(msg::DriveHealth h) {
    return h == msg::DriveHealth::kStarting || h == msg::DriveHealth::kEnabling ||
           h == msg::DriveHealth::kOperational || reportsFault(h);
}

bool drivesOrFaulted(msg::DriveHealth h) { return h == msg::DriveHealth::kOperational || reportsFault(h); }

// How long the lag needs to bring a target step of `step` rad/s down to the
// settled residual, from the frame the changed target is sent.
core::TimeNs settleTimeFor(double step) {
    const double lagS = kDriveLagTimeConstantS * std::log(std::fmax(step, kSettledResidualRadS) / kSettledResidualRadS);
    const core::TimeNs settle = kCommandDelayNs + static_cast<core::TimeNs>(lagS * static_cast<double>(core::kNsPerSec));
    return settle > kMinSettleTimeNs ? settle : kMinSettleTimeNs;
}

// Median of at most kWheelCount - 1 values (insertion sort; n is tiny).
double median(double* values, std::size_t n) {
    for (std::size_t i = 1; i < n; ++i) {
        const double v = values[i];
        std::size_t j = i;
        while (j > 0 && values[j - 1] > v) {
            values[j] = values[j - 1];
            --j;
        }
        values[j] = v;
    }
    return (n % 2 == 1) ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

double transitionProbability(msg::DriveMode from, msg::DriveMode to, const DriveHealthModel& model) {
    const std::size_t f = static_cast<std::size_t>(from);
    const std::size_t t = static_cast<std::size_t>(to);
    if (f >= msg::kDriveModeCount || t >= msg::kDriveModeCount) {
        return 0.0;
    }
    double row[msg::kDriveModeCount];
    transitionRow(f, model, row);
    return row[t];
}

double observationLikelihood(msg::DriveMode mode, const DriveObservation& o, const DriveHealthModel& m) {
    const std::size_t k = static_cast<std::size_t>(mode);
    double likelihood = 1.0;
    if (o.track != TrackReading::kNone) {
        const double stall = probabilityOfYes(k, static_cast<double>(m.p_stall_nominal),
                                              static_cast<double>(m.p_stall_degraded),
                                              static_cast<double>(m.p_stall_failed));
        likelihood *= o.track == TrackReading::kStall ? stall : 1.0 - stall;
    }
    if (o.current != CurrentReading::kNone) {
        const double high = probabilityOfYes(k, static_cast<double>(m.p_high_current_nominal),
                                             static_cast<double>(m.p_high_current_degraded), kHighCurrentGivenFailed);
        likelihood *= o.current == CurrentReading::kHigh ? high : 1.0 - high;
    }
    if (o.fault != FaultReading::kNone) {
        const double fault = probabilityOfYes(k, static_cast<double>(m.p_fault_report_nominal),
                                              static_cast<double>(m.p_fault_report_degraded),
                                              static_cast<double>(m.p_fault_report_failed));
        likelihood *= o.fault == FaultReading::kYes ? fault : 1.0 - fault;
    }
    return likelihood;
}

// ---- DriveModeFilter ----------------------------------------------------------

void DriveModeFilter::reset() {
    for (double& p : belief_) {
        p = kProbabilityFloor;
    }
    belief_[kNominal] = 1.0 - static_cast<double>(msg::kDriveModeCount - 1) * kProbabilityFloor;
    declared_ = msg::DriveMode::kNominal;
    powerFactor_ = 1.0;
}

ModeChange DriveModeFilter::update(const DriveObservation& observation, const DriveHealthModel& model) {
    double predicted[msg::kDriveModeCount] = {};
    for (std::size_t from = 0; from < msg::kDriveModeCount; ++from) {
        double row[msg::kDriveModeCount];
        transitionRow(from, model, row);
        for (std::size_t to = 0; to < msg::kDriveModeCount; ++to) {
            predicted[to] += belief_[from] * row[to];
        }
    }
    double posterior[msg::kDriveModeCount];
    double total = 0.0;
    for (std::size_t m = 0; m < msg::kDriveModeCount; ++m) {
        posterior[m] = predicted[m] * observationLikelihood(static_cast<msg::DriveMode>(m), observation, model);
        total += posterior[m];
    }
    // Every likelihood is >= 1e-4 cubed and every prior >= the floor, so total > 0;
    // the prediction stands in should that ever not hold.
    const double* source = (total > 0.0 && std::isfinite(total)) ? posterior : predicted;
    if (source == predicted) {
        total = 0.0;
        for (double p : predicted) {
            total += p;
        }
    }
    double floored = 0.0;
    for (std::size_t m = 0; m < msg::kDriveModeCount; ++m) {
        belief_[m] = std::fmax(source[m] / total, kProbabilityFloor);
        floored += belief_[m];
    }
    for (double& p : belief_) {
        p /= floored;
    }

    if (observation.ratioMeasured && std::isfinite(observation.currentRatio)) {
        powerFactor_ += static_cast<double>(model.power_factor_gain) * (observation.currentRatio - powerFactor_);
    }

    ModeChange change;
    const msg::DriveMode best = mostProbable();
    const double pBest = probability(best);
    if (best != declared_ && pBest >= static_cast<double>(model.declare_probability)) {
        change.changed = true;
        change.from = declared_;
        change.to = best;
        change.probability = pBest;
        declared_ = best;
    }
    return change;
}

double DriveModeFilter::probability(msg::DriveMode mode) const {
    const std::size_t m = static_cast<std::size_t>(mode);
    return m < msg::kDriveModeCount ? belief_[m] : 0.0;
}

msg::DriveMode DriveModeFilter::mostProbable() const {
    std::size_t best = 0;
    for (std::size_t m = 1; m < msg::kDriveModeCount; ++m) {
        if (belief_[m] > belief_[best]) {
            best = m;
        }
    }
    return static_cast<msg::DriveMode>(best);
}

// ---- DriveModeEstimator -------------------------------------------------------

core::Status DriveModeEstimator::addStatus(const msg::DriveStatusMsg& status, const DriveHealthModel& model) {
    for (const msg::WheelStatus& w : status.wheels) {
        if (!isFiniteWheel(w)) {
            return core::Status::kInvalidArgument;
        }
    }
    FrameCurrents* frame = framesInWindow_ < kMaxWindowFrames ? &frames_[framesInWindow_] : nullptr;
    if (frame != nullptr) {
        *frame = FrameCurrents{};
    }
    ++framesInWindow_;
    const double activeSpeed = static_cast<double>(model.active_speed_rad_s);
    const double settleStep = std::fmin(kSettleStepCapRadS, 0.5 * static_cast<double>(model.tracking_error_rad_s));
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        const msg::WheelStatus& w = status.wheels[i];
        SettleState& settle = settle_[i];
        const double step = std::fabs(w.targetRadS - settle.anchorTargetRadS);
        if (!settle.anchored || step > settleStep) {
            // An earlier step may still be settling longer than this one.
            const core::TimeNs until = status.timeNs + settleTimeFor(settle.anchored ? step : 0.0);
            settle.settleUntilNs = settle.anchored && settle.settleUntilNs > until ? settle.settleUntilNs : until;
            settle.anchored = true;
            settle.anchorTargetRadS = w.targetRadS;
        }
        WheelWindow& window = windows_[i];
        const bool fault = reportsFault(w.health);
        window.faultReported = window.faultReported || fault;
        window.overCurrentReported = window.overCurrentReported || (fault && isOverCurrentCode(w.lastEmcyCode));
        window.couldReportFault = window.couldReportFault || couldReportFault(w.health);
        const bool fresh = w.feedbackCount > 0 && status.timeNs - w.feedbackTimeNs <= kFeedbackMaxAgeNs;
        const bool moving = std::fabs(w.targetRadS) >= activeSpeed && fresh && drivesOrFaulted(w.health);
        const bool settling = status.timeNs < settle.settleUntilNs;
        if (moving && !settling) {
            ++window.activeFrames;
            window.errorSumRadS += std::fabs(w.targetRadS - w.velocityRadS);
        }
        if (moving && frame != nullptr) {
            const std::uint8_t bit = static_cast<std::uint8_t>(1U << i);
            frame->movingMask = static_cast<std::uint8_t>(frame->movingMask | bit);
            if (settling) {
                frame->settlingMask = static_cast<std::uint8_t>(frame->settlingMask | bit);
            }
            if (w.health == msg::DriveHealth::kOperational) {
                frame->operationalMask = static_cast<std::uint8_t>(frame->operationalMask | bit);
            }
            frame->currentA[i] = std::fabs(w.currentA);
            frame->anchorTargetRadS[i] = settle.anchorTargetRadS;
            frame->settleUntilNs[i] = settle.settleUntilNs;
        }
    }
    return core::Status::kOk;
}

// The wheels whose current wheel i's current is compared with in one frame:
// operational wheels that turn as i does. Settled, they must have tracked over
// the window; while settling, they must have taken the same step at the same
// time (same target, same settling end: the wheels of one side, or all six on a
// straight start), so their acceleration current matches i's, and not stalled.
std::size_t DriveModeEstimator::referencesOf(std::size_t i, const FrameCurrents& frame, std::uint8_t trackingMask,
                                             std::uint8_t stallMask, double (&references)[msg::kWheelCount]) {
    const bool settling = (frame.settlingMask & (1U << i)) != 0;
    std::size_t count = 0;
    for (std::size_t j = 0; j < msg::kWheelCount; ++j) {
        const unsigned bit = 1U << j;
        if (j == i || (frame.movingMask & frame.operationalMask & bit) == 0) {
            continue;
        }
        bool matches = false;
        if (!settling) {
            matches = (frame.settlingMask & bit) == 0 && (trackingMask & bit) != 0;
        } else {
            matches = (frame.settlingMask & bit) != 0 && (stallMask & bit) == 0 &&
                      frame.settleUntilNs[j] == frame.settleUntilNs[i] &&
                      std::fabs(frame.anchorTargetRadS[j] - frame.anchorTargetRadS[i]) <= kSameTargetRadS;
        }
        if (matches) {
            references[count++] = frame.currentA[j];
        }
    }
    return count;
}

void DriveModeEstimator::observe(const DriveHealthModel& model) {
    const double trackingError = static_cast<double>(model.tracking_error_rad_s);
    std::uint8_t trackingMask = 0;
    std::uint8_t stallMask = 0;
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        const WheelWindow& window = windows_[i];
        DriveObservation& o = observations_[i];
        o = DriveObservation{};
        o.activeFrames = window.activeFrames;
        if (window.activeFrames > 0) {
            o.meanTrackingErrorRadS = window.errorSumRadS / static_cast<double>(window.activeFrames);
            o.track = o.meanTrackingErrorRadS > trackingError ? TrackReading::kStall : TrackReading::kTracking;
            const std::uint8_t bit = static_cast<std::uint8_t>(1U << i);
            if (o.track == TrackReading::kTracking) {
                trackingMask = static_cast<std::uint8_t>(trackingMask | bit);
            } else {
                stallMask = static_cast<std::uint8_t>(stallMask | bit);
            }
        }
        if (window.faultReported) {
            o.fault = FaultReading::kYes;
        } else if (window.couldReportFault) {
            o.fault = FaultReading::kNo;
        }
    }
    const std::size_t storedFrames = framesInWindow_ < kMaxWindowFrames ? framesInWindow_ : kMaxWindowFrames;
    const double ratioHigh = static_cast<double>(model.current_ratio_high);
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        DriveObservation& o = observations_[i];
        double ownSum = 0.0;
        double referenceSum = 0.0;
        std::size_t counted = 0;
        for (std::size_t f = 0; f < storedFrames; ++f) {
            const FrameCurrents& frame = frames_[f];
            if ((frame.movingMask & (1U << i)) == 0) {
                continue;
            }
            double references[msg::kWheelCount] = {};
            const std::size_t count = referencesOf(i, frame, trackingMask, stallMask, references);
            if (count >= kMinReferenceWheels) {
                ownSum += frame.currentA[i];
                referenceSum += median(references, count);
                ++counted;
            }
        }
        o.currentFrames = static_cast<std::uint16_t>(counted);
        if (counted >= kMinCurrentFrames) {
            const double reference = referenceSum / static_cast<double>(counted);
            o.meanCurrentA = ownSum / static_cast<double>(counted);
            if (reference >= kMinReferenceCurrentA) {
                o.currentRatio = o.meanCurrentA / reference;
                o.ratioMeasured = true;
                o.current = o.currentRatio > ratioHigh ? CurrentReading::kHigh : CurrentReading::kNormal;
            }
        }
        // The drive's own over-current trip is a current reading too, and the
        // surest one: its window may hold too few frames to compare.
        if (windows_[i].overCurrentReported) {
            o.current = CurrentReading::kHigh;
        }
    }
}

void DriveModeEstimator::update(const DriveHealthModel& model, ModeChange (&changes)[msg::kWheelCount]) {
    observe(model);
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        changes[i] = filters_[i].update(observations_[i], model);
        windows_[i] = WheelWindow{};
    }
    framesInWindow_ = 0;
    ++updates_;
}

const char* driveModeName(msg::DriveMode mode) {
    switch (mode) {
        case msg::DriveMode::kNominal:
            return "nominal";
        case msg::DriveMode::kDegraded:
            return "degraded";
        case msg::DriveMode::kFailed:
            return "failed";
        case msg::DriveMode::kUnknown:
            return "unknown";
    }
    return "?";
}


}  // namespace rse::estimator

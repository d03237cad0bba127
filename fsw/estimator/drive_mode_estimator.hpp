// Drive mode estimation: for each of the six wheel drives a discrete Bayes filter
// (a hidden Markov model, Livingstone style) over the modes nominal / degraded /
// failed / unknown, updated every 100 ms from the drive status frames of the
// window. Pure logic: no bus, no events; DriveModeTask drives it.
//
// ---- Observations (one of each per drive and update, independent given the mode)
// A frame of a wheel is ACTIVE when |target| >= active_speed_rad_s, its feedback
// is fresh (reported within kFeedbackMaxAgeNs of the status), the drive is
// operational, faulted or failed, and the wheel is not settling. A target change
// of more than min(kSettleStepCapRadS, tracking_error_rad_s / 2) since the last
// such change starts a settling time in which the wheel's frames do not count:
// the command delay plus the time the drives' first-order lag (tau 50 ms) needs
// to shrink the step to kSettledResidualRadS, at least kMinSettleTimeNs (3 tau).
// So neither the lag error nor the acceleration current (20 mA per rad/s^2, under
// 1 % of the steady draw once settled) of a speed change reads as a fault.
//  o_track   none     : no active frame (idle, stale, settling): no evidence
//            stall    : mean |target - velocity| over the active frames > tracking_error_rad_s
//            tracking : otherwise
//  o_current none     : fewer than kMinCurrentFrames frames with references
//                       (below; one frame's noise is several % of the draw), or
//                       the references' current below kMinReferenceCurrentA
//            high     : ratio > current_ratio_high, normal otherwise, where
//                       ratio = this wheel's mean |current| / the mean of the
//                       references' median current, over the counted frames. A
//                       frame counts when this wheel is active or settling in it
//                       and has at least kMinReferenceWheels references: other
//                       operational wheels that turn as it does. Settled, they
//                       must be settled too and have read "tracking" over the
//                       window. Settling, they must have taken the same step at
//                       the same time (same target, same settling end: the
//                       wheels of one side, or all six on a straight start) and
//                       not read "stall", so their acceleration current matches
//                       and a degradation shows from the first frames of a start.
//                       All wheels share the load torque, so a healthy drive
//                       draws about the median; comparing frame by frame keeps a
//                       load change inside the window (a turn starting) from
//                       reading as a ratio.
//            high also when the drive reported an over-current fault (EMCY
//                       0x23xx) in the window: its own measurement, and the
//                       surest one when the trip leaves too few frames to compare.
//  o_fault   yes      : the drive reported CiA 402 fault (health kFaulted or kFailed)
//                       in any frame of the window
//            no       : otherwise, if a frame showed it starting, enabling or operational
//            none     : lost, booting or configuring all window: it could not report
// Likelihoods (table 7, DRIVE_HEALTH_MODEL; "none" is 1 for every mode):
//              nominal                  degraded                  failed                  unknown
//  P(stall)    p_stall_nominal          p_stall_degraded          p_stall_failed          1/2
//  P(high)     p_high_current_nominal   p_high_current_degraded   1/2 (kHighCurrentGivenFailed) 1/2
//  P(fault)    p_fault_report_nominal   p_fault_report_degraded   p_fault_report_failed   1/2
// and the complements for tracking / normal / no. P(high | failed) = 1/2 is
// neutral on purpose: a failed motor draws nothing, but its locked wheel is
// rarely active and tracking, and its current says nothing that the fault report
// and the tracking do not; so the current reading neither argues for nor against
// a failure. Unknown gives every value the same probability: it wins exactly when
// the evidence fits no modelled mode (e.g. stall with high current and no fault).
//
// ---- Transitions per update (row "from", normalised so each row sums to 1)
//  nominal  -> degraded p_degrade, -> failed p_fail_nominal,  -> unknown p_unknown
//  degraded -> nominal  p_recover, -> failed p_fail_degraded, -> unknown p_unknown
//  failed   -> unknown  p_unknown (otherwise absorbing: a failed drive comes back
//              only through unknown, when the evidence stops fitting "failed")
//  unknown  -> nominal  p_leave_unknown
// The rest of each row stays. Start belief: nominal 1 - 3 x kProbabilityFloor
// (the drives are checked out before a drive), the others at the floor. After
// each update the belief is normalised, floored at kProbabilityFloor (no mode is
// ever impossible, so evidence can always move it) and normalised again.
//
// ---- Declared mode and power factor
// The most probable mode is declared once its probability reaches
// declare_probability; below that the declared mode stays as it was. The power
// factor (estimated current draw relative to a nominal drive) is a low-pass, gain
// power_factor_gain per update, of the current ratio on updates where the
// comparison gave one (not from an over-current trip alone); it starts at 1.
//
// Time bounds with the default table (unit_test/fsw/estimator/test_drive_mode_*.cpp prove them on a
// drive model with the simulator's lag and current law):
//  - a degradation with current factor >= 1.5 while driving is declared within
//    0.6 s (the partial window, then four updates of "high" current);
//  - a failure is declared within 0.5 s of the motor failing when the drive
//    reports its fault within 20 ms (four updates from the first fault report,
//    even when the interlock idles every wheel at once).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/status.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::estimator {

using DriveHealthModel = tables::DriveHealthModelTable;

constexpr double kSettleStepCapRadS = 0.1;
constexpr core::TimeNs kMinSettleTimeNs = 150 * core::kNsPerMs;
constexpr core::TimeNs kCommandDelayNs = 20 * core::kNsPerMs;  // target sent -> applied at SYNC -> reported
constexpr double kDriveLagTimeConstantS = 0.05;                 // docs/icd.md: the drives' velocity loop
constexpr double kSettledResidualRadS = 0.02;
constexpr double kSameTargetRadS = 1e-3;  // targets this close are the same command (one side of the rover)
constexpr std::size_t kMaxWindowFrames = 40;  // 10 runs x the task's pipe depth of 4
constexpr core::TimeNs kFeedbackMaxAgeNs = 50 * core::kNsPerMs;
constexpr std::size_t kMinReferenceWheels = 2;
constexpr std::size_t kMinCurrentFrames = 3;
constexpr double kMinReferenceCurrentA = 0.05;  // a running nominal drive draws >= 0.15 A
constexpr double kHighCurrentGivenFailed = 0.5;
constexpr double kProbabilityFloor = 1e-9;

enum class TrackReading : std::uint8_t { kNone = 0, kTracking, kStall };
enum class CurrentReading : std::uint8_t { kNone = 0, kNormal, kHigh };
enum class FaultReading : std::uint8_t { kNone = 0, kNo, kYes };

struct DriveObservation {
    TrackReading track = TrackReading::kNone;
    CurrentReading current = CurrentReading::kNone;
    FaultReading fault = FaultReading::kNone;
    std::uint16_t activeFrames = 0;      // settled active frames (tracking)
    std::uint16_t currentFrames = 0;     // frames whose current was compared
    double meanTrackingErrorRadS = 0.0;  // over the active frames (0 if none)
    double meanCurrentA = 0.0;           // over the compared frames (0 if fewer than kMinCurrentFrames)
    double currentRatio = 0.0;           // from the comparison, when ratioMeasured
    bool ratioMeasured = false;
};

struct ModeChange {
    bool changed = false;
    msg::DriveMode from = msg::DriveMode::kNominal;
    msg::DriveMode to = msg::DriveMode::kNominal;
    double probability = 0.0;  // of the newly declared mode
};

// The model's two halves, exposed so tests (and docs) can check them alone.
double transitionProbability(msg::DriveMode from, msg::DriveMode to, const DriveHealthModel& model);
double observationLikelihood(msg::DriveMode mode, const DriveObservation& observation,
                             const DriveHealthModel& model);

// One drive's hidden Markov model.
class DriveModeFilter {
public:
    DriveModeFilter() { reset(); }

    void reset();
    // Predict with the transition model, correct with the observation.
    ModeChange update(const DriveObservation& observation, const DriveHealthModel& model);

    double probability(msg::DriveMode mode) const;
    msg::DriveMode mostProbable() const;
    msg::DriveMode declared() const { return declared_; }
    double powerFactor() const { return powerFactor_; }

private:
    double belief_[msg::kDriveModeCount] = {};
    msg::DriveMode declared_ = msg::DriveMode::kNominal;
    double powerFactor_ = 1.0;
};

// The six drives: collects the frames of the window, turns them into one
// observation per drive at update() and runs the six filters.
class DriveModeEstimator {
public:
    // One frame. kInvalidArgument (nothing taken) for a status with a non-finite
    // target, velocity or current, or a health value that is no DriveHealth.
    core::Status addStatus(const msg::DriveStatusMsg& status, const DriveHealthModel& model);
    // Ends the window: one belief update per drive; changes[w] tells wheel w's.
    void update(const DriveHealthModel& model, ModeChange (&changes)[msg::kWheelCount]);

    // wheel < kWheelCount (callers check); out of range gives wheel 0's.
    const DriveModeFilter& drive(std::size_t wheel) const { return filters_[wheel < msg::kWheelCount ? wheel : 0]; }
    const DriveObservation& lastObservation(std::size_t wheel) const {
        return observations_[wheel < msg::kWheelCount ? wheel : 0];
    }
    std::uint32_t updates() const { return updates_; }
    std::uint32_t framesInWindow() const { return framesInWindow_; }

private:
    struct WheelWindow {
        std::uint16_t activeFrames = 0;
        double errorSumRadS = 0.0;
        bool faultReported = false;
        bool overCurrentReported = false;
        bool couldReportFault = false;
    };
    // Each frame's currents, for the frame-by-frame comparison; frames beyond
    // kMaxWindowFrames still count for tracking and faults, not for current.
    struct FrameCurrents {
        std::uint8_t movingMask = 0;       // bit w: wheel w active or settling
        std::uint8_t settlingMask = 0;     // ... and settling
        std::uint8_t operationalMask = 0;  // ... and operational (no fault)
        double currentA[msg::kWheelCount] = {};
        double anchorTargetRadS[msg::kWheelCount] = {};
        core::TimeNs settleUntilNs[msg::kWheelCount] = {};
    };
    struct SettleState {
        bool anchored = false;
        double anchorTargetRadS = 0.0;
        core::TimeNs settleUntilNs = 0;
    };

    void observe(const DriveHealthModel& model);
    static std::size_t referencesOf(std::size_t wheel, const FrameCurrents& frame, std::uint8_t trackingMask,
                                    std::uint8_t stallMask, double (&references)[msg::kWheelCount]);

    WheelWindow windows_[msg::kWheelCount] = {};
    FrameCurrents frames_[kMaxWindowFrames] = {};
    SettleState settle_[msg::kWheelCount] = {};
    DriveObservation observations_[msg::kWheelCount] = {};
    DriveModeFilter filters_[msg::kWheelCount];
    std::uint32_t framesInWindow_ = 0;
    std::uint32_t updates_ = 0;
};

const char* driveModeName(msg::DriveMode mode);  // "nominal", ... "?" for a value that is no mode

}  // namespace rse::estimator

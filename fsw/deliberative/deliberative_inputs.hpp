// The deliberative task's inputs: its two pipes on the bus (core::InputPipe),
// the ids each takes, and what makes each message usable. A message that does
// not decode, that no route takes, or whose content is unusable is counted
// (malformed(): DeliberativeCounters::malformedInputs) and evented (916, the
// 1st, 2nd, 4th ... time on each pipe); the task keeps the last good one.
//
//   "delib_fast" (kFastPipeDepth): PoseEstimateMsg (finite mean, heading and
//       covariance), DriveStatusMsg (the interlock, each drive's health)
//   "deliberative" (kInputPipeDepth): PlanGoalMsg (the plan executive's drive
//       activity, its only source of goals: msg::goalListUsable, listIndex
//       within a list), LegReportMsg (a known habitual state and constraint),
//       DriveModesMsg, ModeMsg (a known mode), KnownHazardsMsg (finite discs,
//       radius in (0, kMaxHazardRadiusM], id nonzero, at most
//       msg::kMaxKnownHazards), MissionHoldMsg (msg::holdUsable),
//       FaultStatusMsg, ReplanRequestMsg (fault 46, off the map, try >= 1)
//
// Each usable message goes to the Receiver (the task) as it is drained, in
// the order it was published. No heap: the pipes decode into their own storage.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/core/status.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"

namespace rse::deliberative {

// Poses and drive status come at 100 Hz: 20 per run, 40 survive one skipped run.
constexpr std::uint16_t kFastPipeDepth = 40;
constexpr std::uint16_t kInputPipeDepth = 16;
// Largest hazard radius believed (the habitual layer merges no disc beyond 2 m).
constexpr float kMaxHazardRadiusM = 10.0F;

// Content checks, after decoding (kOk, or kInvalidArgument: malformed).
core::Status checkPose(const msg::PoseEstimateMsg& pose);
core::Status checkGoals(const msg::PlanGoalMsg& goal);
core::Status checkLegReport(const msg::LegReportMsg& report);
core::Status checkMode(const msg::ModeMsg& mode);
core::Status checkHazards(const msg::KnownHazardsMsg& hazards);
core::Status checkHold(const msg::MissionHoldMsg& hold);
core::Status checkReplanRequest(const msg::ReplanRequestMsg& request);

class DeliberativeInputs {
public:
    // What the task does with each usable input.
    class Receiver {
    public:
        virtual void takePose(const msg::PoseEstimateMsg& pose) = 0;
        virtual void takeDriveStatus(const msg::DriveStatusMsg& drives) = 0;
        virtual void takeGoals(const msg::PlanGoalMsg& goal) = 0;
        virtual void takeLegReport(const msg::LegReportMsg& report) = 0;
        virtual void takeDriveModes(const msg::DriveModesMsg& modes) = 0;
        virtual void takeMode(const msg::ModeMsg& mode) = 0;
        virtual void takeHazards(const msg::KnownHazardsMsg& hazards) = 0;
        virtual void takeHold(const msg::MissionHoldMsg& hold) = 0;
        virtual void takeFaults(const msg::FaultStatusMsg& faults) = 0;
        virtual void takeReplanRequest(const msg::ReplanRequestMsg& request) = 0;

    protected:
        ~Receiver() = default;  // the task is owned by the application
    };

    DeliberativeInputs(core::SoftwareBus& bus, core::EventLog& events, Receiver& receiver);

    // Start-up: both pipes and their routes; the bus's refusal as it is.
    core::Status init();
    // Every run: the fast pipe first (the pose the run works from), then the rest.
    void drainFast() { (void)fast_.drain(); }
    void drainInputs() { (void)inputs_.drain(); }

    // Messages refused on either pipe.
    std::uint32_t malformed() const { return fast_.malformed() + inputs_.malformed(); }

private:
    core::Status pose(const msg::PoseEstimateMsg& m);
    void driveStatus(const msg::DriveStatusMsg& m) { receiver_.takeDriveStatus(m); }
    core::Status goals(const msg::PlanGoalMsg& m);
    core::Status legReport(const msg::LegReportMsg& m);
    void driveModes(const msg::DriveModesMsg& m) { receiver_.takeDriveModes(m); }
    core::Status mode(const msg::ModeMsg& m);
    core::Status hazards(const msg::KnownHazardsMsg& m);
    core::Status hold(const msg::MissionHoldMsg& m);
    void faults(const msg::FaultStatusMsg& m) { receiver_.takeFaults(m); }
    core::Status replanRequest(const msg::ReplanRequestMsg& m);

    Receiver& receiver_;
    core::InputPipe fast_;
    core::InputPipe inputs_;
};

}  // namespace rse::deliberative

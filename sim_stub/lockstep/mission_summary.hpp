// How a lockstep mission went (runMission's MissionSummary): the outcome,
// what the flight software published and counted, fault protection's marks as
// the operator saw them, the simulator's truth at the end, and the ten points
// with the mission record; printMissionSummary prints it as rse-demo's
// "mission summary" (the console's last lines before the flight software's
// timing summary).
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "ground/mission_record.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::sim {

enum class MissionOutcome : std::uint8_t {
    kSetupFailed = 0,  // the scenario, the flight software, the drives or the ground link could not be used
    kGoalReached = 1,  // the deliberative layer published COMPLETE
    kCalledHome = 2,   // ... published CALLED HOME (callHome says why), or fault protection called home; a
                       // plan mission: the plan executive found no method left (callHome kPlanNoMethod)
    kTimedOut = 3,     // neither before the duration
    kPlanComplete = 4,  // a plan mission: the plan executive published its plan complete
};
const char* toString(MissionOutcome outcome);

// A moment of fault handling the operator can see: what happened, when, and
// which fault it was about.
enum class MarkKind : std::uint8_t {
    kFaultRaised,      // a health raise event (720..738, even ids)
    kResponseStarted,  // fault protection event 930
    kRecoveryAction,   // 931 (drive fault reset / node reset), 935 (task restart) or 942 (replan from the pose)
    kHoldSet,          // MissionHoldMsg reasons went from 0 to non-zero
    kHoldReleased,     // ... back to 0
    kGaveUp,           // 933
};
constexpr std::uint8_t kNoWheel = 0xFF;
// faultId and wheel come from the telemetry the flight software publishes in
// the frame of the mark's event, never from the event's text:
//   kFaultRaised      the fault id newly set in FaultStatusMsg::activeMask
//   kResponseStarted  the fault id of the response FaultProtectionStatusMsg
//                     newly lists as active (a drive lost or faulted: 1 + wheel,
//                     msg::fault::kDriveHeartbeatLost + wheel, as fault protection names it)
//   kRecoveryAction   931: 1 + DriveRecoveryMsg::wheel; 935: msg::fault::kTaskStalled +
//                     TaskRestartMsg::row; 942: ReplanRequestMsg::faultId
// faultId 0 for the hold and give-up marks, and for a mark no telemetry named
// (MissionSummary::marksUnattributed counts those). wheel is the drive's (0..5)
// for a wheel's fault id (drive heartbeat, over-current, over-temperature) and a
// drive action, else kNoWheel.
struct MissionMark {
    MarkKind kind = MarkKind::kFaultRaised;
    std::uint16_t eventId = 0;
    double timeS = 0.0;
    std::uint8_t faultId = 0;
    std::uint8_t wheel = kNoWheel;
};
constexpr std::size_t kMissionMarks = 256;  // the first ones are kept; marksDropped counts the rest

struct MissionSummary {
    MissionOutcome outcome = MissionOutcome::kSetupFailed;
    std::string setupError;
    msg::CallHomeReason callHome = msg::CallHomeReason::kNone;
    std::string callHomeText;   // why, in the flight software's words (its call-home event)
    double outcomeTimeS = 0.0;  // when the flight software published the outcome (timed out: the end)
    double endTimeS = 0.0;      // simulated time when the run stopped
    double wallTimeS = 0.0;
    // --pace: the factor, the frames paced, those reached after their due
    // wall time (run at once, without sleeping) and the most one was late.
    double pace = 0.0;
    std::uint64_t pacedFrames = 0;
    std::uint64_t framesBehind = 0;
    double behindMaxMs = 0.0;
    // --udp-telemetry: where the UDP link sent, its command port as bound and
    // its counters at the end (undeliverable: ICMP "port unreachable" reports,
    // nothing listening there; also in errors).
    bool udpLink = false;
    std::string udpTelemetry;  // "HOST:PORT"
    std::string udpCommands;   // "ADDR:PORT" as bound
    hal::PacketLinkStats udpStats{};
    std::uint32_t udpUndeliverable = 0;
    double goalX = 0.0;  // a plan mission: its latest drive's goal
    double goalY = 0.0;
    bool planMission = false;
    msg::PlanExecutiveStatusMsg planExec{};  // the plan executive's last status (a plan mission's verdict)

    // What the flight software published (PlanStatusMsg, mode) and its counters.
    msg::DeliberativeState finalState = msg::DeliberativeState::kIdle;
    std::uint8_t finalMode = 0;
    bool interlockTripped = false;
    std::uint32_t plansMade = 0;
    // Site mode (PlanStatusMsg, as PLAN telemetry shows them).
    bool siteMode = false;
    std::uint32_t routesFound = 0;
    std::uint32_t horizonsReached = 0;
    std::uint32_t horizonsDrivenThrough = 0;  // the next horizon planned while driving, its leg sent at once
    std::uint32_t horizonStops = 0;           // stopped at the end to plan the next horizon
    std::uint32_t lookAheadsStarted = 0;
    std::uint32_t lookAheadsDropped = 0;
    double planLengthM = 0.0;
    double riskBound = 0.0;
    double riskInForce = 0.0;
    double riskUsed = 0.0;
    std::uint32_t legsSent = 0;
    std::uint32_t legsAchieved = 0;
    std::uint32_t failUps = 0;
    std::uint32_t replans = 0;
    std::uint32_t boundRelaxations = 0;
    std::uint32_t riskRelaxations = 0;
    std::uint32_t callHomes = 0;
    std::uint32_t habitualReplans = 0;
    std::uint32_t commandsAccepted = 0;
    std::uint32_t commandsRejected = 0;

    // The scenario's task stalls, as the ground saw them (EXEC_SET_TASK sent,
    // the row's runs from TASK_TIMING: up to a second old).
    std::uint32_t taskStallCommands = 0;   // EXEC_SET_TASK sent for task_stall faults (disable and enable)
    double taskStallTimeS = -1.0;          // the first disable (-1: none)
    int stalledRow = -1;                   // its row
    std::uint32_t stalledRowRunsAtStall = 0;  // TASK_TIMING.runs of the row when it was disabled
    std::uint32_t stalledRowRunsAtEnd = 0;    // ... at the end of the run

    // Fault protection, as the operator sees it: its events and its hold.
    bool faultProtectionCalledHome = false;  // the call home was fault protection's (event 941)
    std::uint32_t responsesStarted = 0;      // events 930
    std::uint32_t responsesRecovered = 0;    // events 932
    std::uint32_t responsesGaveUp = 0;       // events 933
    std::uint32_t recoveryActions = 0;       // events 931 (drive fault reset / node reset), 935 (task restart), 942 (replan)
    std::uint32_t holdsReleased = 0;         // MissionHoldMsg resumeCount at the end
    double firstResponseTimeS = -1.0;        // first event 930 (-1: none)
    double firstHoldTimeS = -1.0;            // first MissionHoldMsg with a reason set
    double lastResumeTimeS = -1.0;           // last hold release
    std::array<MissionMark, kMissionMarks> marks{};  // in time order
    std::size_t markCount = 0;
    std::size_t marksDropped = 0;
    std::size_t marksUnattributed = 0;  // raise, response and action marks with faultId 0 (no telemetry named them)
    // The first mark of a kind at or after timeS (nullptr: none).
    const MissionMark* firstMark(MarkKind kind, double timeS) const;
    // ... and about fault faultId; how many marks of a kind are about it.
    const MissionMark* firstMark(MarkKind kind, double timeS, std::uint8_t faultId) const;
    std::size_t countMarks(MarkKind kind, std::uint8_t faultId) const;
    // Whether the mission hold was in force just before timeS (its last change
    // before timeS set it).
    bool heldBefore(double timeS) const;

    // The simulator's truth at the end.
    double finalX = 0.0;
    double finalY = 0.0;
    double finalHeadingDeg = 0.0;
    double goalDistanceM = 0.0;  // from the final position to the goal
    double distanceM = 0.0;      // path length driven
    std::uint32_t collisions = 0;
    double leastClearanceM = 0.0;  // least gap between the footprint disc and any rock, hidden ones included
    double energyWh = 0.0;
    double stateOfCharge = 0.0;

    // The ten points and the rest of the mission as the report has it
    // (points, verdict, legs, decisions, plans, tracks, timing).
    ground::MissionRecord record;
    bool tenPointsInOrder = false;
    std::string reportPath;   // written files ("" when none)
    std::string mapPath;
    std::string reportError;  // why they could not be written
};

void printMissionSummary(const MissionSummary& summary, std::FILE* out);

// Names as the console and the summary print them.
const char* deliberativeStateName(msg::DeliberativeState state);      // "EXECUTING", "CALLED HOME", ...
const char* planExecutiveStateName(msg::PlanExecutiveState state);    // "dispatching", "complete", ...
std::string planName(const msg::PlanExecutiveStatusMsg& status);      // the plan's name, as the status carries it

}  // namespace rse::sim

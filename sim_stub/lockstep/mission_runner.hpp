// The autonomous mission in lockstep (rse-demo, `make demo`): the flight
// software and the simulator booted on one virtual clock (LockstepRig), the
// drives brought up, then the operator's commands - the scenario's COARSE_MAP,
// SET_MODE AUTONOMOUS and GOTO x,y,risk (or, for a plan mission, SET_RISK_BOUND
// and the plan as PLAN_LOAD chunks and PLAN_START), authenticated with the lab
// key - through the in-memory ground link (MemoryGround), never on the
// software bus. The run lasts until the deliberative layer publishes
// (PlanStatusMsg) that every goal is reached or that it called home (a plan
// mission: until the plan executive publishes its plan complete or failed),
// or fault protection calls home, plus kMissionTailNs so the last events
// reach the console; or until the duration. The simulator's truth is read only for the
// summary at the end (and the report's driven track and hidden rocks).
//
// By default the frames run as fast as the CPU allows; MissionOptions::pace
// paces them against the wall clock, and the UDP options add rse-fsw's UDP
// ground link beside the in-memory one, so a ground (rse-ground watch, the
// mission control display) receives the telemetry as it would a rover's.
//
// The ten points of the RSE demonstration are read from the flight software's
// events and plan status as they come (MissionRecorder, ground/mission_points.hpp),
// printed as "POINT n" lines, judged ("ten points: all in order" or what is
// missing or out of order) and written with the rest of the mission to
// <reportDir>/report.md and <reportDir>/map.svg (ground/mission_report.hpp).
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "fsw/core/clock.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "ground/mission_record.hpp"
#include "hal/link/packet_link.hpp"
#include "sim_stub/scenario/scenario.hpp"

namespace rse::sim {

class LockstepRig;

constexpr const char* kDefaultMissionScenario = "sim_stub/scenarios/demo_mission.toml";
constexpr core::TimeNs kMissionTailNs = 2 * core::kNsPerSec;
constexpr const char* kDefaultReportDir = "build/mission";
// A scenario without [mission]: the demo's goal and duration.
constexpr double kDefaultGoalX = 20.0;
constexpr double kDefaultGoalY = 0.0;
constexpr double kDefaultMissionDurationS = 180.0;
// --pace: the factors over real time accepted.
constexpr double kMinPace = 0.1;
constexpr double kMaxPace = 1000.0;
constexpr const char* kDefaultUdpCommandHost = "127.0.0.1";

// What the mission is: the command line's (parseMissionArgs), and where it
// says nothing, the scenario's own [mission] (applyScenarioMission, which
// runMission calls once the scenario is loaded): a goal (GOTO) or a mission
// plan (PLAN_LOAD, PLAN_START) at a risk bound, and a duration.
struct MissionOptions {
    std::string scenarioPath = kDefaultMissionScenario;
    bool clearFaults = false;  // --no-faults: the scenario's faults left out
    double goalX = kDefaultGoalX;  // --goto X,Y[,RISK], or the scenario's
    double goalY = kDefaultGoalY;
    double risk = kDefaultMissionRiskBound;  // GOTO's, or a plan mission's SET_RISK_BOUND
    // Simulated seconds, boot included (--duration); 0: the scenario's
    // duration_s when it has a [mission], else kDefaultMissionDurationS.
    double durationS = 0.0;
    // --command-at SECONDS: SET_MODE and GOTO (or the plan) wait until this
    // simulated time (0: as soon as the drives are up and the map uploaded,
    // about 0.5 s). A ground on a real bus commands later (the vcan mission's
    // GOTO came at about 2 s); this runs the lockstep mission so.
    double commandAtS = 0.0;
    bool quiet = false;        // no console lines (the summary is still written)
    // --report DIR: report.md and map.svg there; "" writes none. rse-demo's
    // main (missionMain) makes it kDefaultReportDir unless --no-report is given;
    // runMission itself writes only when told where.
    std::string reportDir;
    bool noReport = false;     // --no-report
    bool anyOutcome = false;   // --any-outcome: exit 0 even when the ten points are not all in order
    // The GOTO argument bytes (the ground's encoder): --goto's, or empty for
    // the scenario's goal (or the default, 20,0,1e-3).
    std::vector<std::uint8_t> gotoArgs;
    // A plan mission (the scenario's [mission] plan_file, when no --goto):
    // the text and the file it came from.
    std::string planText;
    std::string planFile;
    // Tests and benchmarks: changes to the loaded scenario (seed, faults, start)
    // before the rig is built; applied after --no-faults.
    std::function<void(Scenario&)> editScenario;
    // Changes to what the operator uplinks as COARSE_MAP (by default the
    // scenario's site and known rocks): an orbital survey that covers less
    // than the world, a rock the survey placed wrong.
    std::function<void(Scenario&)> editUplinkedMap;
    // --pace F: the frames paced against the wall clock, F times faster than
    // real time (frame k of the run due at start + k x 10 ms / F; a frame
    // reached late runs at once and is counted, MissionSummary::framesBehind).
    // 0: as fast as the CPU allows (the default, and rse-montecarlo's).
    double pace = 0.0;
    // --udp-telemetry HOST:PORT: rse-fsw's UDP ground link (hal::UdpPacketLink)
    // added to the flight software beside the in-memory ground, so every
    // telemetry packet and event also goes to HOST:PORT as datagrams (for
    // rse-ground watch / serve). Empty host: no UDP link.
    std::string udpTelemetryHost;
    std::uint16_t udpTelemetryPort = 0;
    // --udp-commands [ADDR:]PORT: where that link takes commands (default
    // address 127.0.0.1). The link always binds a command socket; without this
    // option it binds 127.0.0.1 port 0, a port the kernel picks and nobody is told.
    std::string udpCommandHost = kDefaultUdpCommandHost;
    std::uint16_t udpCommandPort = 0;
    // Tools (rse-montecarlo): called once the rig is up and then after every
    // frame, to read what they measure of the flight software and the
    // simulator; it must change neither.
    std::function<void(LockstepRig&)> onFrame;
};

enum class ParseOutcome : std::uint8_t { kRun, kHelp, kUsageError };

// rse-demo's command line (argv[0] is the program). The goal is checked with
// the ground's command encoder (the dictionary's ranges), as rse-ground would;
// on kUsageError *error says why.
ParseOutcome parseMissionArgs(int argc, const char* const* argv, MissionOptions* options, std::string* error);
// Fills what the command line left open from the scenario's [mission]: the
// duration when 0; the goal and risk bound (encoded as GOTO) or the plan when
// neither gotoArgs nor planText is set; without [mission], 20,0,1e-3 and
// 180 s. False (why in *error) when the goal does not encode.
bool applyScenarioMission(const Scenario& scenario, MissionOptions* options, std::string* error);
void printMissionUsage(std::FILE* out);

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
    // wall time (run at once, without sleeping) and by how much the latest was late.
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

// Runs the mission. out gets the narration, the console (unless quiet), the
// mission summary and the flight software's timing summary (nullptr: nothing).
MissionSummary runMission(const MissionOptions& options, std::FILE* out);
void printMissionSummary(const MissionSummary& summary, std::FILE* out);

// rse-demo itself: 0 when the mission ran and showed the ten points in order
// (or ran at all, with --any-outcome) or for --help, 3 when it ran but the ten
// points were not all seen in order, 2 for a bad command line, 1 when the
// setup failed or the report could not be written.
int missionMain(int argc, const char* const* argv, std::FILE* out, std::FILE* err);

}  // namespace rse::sim

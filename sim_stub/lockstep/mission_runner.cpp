#include "sim_stub/lockstep/mission_runner.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/mission_report.hpp"
#include "hal/link/udp_packet_link.hpp"
#include "sim_stub/cli/command_line.hpp"
#include "sim_stub/lockstep/flight_watch.hpp"
#include "sim_stub/lockstep/frame_pacer.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/map_upload.hpp"
#include "sim_stub/lockstep/memory_ground.hpp"
#include "sim_stub/lockstep/mission_recorder.hpp"
#include "sim_stub/lockstep/plan_uplink.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

namespace rse::sim {

namespace {

constexpr core::TimeNs kDrivesUpLimitNs = 3 * core::kNsPerSec;
constexpr core::TimeNs kModeAckLimitNs = core::kNsPerSec;

double seconds(core::TimeNs t) { return static_cast<double>(t) * 1e-9; }

// The demo's own lines, stamped like the console's.
void say(std::FILE* out, LockstepRig& rig, const std::string& text) {
    if (out != nullptr) {
        std::fprintf(out, "[%10.3f] DEMO %s\n", seconds(rig.clock().now()), text.c_str());
        std::fflush(out);
    }
}

// The scenario's faults as the opening line lists them.
std::string describeFaults(const Scenario& s, const MissionOptions& o) {
    std::string text;
    if (o.clearFaults) {
        text += "; faults cleared (--no-faults)";
    } else if (s.faults.empty()) {
        text += "; no faults";
    }
    char line[512];
    for (const FaultSpec& f : s.faults) {
        const bool onWheel = f.type == FaultType::kMotorDegradation || f.type == FaultType::kMotorFailure ||
                             f.type == FaultType::kDriveHeartbeatLoss || f.type == FaultType::kDriveCrash;
        if (f.type == FaultType::kTaskStall) {
            const std::string task = f.taskName.empty() ? "row " + std::to_string(f.taskRow) : f.taskName;
            std::snprintf(line, sizeof line, "; fault task_stall of %s at %.1f s", task.c_str(), seconds(f.at));
        } else {
            std::snprintf(line, sizeof line, "; fault %s%s%s at %.1f s", toString(f.type), onWheel ? " on " : "",
                          onWheel && f.wheel < msg::kWheelCount ? msg::wheelName(f.wheel) : "", seconds(f.at));
        }
        text += line;
    }
    return text;
}

// The opening line: the scenario, the mission and the faults.
std::string describeScenario(const Scenario& s, const MissionOptions& o) {
    std::size_t hidden = 0;
    for (const Obstacle& ob : s.obstacles) {
        hidden += ob.known ? 0 : 1;
    }
    char line[512];
    char mission[160];
    if (o.planText.empty()) {
        std::snprintf(mission, sizeof mission, "goal (%.2f, %.2f)", o.goalX, o.goalY);
    } else {
        std::snprintf(mission, sizeof mission, "plan %s (%zu B)", o.planFile.c_str(), o.planText.size());
    }
    std::snprintf(line, sizeof line, "scenario %s (%s): start (%.2f, %.2f), %zu rocks (%zu hidden), %s risk bound "
                  "%.3g, up to %.0f s",
                  s.name.c_str(), o.scenarioPath.c_str(), s.start.x, s.start.y, s.obstacles.size(), hidden, mission,
                  o.risk, o.durationS);
    return line + describeFaults(s, o);
}

// The scenario's task stalls as the operator's commands: each is sent as
// EXEC_SET_TASK through the ground link (MemoryGround), narrated and timed.
class ScheduledTaskCommands final : public FlightTaskCommander {
public:
    ScheduledTaskCommands(MemoryGround& ground, LockstepRig& rig, std::FILE* out)
        : ground_(ground), rig_(rig), out_(out) {}
    bool setFlightTaskEnabled(std::size_t row, const std::string& name, bool enabled) override {
        const bool sent = ground_.setFlightTaskEnabled(row, name, enabled);
        const std::size_t sentRow = ground_.lastTaskRow();
        char line[160];
        if (!sent) {
            std::snprintf(line, sizeof line, "scenario task_stall: EXEC_SET_TASK for %s%s NOT sent (task unknown to "
                          "the ground, or the link full)", name.empty() ? "row " : "", name.empty()
                          ? std::to_string(row).c_str() : name.c_str());
            say(out_, rig_, line);
            return false;
        }
        std::snprintf(line, sizeof line, "ground: EXEC_SET_TASK row=%zu (%s) enabled=%d (scenario task_stall)", sentRow,
                      ground_.task(sentRow).name, enabled ? 1 : 0);
        say(out_, rig_, line);
        if (!enabled && disabledAtS_ < 0.0) {
            disabledAtS_ = seconds(rig_.clock().now());
            row_ = sentRow;
            runsAtDisable_ = ground_.task(sentRow).runs;
        }
        return true;
    }
    void fill(MissionSummary* s) const {
        s->taskStallCommands = ground_.taskCommandsSent();
        s->taskStallTimeS = disabledAtS_;
        if (disabledAtS_ >= 0.0) {
            s->stalledRow = static_cast<int>(row_);
            s->stalledRowRunsAtStall = runsAtDisable_;
            s->stalledRowRunsAtEnd = ground_.task(row_).runs;
        }
    }

private:
    MemoryGround& ground_;
    LockstepRig& rig_;
    std::FILE* out_;
    double disabledAtS_ = -1.0;
    std::size_t row_ = 0;
    std::uint32_t runsAtDisable_ = 0;
};

// One lockstep mission, in the order run() takes its steps: the set-up (the
// scenario, the mission, the rig), the ground links, the flight software
// started and watched, the drives up and the map uplinked, the operator's
// commands, the frames to the outcome, then the summary and the record. A
// step that fails ends the run as "setup failed" with its reason.
//
// The members are destroyed in reverse order: the UDP link after the rig,
// whose flight software keeps a pointer to it; the task commands before it.
class MissionRun {
public:
    MissionRun(const MissionOptions& options, std::FILE* out) : o_(options), out_(out) {}
    MissionSummary run();

private:
    bool setUp();
    bool addGroundLinks();
    bool addUdpLink();
    bool startFlightSoftware();
    void service();
    bool bringUpDrivesAndMap();
    bool commandMission();
    void flyToOutcome();
    void judgeOutcome();
    void collectSummary();
    void collectTruth();
    void recordMission();
    void printEnd() const;
    bool fail(const std::string& why);

    MissionOptions o_;  // the command line's, completed from the scenario's [mission]
    std::FILE* out_;
    const std::chrono::steady_clock::time_point wallStart_ = std::chrono::steady_clock::now();
    MissionSummary summary_;
    Scenario scenario_;
    // --udp-telemetry's link (on the heap: its receive batch is 20 kB).
    std::unique_ptr<hal::UdpPacketLink> udpLink_;
    // About 2.5 MB (the flight software's planners and the console buffer): on the heap.
    std::unique_ptr<LockstepRig> rig_;
    MemoryGround ground_;
    std::optional<FlightWatch> watch_;
    std::optional<MissionRecorder> recorder_;
    FramePacer pacer_{0.0};
    std::optional<ScheduledTaskCommands> taskCommands_;
    std::uint32_t planGoals_ = 0;  // the plan goals seen: a plan mission's goal is its latest drive's
};

MissionSummary MissionRun::run() {
    if (!setUp() || !addGroundLinks() || !startFlightSoftware() || !bringUpDrivesAndMap() || !commandMission()) {
        return summary_;
    }
    flyToOutcome();
    collectSummary();
    collectTruth();
    recordMission();
    printEnd();
    return summary_;
}

bool MissionRun::fail(const std::string& why) {
    summary_.outcome = MissionOutcome::kSetupFailed;
    summary_.setupError = why;
    return false;
}

// The scenario and the mission (the command line's over the scenario's own
// [mission]); a plan checked on the ground; the scenario's changes; the rig.
bool MissionRun::setUp() {
    std::string error;
    if (!tryLoadScenarioFile(o_.scenarioPath, &scenario_, &error)) {
        return fail(error);
    }
    if (!applyScenarioMission(scenario_, &o_, &error)) {
        return fail(error);
    }
    summary_.planMission = !o_.planText.empty();
    if (summary_.planMission && !planPassesGroundCheck(o_, &error)) {
        return fail(o_.planFile + ": " + error);
    }
    summary_.goalX = summary_.planMission ? scenario_.start.x : o_.goalX;  // a plan's: its drives' (service)
    summary_.goalY = summary_.planMission ? scenario_.start.y : o_.goalY;
    if (o_.clearFaults) {
        scenario_.faults.clear();
    }
    if (o_.editScenario) {
        // An edit may draw a new field (rse-montecarlo: a field per seed) that
        // does not fit: a setup failure with its reason, as loading would give.
        try {
            o_.editScenario(scenario_);
        } catch (const ScenarioError& e) {
            return fail(e.what());
        }
    }
    rig_ = std::make_unique<LockstepRig>(scenario_);
    return true;
}

// The in-memory ground, then --udp-telemetry's link.
bool MissionRun::addGroundLinks() {
    if (!core::isOk(rig_->fsw().addGroundLink(&ground_.link()))) {
        return fail("the in-memory ground link could not be added");
    }
    return o_.udpTelemetryHost.empty() || addUdpLink();
}

// rse-fsw --udp's link, opened and added as rse-fsw does it (fsw/app/main.cpp),
// after the in-memory ground: every telemetry packet goes to both. It counts as
// always having room (a datagram leaves at once), so events are still offered
// only as fast as the in-memory ground's queue takes them, as without it.
bool MissionRun::addUdpLink() {
    app::FswApp& fsw = rig_->fsw();
    udpLink_ = std::make_unique<hal::UdpPacketLink>(fsw.events());
    if (!core::isOk(udpLink_->open(o_.udpCommandHost.c_str(), o_.udpCommandPort, o_.udpTelemetryHost.c_str(),
                                   o_.udpTelemetryPort))) {
        return fail("cannot open the UDP ground link (commands on " + o_.udpCommandHost + ":" +
                    std::to_string(o_.udpCommandPort) + ", telemetry to " + o_.udpTelemetryHost + ":" +
                    std::to_string(o_.udpTelemetryPort) + "): " + std::strerror(udpLink_->lastErrno()));
    }
    if (!core::isOk(fsw.addGroundLink(udpLink_.get()))) {
        return fail("the UDP ground link could not be added");
    }
    summary_.udpLink = true;
    summary_.udpTelemetry = o_.udpTelemetryHost + ":" + std::to_string(o_.udpTelemetryPort);
    summary_.udpCommands = o_.udpCommandHost + ":" + std::to_string(udpLink_->boundPort());
    return true;
}

// The flight software initialised, its watch and the recorder, the opening
// lines, the pacer and the scenario's task commands.
bool MissionRun::startFlightSoftware() {
    if (!core::isOk(rig_->init(o_.quiet ? nullptr : out_))) {
        return fail("the flight software did not initialise");
    }
    app::FswApp& fsw = rig_->fsw();
    watch_.emplace(fsw.bus(), fsw.events());
    if (!watch_->subscribe()) {
        return fail("no software-bus pipe for the plan status");
    }
    recorder_.emplace(*rig_, out_);
    watch_->forwardTo(&*recorder_);
    say(out_, *rig_, describeScenario(rig_->scenario(), o_));
    if (summary_.udpLink) {
        say(out_, *rig_, "telemetry and events also as UDP datagrams to " + summary_.udpTelemetry +
                             " (rse-fsw's UDP link; its commands on " + summary_.udpCommands +
                             (o_.udpCommandPort == 0 ? ", a port the kernel picked)" : ")"));
    }
    pacer_ = FramePacer(o_.pace);
    if (o_.pace > 0.0) {
        char paceText[120];
        std::snprintf(paceText, sizeof paceText, "paced at %gx real time: a frame every %.3f ms of wall time", o_.pace,
                      seconds(app::kMinorFramePeriod) * 1e3 / o_.pace);
        say(out_, *rig_, paceText);
    }
    taskCommands_.emplace(ground_, *rig_, out_);
    rig_->rover().attachFlightTasks(&*taskCommands_);
    planGoals_ = rig_->planGoalCount();
    return true;
}

// Once a frame: the downlink drained, the watch and the recorder, a plan
// mission's goal, the tool's hook; last the pacer, so its wait is right
// before the next frame.
void MissionRun::service() {
    ground_.drainDownlink();
    watch_->drain();
    if (rig_->planGoalCount() != planGoals_ && summary_.planMission) {
        planGoals_ = rig_->planGoalCount();
        const msg::GoalListMsg& g = rig_->planGoal().goals;
        if (g.count > 0) {
            summary_.goalX = g.goals[0].xM;
            summary_.goalY = g.goals[0].yM;
        }
    }
    recorder_->frame();
    if (o_.onFrame) {
        o_.onFrame(*rig_);
    }
    pacer_.beforeFrame(rig_->fsw().executive().nextFrame());
}

// The drives operational, then the scenario's site and known rocks uplinked
// as the operator's COARSE_MAP.
bool MissionRun::bringUpDrivesAndMap() {
    if (!rig_->runUntil([&] { service(); return rig_->allDrivesOperational(); }, kDrivesUpLimitNs)) {
        return fail("the drives did not become operational");
    }
    Scenario uplinked = rig_->scenario();
    if (o_.editUplinkedMap) {
        o_.editUplinkedMap(uplinked);
    }
    const MapUploadResult map = uploadCoarseMap(uplinked, ground_, *rig_, [this] { service(); });
    if (!map.ok) {
        return fail("the scenario's coarse map was not uploaded: " + map.error);
    }
    char mapLine[200];
    std::snprintf(mapLine, sizeof mapLine,
                  "ground: COARSE_MAP of the scenario (%zu known obstacles, %zu B, CRC-32 0x%08x) loaded in %zu "
                  "TABLE_LOAD chunks, validated, activated",
                  map.obstacles, map.bytes, static_cast<unsigned>(map.crc), map.chunks);
    say(out_, *rig_, mapLine);
    if (!uplinked.usesSiteMap()) {
        return true;
    }
    const MapUploadResult site = uploadSiteMap(uplinked, ground_, *rig_, [this] { service(); });
    if (!site.ok) {
        return fail("the scenario's site map was not uploaded: " + site.error);
    }
    std::snprintf(mapLine, sizeof mapLine,
                  "ground: site map of the scenario (%zu known rocks, %zu B, CRC-32 0x%08x) loaded in %zu MAP_LOAD "
                  "chunks and committed",
                  site.obstacles, site.bytes, static_cast<unsigned>(site.crc), site.chunks);
    say(out_, *rig_, mapLine);
    return true;
}

// At --command-at (or now): SET_MODE AUTONOMOUS, then the GOTO or the plan.
bool MissionRun::commandMission() {
    const auto commandAtNs = static_cast<core::TimeNs>(o_.commandAtS * static_cast<double>(core::kNsPerSec));
    if (commandAtNs > rig_->clock().now() &&
        !rig_->runUntil([&] { service(); return rig_->clock().now() >= commandAtNs; },
                        commandAtNs - rig_->clock().now() + core::kNsPerSec)) {
        return fail("the run did not reach --command-at");
    }
    say(out_, *rig_, "all six drives operational; ground: SET_MODE AUTONOMOUS");
    const auto autonomous = static_cast<std::uint8_t>(cmdtlm::Mode::kAutonomous);
    if (!ground_.setMode(autonomous) ||
        !rig_->runUntil([&] { service(); return watch_->modeIs(autonomous); }, kModeAckLimitNs)) {
        return fail("SET_MODE AUTONOMOUS was not sent or not taken");
    }
    char line[200];
    if (summary_.planMission) {
        std::string error;
        if (!uplinkPlan(o_, ground_, *rig_, *watch_, [this] { service(); }, &error)) {
            return fail(o_.planFile + ": " + error);
        }
        std::snprintf(line, sizeof line, "ground: SET_RISK_BOUND risk=%.3g, plan %s loaded (%zu B, PLAN_LOAD and "
                      "PLAN_START, authenticated, lab key): accepted", o_.risk, o_.planFile.c_str(), o_.planText.size());
    } else {
        if (!ground_.send("GOTO", o_.gotoArgs.data(), o_.gotoArgs.size())) {
            return fail("GOTO could not be sent");
        }
        std::snprintf(line, sizeof line, "ground: GOTO x=%.2f y=%.2f risk=%.3g (authenticated, lab key)", o_.goalX,
                      o_.goalY, o_.risk);
    }
    say(out_, *rig_, line);
    return true;
}

// The frames until the flight software ends the mission or the duration
// passes; the outcome judged and narrated, then the tail; the flight
// software shut down.
void MissionRun::flyToOutcome() {
    const auto durationNs = static_cast<core::TimeNs>(o_.durationS * 1e9);
    const core::TimeNs left = durationNs - rig_->clock().now();
    const bool ended =
        left > 0 && rig_->runUntil([&] { service(); return watch_->ended(summary_.planMission); }, left);
    summary_.outcomeTimeS = seconds(rig_->clock().now());
    if (ended) {
        judgeOutcome();
        // The console task writes events at 10 Hz; the downlink is still drained.
        (void)rig_->runUntil([&] { service(); return false; }, kMissionTailNs);
    } else {
        summary_.outcome = MissionOutcome::kTimedOut;
        char line[200];
        std::snprintf(line, sizeof line, "duration over; deliberative layer %s, plan executive %s",
                      deliberativeStateName(watch_->plan().state), planExecutiveStateName(watch_->planExec().state));
        say(out_, *rig_, line);
    }
    service();
    rig_->fsw().shutdown("mission demo over");
}

// The mission ended: goal reached, plan complete, or called home (and why).
void MissionRun::judgeOutcome() {
    const msg::PlanStatusMsg& plan = watch_->plan();
    const msg::PlanExecutiveStatusMsg& planExec = watch_->planExec();
    const bool fpCalledHome = watch_->faultProtectionCalledHome();
    if (summary_.planMission) {
        summary_.outcome = planExec.state == msg::PlanExecutiveState::kComplete && !fpCalledHome
                               ? MissionOutcome::kPlanComplete
                               : MissionOutcome::kCalledHome;
        summary_.callHome = fpCalledHome ? msg::CallHomeReason::kFaultUnrecovered
                                         : static_cast<msg::CallHomeReason>(planExec.callHomeReason);
    } else {
        summary_.outcome = plan.state == msg::DeliberativeState::kComplete && !fpCalledHome
                               ? MissionOutcome::kGoalReached
                               : MissionOutcome::kCalledHome;
        summary_.callHome = fpCalledHome ? msg::CallHomeReason::kFaultUnrecovered : plan.callHome;
    }
    say(out_, *rig_, fpCalledHome           ? std::string("fault protection called home")
                     : summary_.planMission ? "plan executive: plan " + planName(planExec) + " " +
                                                  planExecutiveStateName(planExec.state)
                                            : std::string("deliberative layer: ") + deliberativeStateName(plan.state));
}

// What the flight software published and counted, the pacer's and the UDP
// link's figures, fault protection's marks and the task commands.
void MissionRun::collectSummary() {
    MissionSummary& s = summary_;
    app::FswApp& fsw = rig_->fsw();
    s.pace = pacer_.factor();
    s.pacedFrames = pacer_.framesPaced();
    s.framesBehind = pacer_.framesBehind();
    s.behindMaxMs = pacer_.behindMaxMs();
    if (s.udpLink) {
        s.udpStats = udpLink_->stats();
        s.udpUndeliverable = udpLink_->undeliverableReports();
    }
    s.callHomeText = watch_->callHomeText();
    watch_->fill(&s);
    taskCommands_->fill(&s);
    rig_->rover().attachFlightTasks(nullptr);  // the commander goes out of scope before the rig

    const msg::PlanStatusMsg& last = watch_->plan();
    const deliberative::DeliberativeCounters& c = fsw.deliberative().counters();
    s.endTimeS = seconds(rig_->clock().now());
    s.finalState = last.state;
    s.planExec = watch_->planExec();
    s.finalMode = watch_->mode();
    s.interlockTripped = fsw.canIo().interlock().tripped();
    s.plansMade = last.plansMade;
    s.siteMode = last.siteMode != 0;
    s.routesFound = last.routesFound;
    s.horizonsReached = last.horizonsReached;
    s.horizonsDrivenThrough = last.horizonsDrivenThrough;
    s.horizonStops = last.horizonStops;
    s.lookAheadsStarted = last.lookAheadsStarted;
    s.lookAheadsDropped = last.lookAheadsDropped;
    s.planLengthM = last.planLengthM;
    s.riskBound = last.riskBound;
    s.riskInForce = last.riskInForce;
    s.riskUsed = last.riskUsed;
    s.legsSent = c.legsSent;
    s.legsAchieved = c.legsAchieved;
    s.failUps = c.failUps;
    s.replans = last.replans;
    s.boundRelaxations = last.boundRelaxations;
    s.riskRelaxations = last.riskRelaxations;
    s.callHomes = last.callHomes;
    s.habitualReplans = fsw.habitual().counters().replans;
    s.commandsAccepted = fsw.commands().counters().accepted;
    s.commandsRejected = fsw.commands().counters().rejected;
}

// The simulator's truth at the end, and the wall time the run took.
void MissionRun::collectTruth() {
    MissionSummary& s = summary_;
    const TruthRecord& truth = rig_->rover().truth();
    s.finalX = truth.pose.x;
    s.finalY = truth.pose.y;
    s.finalHeadingDeg = truth.pose.theta * 180.0 / kPi;
    s.goalDistanceM = std::hypot(truth.pose.x - s.goalX, truth.pose.y - s.goalY);
    s.distanceM = truth.distanceM;
    s.collisions = truth.collisions;
    s.leastClearanceM = truth.leastClearanceM;
    s.energyWh = truth.energyDrawnWh;
    s.stateOfCharge = truth.stateOfCharge;
    s.wallTimeS = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart_).count();
}

// The mission record (the recorder's, with the outcome and the counters) and
// its report and map, when asked for.
void MissionRun::recordMission() {
    MissionSummary& s = summary_;
    ground::MissionRecord& record = s.record;
    record = recorder_->record();
    record.scenario = rig_->scenario().name + " (" + o_.scenarioPath + ")";
    record.goalX = s.goalX;
    record.goalY = s.goalY;
    record.riskBound = o_.risk;
    record.endTimeS = s.endTimeS;
    char outcome[256];
    if (s.outcome == MissionOutcome::kGoalReached) {
        std::snprintf(outcome, sizeof outcome, "goal reached at %.1f s", s.outcomeTimeS);
    } else if (s.outcome == MissionOutcome::kPlanComplete) {
        std::snprintf(outcome, sizeof outcome, "plan %s complete at %.1f s", planName(s.planExec).c_str(),
                      s.outcomeTimeS);
    } else if (s.outcome == MissionOutcome::kCalledHome) {
        std::snprintf(outcome, sizeof outcome, "called home at %.1f s, reason %u: %s", s.outcomeTimeS,
                      static_cast<unsigned>(s.callHome), s.callHomeText.c_str());
    } else {
        std::snprintf(outcome, sizeof outcome, "timed out at %.1f s", s.outcomeTimeS);
    }
    record.outcome = outcome;
    record.legsSent = s.legsSent;
    record.legsAchieved = s.legsAchieved;
    record.failUps = s.failUps;
    record.replans = s.replans;
    record.boundRelaxations = s.boundRelaxations;
    record.riskRelaxations = s.riskRelaxations;
    record.callHomes = s.callHomes;
    record.habitualReplans = s.habitualReplans;
    s.tenPointsInOrder = record.allInOrder;
    if (!o_.reportDir.empty() &&
        !ground::writeMissionFiles(record, o_.reportDir, &s.reportPath, &s.mapPath, &s.reportError)) {
        s.reportPath.clear();
        s.mapPath.clear();
    }
}

// The mission summary, the flight software's timing summary and where the
// report went.
void MissionRun::printEnd() const {
    if (out_ == nullptr) {
        return;
    }
    printMissionSummary(summary_, out_);
    rig_->fsw().printSummary(out_);
    if (!summary_.reportPath.empty()) {
        std::fprintf(out_, "\nmission report: %s\nmission map:    %s\n", summary_.reportPath.c_str(),
                     summary_.mapPath.c_str());
    } else if (!summary_.reportError.empty()) {
        std::fprintf(out_, "\nmission report NOT written: %s\n", summary_.reportError.c_str());
    }
    std::fflush(out_);
}

}  // namespace

MissionSummary runMission(const MissionOptions& options, std::FILE* out) {
    MissionRun run(options, out);
    return run.run();
}

int missionMain(int argc, const char* const* argv, std::FILE* out, std::FILE* err) {
    MissionOptions options;
    std::string error;
    switch (parseMissionArgs(argc, argv, &options, &error)) {
        case ParseOutcome::kHelp:
            printMissionUsage(out);
            return 0;
        case ParseOutcome::kUsageError:
            return cli::usageError(err, "rse-demo", error);
        case ParseOutcome::kRun:
            break;
    }
    if (options.reportDir.empty() && !options.noReport) {
        options.reportDir = kDefaultReportDir;
    }
    const MissionSummary summary = runMission(options, out);
    if (summary.outcome == MissionOutcome::kSetupFailed) {
        std::fprintf(err, "rse-demo: setup failed: %s\n", summary.setupError.c_str());
        return 1;
    }
    if (!options.reportDir.empty() && summary.reportPath.empty()) {
        std::fprintf(err, "rse-demo: mission report not written: %s\n", summary.reportError.c_str());
        return 1;
    }
    if (!summary.tenPointsInOrder && !options.anyOutcome) {
        std::fprintf(err, "rse-demo: %s\n", summary.record.verdict.c_str());
        return 3;
    }
    return 0;
}

}  // namespace rse::sim

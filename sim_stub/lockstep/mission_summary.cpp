#include "sim_stub/lockstep/mission_summary.hpp"

#include <cstring>

#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::sim {

namespace {

const char* modeName(std::uint8_t mode) {
    return mode < cmdtlm::kModeCount ? cmdtlm::toString(static_cast<cmdtlm::Mode>(mode)) : "?";
}

}  // namespace

const char* deliberativeStateName(msg::DeliberativeState s) {
    switch (s) {
        case msg::DeliberativeState::kIdle: return "IDLE";
        case msg::DeliberativeState::kWaiting: return "WAITING";
        case msg::DeliberativeState::kPlanning: return "PLANNING";
        case msg::DeliberativeState::kExecuting: return "EXECUTING";
        case msg::DeliberativeState::kCalledHome: return "CALLED HOME";
        case msg::DeliberativeState::kComplete: return "COMPLETE";
    }
    return "?";
}

const char* planExecutiveStateName(msg::PlanExecutiveState s) {
    switch (s) {
        case msg::PlanExecutiveState::kIdle: return "idle";
        case msg::PlanExecutiveState::kSelecting: return "selecting";
        case msg::PlanExecutiveState::kDispatching: return "dispatching";
        case msg::PlanExecutiveState::kRegenerating: return "regenerating";
        case msg::PlanExecutiveState::kComplete: return "complete";
        case msg::PlanExecutiveState::kFailed: return "failed";
    }
    return "?";
}

std::string planName(const msg::PlanExecutiveStatusMsg& s) {
    return std::string(s.planName, strnlen(s.planName, sizeof s.planName));
}

const MissionMark* MissionSummary::firstMark(MarkKind kind, double timeS) const {
    for (std::size_t i = 0; i < markCount; ++i) {
        if (marks[i].kind == kind && marks[i].timeS >= timeS) {
            return &marks[i];
        }
    }
    return nullptr;
}

const MissionMark* MissionSummary::firstMark(MarkKind kind, double timeS, std::uint8_t faultId) const {
    for (std::size_t i = 0; i < markCount; ++i) {
        if (marks[i].kind == kind && marks[i].timeS >= timeS && marks[i].faultId == faultId) {
            return &marks[i];
        }
    }
    return nullptr;
}

std::size_t MissionSummary::countMarks(MarkKind kind, std::uint8_t faultId) const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < markCount; ++i) {
        n += marks[i].kind == kind && marks[i].faultId == faultId ? 1U : 0U;
    }
    return n;
}

bool MissionSummary::heldBefore(double timeS) const {
    bool held = false;
    for (std::size_t i = 0; i < markCount; ++i) {
        if (marks[i].timeS < timeS && (marks[i].kind == MarkKind::kHoldSet || marks[i].kind == MarkKind::kHoldReleased)) {
            held = marks[i].kind == MarkKind::kHoldSet;
        }
    }
    return held;
}

const char* toString(MissionOutcome outcome) {
    switch (outcome) {
        case MissionOutcome::kSetupFailed: return "setup failed";
        case MissionOutcome::kGoalReached: return "goal reached";
        case MissionOutcome::kCalledHome: return "called home";
        case MissionOutcome::kTimedOut: return "timed out";
        case MissionOutcome::kPlanComplete: return "plan complete";
    }
    return "?";
}

void printMissionSummary(const MissionSummary& s, std::FILE* out) {
    std::fprintf(out, "\n=== rse-demo mission summary ===\n");
    switch (s.outcome) {
        case MissionOutcome::kSetupFailed:
            std::fprintf(out, "outcome:    setup failed: %s\n", s.setupError.c_str());
            return;
        case MissionOutcome::kGoalReached:
            std::fprintf(out, "outcome:    goal (%.2f, %.2f) reached at %.1f s\n", s.goalX, s.goalY, s.outcomeTimeS);
            break;
        case MissionOutcome::kPlanComplete:
            std::fprintf(out, "outcome:    plan %s complete at %.1f s, the last drive's goal (%.2f, %.2f)\n",
                         planName(s.planExec).c_str(), s.outcomeTimeS, s.goalX, s.goalY);
            break;
        case MissionOutcome::kCalledHome:
            std::fprintf(out, "outcome:    called home at %.1f s, reason %u: %s (mode %s%s)\n", s.outcomeTimeS,
                         static_cast<unsigned>(s.callHome), s.callHomeText.c_str(), modeName(s.finalMode),
                         s.interlockTripped ? ", drive interlock tripped" : "");
            break;
        case MissionOutcome::kTimedOut:
            std::fprintf(out, "outcome:    timed out at %.1f s (deliberative layer %s, mode %s)\n", s.outcomeTimeS,
                         deliberativeStateName(s.finalState), modeName(s.finalMode));
            break;
    }
    std::fprintf(out, "time:       %.1f s simulated in %.1f s wall (%.1fx real time)\n", s.endTimeS, s.wallTimeS,
                 s.wallTimeS > 0.0 ? s.endTimeS / s.wallTimeS : 0.0);
    if (s.pace > 0.0) {
        std::fprintf(out, "pace:       %gx real time: %llu frames paced, %llu reached after their due time; behind by "
                          "up to %.1f ms\n",
                     s.pace, static_cast<unsigned long long>(s.pacedFrames),
                     static_cast<unsigned long long>(s.framesBehind), s.behindMaxMs);
    }
    if (s.udpLink) {
        std::fprintf(out, "udp link:   telemetry to %s: %u packets sent, %u dropped, %u errors (%u undeliverable: "
                          "ICMP port unreachable, nothing listening there); commands on %s: %u received\n",
                     s.udpTelemetry.c_str(), s.udpStats.txPackets, s.udpStats.txDropped, s.udpStats.errors,
                     s.udpUndeliverable, s.udpCommands.c_str(), s.udpStats.rxPackets);
    }
    std::fprintf(out, "truth:      final position (%.2f, %.2f) heading %.1f deg, %.2f m from the goal; driven %.2f m; "
                      "collisions %u, least clearance %.2f m; energy %.2f Wh, state of charge %.1f %%\n",
                 s.finalX, s.finalY, s.finalHeadingDeg, s.goalDistanceM, s.distanceM, s.collisions,
                 s.leastClearanceM, s.energyWh,
                 100.0 * s.stateOfCharge);
    std::fprintf(out, "plan:       %u plans made; the last %.2f m, risk used %.3g (bound %.3g, in force %.3g)\n", s.plansMade,
                 s.planLengthM, s.riskUsed, s.riskBound, s.riskInForce);
    if (s.siteMode) {
        std::fprintf(out, "site:       %u route(s); %u horizon ends: %u driven through (the next horizon planned while "
                          "driving), %u stops to plan; %u look-aheads started, %u dropped\n",
                     s.routesFound, s.horizonsReached, s.horizonsDrivenThrough, s.horizonStops, s.lookAheadsStarted,
                     s.lookAheadsDropped);
    }
    if (s.planMission) {
        const msg::PlanExecutiveStatusMsg& p = s.planExec;
        std::fprintf(out, "plan exec:  %s %s: cost %.2f (before the last regeneration %.2f), %u regenerations, %u "
                          "options deprecated; activities %u started, %u completed (%u early, %u late), %u failed; "
                          "%u operator calls\n",
                     planName(p).c_str(), planExecutiveStateName(p.state), p.cost, p.costBefore, p.regenerations,
                     static_cast<unsigned>(p.deprecatedCount), p.activitiesStarted, p.activitiesCompleted,
                     p.activitiesEarly, p.activitiesLate, p.activitiesFailed, p.operatorCalls);
    }
    std::fprintf(out, "legs:       %u sent, %u achieved, %u fail-ups; %u replans, %u bound relaxations, %u risk "
                      "relaxations, %u call homes; habitual replans %u\n",
                 s.legsSent, s.legsAchieved, s.failUps, s.replans, s.boundRelaxations, s.riskRelaxations, s.callHomes,
                 s.habitualReplans);
    std::fprintf(out, "fault prot: %u responses, %u recovered, %u gave up, %u recovery actions, %u holds released",
                 s.responsesStarted, s.responsesRecovered, s.responsesGaveUp, s.recoveryActions, s.holdsReleased);
    if (s.firstResponseTimeS >= 0.0) {
        std::fprintf(out, "; first response %.2f s, first hold %.2f s, last resume %.2f s", s.firstResponseTimeS,
                     s.firstHoldTimeS, s.lastResumeTimeS);
    }
    std::fprintf(out, "\n");
    if (s.taskStallCommands > 0) {
        std::fprintf(out, "task stall: %u EXEC_SET_TASK sent; row %d disabled at %.2f s; its TASK_TIMING runs %u "
                          "then, %u at the end\n",
                     s.taskStallCommands, s.stalledRow, s.taskStallTimeS, s.stalledRowRunsAtStall,
                     s.stalledRowRunsAtEnd);
    }
    std::fprintf(out, "commands:   %u accepted, %u rejected\n", s.commandsAccepted, s.commandsRejected);
    std::fprintf(out, "points:     %s\n", s.record.verdict.c_str());
    for (const ground::MissionPoint& p : s.record.points) {
        if (p.seen) {
            std::fprintf(out, "            %2d at %8.2f s  %s\n", p.number, p.timeS, p.layer.c_str());
        } else {
            std::fprintf(out, "            %2d not seen\n", p.number);
        }
    }
    std::fprintf(out, "\n");
}

}  // namespace rse::sim

#include "fsw/plan_executive/plan_status.hpp"

#include <cstring>

#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

namespace {

void fillFigures(const StatusFigures& f, msg::PlanExecutiveStatusMsg& s) {
    s.timeNs = f.timeNs;
    s.state = f.state;
    s.selectionStatus = static_cast<std::uint8_t>(f.selectionStatus);
    s.lastRefusal = f.plans.lastRefusal;
    s.lastParseError = static_cast<std::uint8_t>(f.plans.lastParse.error);
    s.lastRegeneration = f.regeneration.last;
    s.callHomeReason = f.plans.callHomeReason;
    std::memcpy(s.refusalToken, f.plans.lastParse.token, sizeof s.refusalToken);
    s.refusalToken[sizeof s.refusalToken - 1] = '\0';
    s.refusalLine = f.plans.lastParse.line;
    s.cost = f.cost;
    s.costBefore = f.costBefore;
    s.plansAccepted = f.plans.accepted;
    s.plansRefused = f.plans.refused;
    s.regenerations = f.regeneration.regenerations;
    s.activitiesStarted = f.activities.started;
    s.activitiesCompleted = f.activities.completed;
    s.activitiesEarly = f.activities.early;
    s.activitiesLate = f.activities.late;
    s.activitiesFailed = f.activities.failed;
    s.operatorCalls = f.plans.operatorCalls;
    s.extensionsAccepted = f.extensions.accepted;
    s.extensionsRefused = f.extensions.refused;
    s.lastExtensionRefusal = f.extensions.lastRefusal;
}

void fillPlan(const StatusPlanView& v, msg::PlanExecutiveStatusMsg& s) {
    const Tpn& p = *v.plan;
    std::memcpy(s.planName, p.name, sizeof s.planName);
    s.planName[sizeof s.planName - 1] = '\0';
    s.choiceCount = p.choiceCount;
    s.activityCount = p.activityCount;
    for (std::size_t c = 0; c < p.choiceCount && c < msg::kPlanStatusOptions; ++c) {
        s.options[c] = v.selection->option[c];
    }
    s.deprecatedCount = static_cast<std::uint8_t>(v.deprecatedCount);
    const PlanDispatcher& d = *v.dispatcher;
    if (d.phase() != DispatchPhase::kIdle) {
        s.planTimeMs = v.planMs;
        s.slackMs = d.slackMs(v.planMs);
    }
    for (std::uint16_t a = 0; a < p.activityCount; ++a) {
        const ActivityState st = d.state(a);
        s.running = static_cast<std::uint16_t>(s.running + (st == ActivityState::kRunning ? 1 : 0));
        if (a < msg::kPlanStatusActivities) {
            const auto nibble = static_cast<std::uint8_t>(static_cast<std::uint8_t>(st) & 0x0F);
            s.activityStates[a / 2] =
                static_cast<std::uint8_t>(s.activityStates[a / 2] | (a % 2 == 0 ? nibble : nibble << 4));
        }
    }
}

}  // namespace

void assembleStatus(const StatusFigures& f, const StatusPlanView& v, msg::PlanExecutiveStatusMsg* out) {
    msg::PlanExecutiveStatusMsg& s = *out;
    s = msg::PlanExecutiveStatusMsg{};
    fillFigures(f, s);
    s.slackMs = kInfiniteMs;
    for (std::uint8_t& o : s.options) {
        o = kNoOption;
    }
    if (v.plan != nullptr && v.selection != nullptr && v.dispatcher != nullptr) {
        fillPlan(v, s);
    }
}

void PlanStatusReport::publish(ExecutiveContext& ctx, const StatusFigures& f, const StatusPlanView& v) {
    assembleStatus(f, v, &status_);
    if (!core::isOk(ctx.bus.publish(status_))) {
        ++ctx.publishFailures;
        if (core::isReportableOccurrence(ctx.publishFailures)) {
            ctx.events.report(events::kPublishFailed, core::Severity::kError,
                              "plan_exec: status refused by the bus (%u so far)",
                              static_cast<unsigned>(ctx.publishFailures));
        }
    }
}

}  // namespace rse::plan_executive

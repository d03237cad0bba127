#include "fsw/plan_executive/plan_exec_telemetry.hpp"

#include <algorithm>
#include <cstring>

namespace rse::plan_executive {

void PlanExecTelemetry::takeStatus(const msg::PlanExecutiveStatusMsg& status) {
    msg::PlanExecutiveStatusMsg a = status;
    msg::PlanExecutiveStatusMsg b = status_;
    a.timeNs = b.timeNs = 0;
    a.slackMs = b.slackMs = 0;
    a.planTimeMs = b.planTimeMs = 0;
    changed_ = changed_ || std::memcmp(&a, &b, sizeof a) != 0;
    status_ = status;
}

void PlanExecTelemetry::pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) {
    if (frame.slot == kPlanExecSlot || changed_) {
        changed_ = false;
        send(sink);
    }
}

void PlanExecTelemetry::send(cmdtlm::TelemetrySink& sink) const {
    cmdtlm::PLAN_EXEC_Tlm tlm{};
    const msg::PlanExecutiveStatusMsg& m = status_;
    tlm.state = static_cast<std::uint8_t>(m.state);
    std::memcpy(tlm.plan_name, m.planName, std::min(sizeof tlm.plan_name, sizeof m.planName));
    tlm.selection_status = m.selectionStatus;
    tlm.cost = m.cost;
    tlm.cost_before = m.costBefore;
    tlm.choice_count = m.choiceCount;
    std::memcpy(tlm.options, m.options, std::min(sizeof tlm.options, sizeof m.options));
    tlm.activity_count = m.activityCount;
    tlm.running = m.running;
    std::memcpy(tlm.activity_states, m.activityStates, std::min(sizeof tlm.activity_states, sizeof m.activityStates));
    tlm.deprecated = m.deprecatedCount;
    tlm.slack = m.slackMs;
    tlm.plan_time = m.planTimeMs;
    tlm.plans_accepted = m.plansAccepted;
    tlm.plans_refused = m.plansRefused;
    tlm.regenerations = m.regenerations;
    tlm.started = m.activitiesStarted;
    tlm.completed = m.activitiesCompleted;
    tlm.early = m.activitiesEarly;
    tlm.late = m.activitiesLate;
    tlm.failed = m.activitiesFailed;
    tlm.operator_calls = m.operatorCalls;
    tlm.last_refusal = static_cast<std::uint8_t>(m.lastRefusal);
    tlm.parse_error = m.lastParseError;
    tlm.refusal_line = m.refusalLine;
    std::memcpy(tlm.refusal_token, m.refusalToken, std::min(sizeof tlm.refusal_token, sizeof m.refusalToken));
    tlm.last_regeneration = static_cast<std::uint8_t>(m.lastRegeneration);
    tlm.call_home = m.callHomeReason;
    tlm.extensions = m.extensionsAccepted;
    tlm.extensions_refused = m.extensionsRefused;
    tlm.last_extension_refusal = static_cast<std::uint8_t>(m.lastExtensionRefusal);
    sink.send(tlm);
}

}  // namespace rse::plan_executive

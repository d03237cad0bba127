// The executive's status (docs/plan_executive.md "Status"):
// PlanExecutiveStatusMsg (bus id 0x0191, telemetry PLAN_EXEC) assembled from
// what the parts count and the plan running, and published. The task
// publishes it on any change (ExecutiveContext::changed) and every
// kStatusPeriodRuns runs.
#pragma once

#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/activity_lifecycle.hpp"
#include "fsw/plan_executive/executive_context.hpp"
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/plan_adoption.hpp"
#include "fsw/plan_executive/plan_dispatcher.hpp"
#include "fsw/plan_executive/plan_extension.hpp"
#include "fsw/plan_executive/plan_regeneration.hpp"

namespace rse::plan_executive {

// The figures of the status, each from the part that keeps it.
struct StatusFigures {
    core::TimeNs timeNs = 0;
    msg::PlanExecutiveState state = msg::PlanExecutiveState::kIdle;
    SelectionStatus selectionStatus = SelectionStatus::kRunning;  // of the selection in force
    double cost = 0.0;
    double costBefore = 0.0;
    PlanCounters plans{};
    ActivityCounters activities{};
    RegenerationCounters regeneration{};
    ExtensionCounters extensions{};
};

// The plan running as the status shows it (plan null: none loaded: no name,
// no options, no activities).
struct StatusPlanView {
    const Tpn* plan = nullptr;
    const Selection* selection = nullptr;
    const PlanDispatcher* dispatcher = nullptr;
    std::int32_t planMs = 0;
    std::uint32_t deprecatedCount = 0;  // options the executive deprecated
};

// The message, afresh: the figures; with a plan its name, choices and
// chosen options (the first msg::kPlanStatusOptions), the deprecated
// options, the activities' states (a nibble each, the first
// msg::kPlanStatusActivities) and how many run, and while dispatched the
// plan time and the least slack.
void assembleStatus(const StatusFigures& f, const StatusPlanView& v, msg::PlanExecutiveStatusMsg* out);

class PlanStatusReport {
public:
    // Assembled and published; the bus refusing it is counted
    // (ExecutiveContext::publishFailures) and evented (970, throttled).
    void publish(ExecutiveContext& ctx, const StatusFigures& f, const StatusPlanView& v);
    // The status last assembled.
    const msg::PlanExecutiveStatusMsg& message() const { return status_; }

private:
    msg::PlanExecutiveStatusMsg status_{};
};

}  // namespace rse::plan_executive

// A plan from text to dispatch: selection and adoption (docs/plan_executive.md
// "The task"). A new plan is staged: its text parsed into the Tpn not in use
// and its methods selected there (MethodSelector, kSelectionUnitsPerRun a
// run) while the plan running keeps running. Only a plan with a valid
// selection replaces it: the old plan's running activities cancelled (967),
// the staged Tpn becomes the running one, its time starts (event 0 at the
// run that accepts it: 950) and the dispatcher's check begins
// (kCheckUnitsPerRun rows a run). A regeneration's selection (from
// PlanRegeneration's input) is adopted likewise, the activities carried over
// (963). Anything refused on the way (a parse error, no valid selection, the
// selector refusing the plan; the upload's refusals and busy, reported here)
// is evented with its reason and counted, and leaves the plan running as it
// was. No method left (no selection at a regeneration, the network refused):
// the operator is called (966, SafeRequestMsg with kPlanNoMethod), the plan
// stopped. One selection at a time (SelectionJob).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/activity_lifecycle.hpp"
#include "fsw/plan_executive/component_states.hpp"
#include "fsw/plan_executive/executive_context.hpp"
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/plan_parser.hpp"
#include "fsw/plan_executive/plan_regeneration.hpp"

namespace rse::plan_executive {

// PLAN_EXEC's plan figures: plans accepted and refused, the last refusal
// (with the parser's reason, line and token), operator calls.
struct PlanCounters {
    std::uint32_t accepted = 0;
    std::uint32_t refused = 0;
    msg::PlanRefusal lastRefusal = msg::PlanRefusal::kNone;
    ParseResult lastParse{};
    std::uint32_t operatorCalls = 0;
    std::uint8_t callHomeReason = 0;
};

class PlanAdoption {
public:
    // Work a run: about 0.2 - 0.65 ms of selection on the development host;
    // the dispatcher's check, each row n min-adds (about 0.75 ms at 256 events).
    static constexpr std::uint32_t kSelectionUnitsPerRun = 150000;
    static constexpr std::uint32_t kCheckUnitsPerRun = 4096;

    PlanAdoption(ExecutiveContext& ctx, const ComponentStates& components, ActivityLifecycle& lifecycle,
                 PlanRegeneration& regeneration)
        : ctx_(ctx), components_(components), lifecycle_(lifecycle), regeneration_(regeneration) {}

    // A plan's text (the upload's, PLAN_SHORT's or a goal list's) parsed
    // into the staged Tpn and its selection begun; fromGoals: a goal plan.
    void beginNewPlan(const char* text, std::size_t length, bool fromGoals);
    // The plan running re-selected from where it stands (PlanRegeneration::prepare).
    void startRegeneration(std::int32_t nowMs);
    // A run's slice of the selection under way; finished: adopted or refused.
    void stepSelection();
    // A run's slice of the dispatcher's check; a network found inconsistent calls the operator.
    void stepCheck();
    // PLAN_ABORT (superseded false): the selection dropped, the plan
    // stopped, idle (965); a new plan replacing it (true): 967.
    void abort(bool superseded);
    // No method remains (why): the plan stopped, the operator called (966).
    void callOperator(const char* why);
    // A plan refused (event id with the reason and detail), counted; the plan running kept.
    void refuse(msg::PlanRefusal why, core::EventId id, const char* detail);

    const Selection& selection() const { return selection_; }
    SelectionStatus selectionStatus() const { return selectionStatus_; }
    double cost() const { return cost_; }
    double costBefore() const { return costBefore_; }
    const PlanCounters& counters() const { return counters_; }

private:
    void adoptNewPlan(const SelectionResult& r);
    void adoptRegeneration(const SelectionResult& r);

    ExecutiveContext& ctx_;
    const ComponentStates& components_;
    ActivityLifecycle& lifecycle_;
    PlanRegeneration& regeneration_;
    MethodSelector selector_;
    SelectionParams params_{};
    SelectionInput newInput_{};  // a new plan's selection
    SelectionInput input_{};     // the selection in force was made under this
    Selection selection_{};
    SelectionStatus selectionStatus_ = SelectionStatus::kRunning;
    double cost_ = 0.0;
    double costBefore_ = 0.0;
    std::uint32_t selectionRuns_ = 0;
    std::size_t stagedLength_ = 0;
    bool stagedGoalPlan_ = false;  // the plan being selected was made from the goal list
    PlanCounters counters_{};
};

}  // namespace rse::plan_executive

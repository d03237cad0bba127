#include "fsw/plan_executive/plan_adoption.hpp"

#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

namespace {

const char* refusalName(msg::PlanRefusal r) {
    switch (r) {
        case msg::PlanRefusal::kNone: return "none";
        case msg::PlanRefusal::kParse: return "parse error";
        case msg::PlanRefusal::kBadLength: return "bad length";
        case msg::PlanRefusal::kBadCrc: return "bad CRC-32";
        case msg::PlanRefusal::kGap: return "gap";
        case msg::PlanRefusal::kOverflow: return "overflow";
        case msg::PlanRefusal::kNoUpload: return "nothing uploaded";
        case msg::PlanRefusal::kNoSelection: return "no valid selection";
        case msg::PlanRefusal::kBadPlan: return "bad plan";
        case msg::PlanRefusal::kBusy: return "busy selecting";
    }
    return "?";
}

}  // namespace

void PlanAdoption::refuse(msg::PlanRefusal why, core::EventId id, const char* detail) {
    ++counters_.refused;
    counters_.lastRefusal = why;
    ctx_.changed = true;
    ctx_.events.report(id, core::Severity::kError, "plan_exec: refused (%s): %s; %s", refusalName(why), detail,
                       ctx_.planRunning() ? "the plan running is kept" : "no plan running");
}

void PlanAdoption::beginNewPlan(const char* text, std::size_t length, bool fromGoals) {
    Tpn& staged = ctx_.staged();
    const ParseResult r = parsePlan(text, length, &staged);
    if (r.error != PlanError::kOk) {
        ++counters_.refused;
        counters_.lastRefusal = msg::PlanRefusal::kParse;
        counters_.lastParse = r;
        ctx_.changed = true;
        ctx_.events.report(events::kParseRefused, core::Severity::kError,
                           "plan_exec: plan refused: %s at line %u, token '%s'; %s", toString(r.error),
                           static_cast<unsigned>(r.line), r.token,
                           ctx_.planLoaded ? "the plan running is kept" : "no plan running");
        return;
    }
    newInput_ = SelectionInput{};
    components_.fill(&newInput_);
    regeneration_.clearDeprecations();  // a new plan: the executive has deprecated none of its options
    if (!core::isOk(selector_.start(staged, newInput_, params_))) {
        refuse(msg::PlanRefusal::kBadPlan, events::kSelectionRefused, "method selection refused the plan");
        return;
    }
    stagedLength_ = length;
    stagedGoalPlan_ = fromGoals;
    ctx_.job = SelectionJob::kSelectNew;
    selectionRuns_ = 0;
    const msg::PlanExecutiveState s = ctx_.state;
    if (!ctx_.planLoaded || s == msg::PlanExecutiveState::kIdle || s == msg::PlanExecutiveState::kComplete ||
        s == msg::PlanExecutiveState::kFailed) {
        ctx_.state = msg::PlanExecutiveState::kSelecting;
    }
    ctx_.changed = true;
}

void PlanAdoption::startRegeneration(std::int32_t nowMs) {
    const SelectionInput& input = regeneration_.prepare(nowMs, input_, cost_);
    if (!core::isOk(selector_.start(ctx_.plan(), input, params_))) {
        callOperator("method selection refused the regeneration");
        return;
    }
    ctx_.job = SelectionJob::kRegenerate;
    selectionRuns_ = 0;
    ctx_.state = msg::PlanExecutiveState::kRegenerating;
}

void PlanAdoption::abort(bool superseded) {
    if (!superseded) {
        ctx_.job = SelectionJob::kNone;
    }
    lifecycle_.cancelDispatch();
    if (superseded) {
        ctx_.events.report(events::kPlanSuperseded, core::Severity::kInfo, "plan_exec: plan %s replaced by a new plan",
                           ctx_.plan().name);
        return;
    }
    ctx_.state = msg::PlanExecutiveState::kIdle;
    ctx_.events.report(events::kPlanAborted, core::Severity::kWarning,
                       "plan_exec: PLAN_ABORT: plan %s stopped, selection dropped",
                       ctx_.planLoaded ? ctx_.plan().name : "(none)");
}

void PlanAdoption::stepSelection() {
    ++selectionRuns_;
    if (!selector_.step(kSelectionUnitsPerRun)) {
        return;
    }
    const SelectionResult& r = selector_.result();
    ctx_.events.report(events::kSelectionDone, core::Severity::kInfo,
                       "plan_exec: selection %s, cost %.2f, %llu work units in %u runs", toString(r.status), r.cost,
                       static_cast<unsigned long long>(selector_.work()), static_cast<unsigned>(selectionRuns_));
    const SelectionJob job = ctx_.job;
    ctx_.job = SelectionJob::kNone;
    ctx_.changed = true;
    if (job == SelectionJob::kSelectNew) {
        adoptNewPlan(r);
    } else {
        adoptRegeneration(r);
    }
}

void PlanAdoption::adoptNewPlan(const SelectionResult& r) {
    const Tpn& staged = ctx_.staged();
    if (!r.hasSelection) {
        ++counters_.refused;
        counters_.lastRefusal = msg::PlanRefusal::kNoSelection;
        ctx_.events.report(events::kSelectionRefused, core::Severity::kError,
                           "plan_exec: plan %s refused: no valid selection (%s): inconsistent, unschedulable or every "
                           "method unusable; %s",
                           staged.name, toString(r.status),
                           ctx_.planLoaded ? "the plan running is kept" : "no plan running");
        if (!ctx_.planLoaded || ctx_.state == msg::PlanExecutiveState::kSelecting) {
            ctx_.state = ctx_.planLoaded && ctx_.dispatcher.phase() != DispatchPhase::kIdle
                             ? msg::PlanExecutiveState::kDispatching
                             : msg::PlanExecutiveState::kIdle;
        }
        return;
    }
    if (ctx_.planLoaded && ctx_.dispatcher.phase() != DispatchPhase::kIdle) {
        abort(true);
    }
    ctx_.active = 1 - ctx_.active;
    ctx_.planLoaded = true;
    ctx_.goalPlan = stagedGoalPlan_;
    lifecycle_.newPlan();
    selection_ = r.selection;
    selectionStatus_ = r.status;
    cost_ = r.cost;
    costBefore_ = 0.0;
    input_ = newInput_;
    ctx_.planStartNs = ctx_.now;
    ++counters_.accepted;
    const Tpn& p = ctx_.plan();
    ctx_.events.report(events::kPlanAccepted, core::Severity::kInfo,
                       "plan_exec: plan %s accepted: %u B, %u events, %u activities, %u choices, cost %.2f", p.name,
                       static_cast<unsigned>(stagedLength_), static_cast<unsigned>(p.eventCount),
                       static_cast<unsigned>(p.activityCount), static_cast<unsigned>(p.choiceCount), r.cost);
    ctx_.state = msg::PlanExecutiveState::kDispatching;
    ctx_.checking = core::isOk(ctx_.dispatcher.begin(p, selection_, input_, nullptr));
    if (!ctx_.checking) {
        ctx_.events.report(events::kNetworkRefused, core::Severity::kError,
                           "plan_exec: plan %s: the dispatcher refused the selection", p.name);
        ctx_.state = msg::PlanExecutiveState::kFailed;
    }
}

void PlanAdoption::adoptRegeneration(const SelectionResult& r) {
    const Tpn& p = ctx_.plan();
    if (!r.hasSelection) {
        callOperator(toString(r.status));
        return;
    }
    costBefore_ = cost_;
    cost_ = r.cost;
    selection_ = r.selection;
    selectionStatus_ = r.status;
    input_ = regeneration_.input();
    ctx_.events.report(events::kRegenerated, core::Severity::kWarning,
                       "plan_exec: plan %s regenerated (%s): cost %.2f -> %.2f", p.name, toString(r.status),
                       costBefore_, cost_);
    ctx_.state = msg::PlanExecutiveState::kDispatching;
    // The activities carried over are the dispatcher's own record (completions
    // taken while the selection ran included), read in place.
    ctx_.checking = core::isOk(ctx_.dispatcher.begin(p, selection_, input_, &ctx_.dispatcher.activities()));
    if (!ctx_.checking) {
        ctx_.events.report(events::kNetworkRefused, core::Severity::kError,
                           "plan_exec: plan %s: the dispatcher refused the regenerated selection", p.name);
        callOperator("the regenerated selection was refused");
    }
}

void PlanAdoption::stepCheck() {
    if (!ctx_.dispatcher.stepCheck(kCheckUnitsPerRun)) {
        return;
    }
    ctx_.checking = false;
    ctx_.changed = true;
    if (ctx_.dispatcher.phase() != DispatchPhase::kDispatching && !ctx_.dispatcher.complete()) {
        ctx_.events.report(events::kNetworkRefused, core::Severity::kError,
                           "plan_exec: plan %s: the selected network is not consistent", ctx_.plan().name);
        callOperator("the selected network is not consistent");
    }
}

void PlanAdoption::callOperator(const char* why) {
    ++counters_.operatorCalls;
    counters_.callHomeReason = static_cast<std::uint8_t>(msg::CallHomeReason::kPlanNoMethod);
    lifecycle_.cancelDispatch();
    ctx_.state = msg::PlanExecutiveState::kFailed;
    ctx_.events.report(events::kOperatorCalled, core::Severity::kCritical,
                       "plan_exec: plan %s: no method remains (%s): operator called, rover safed", ctx_.plan().name,
                       why);
    msg::SafeRequestMsg safe{};
    safe.timeNs = ctx_.now;
    safe.reason = msg::CallHomeReason::kPlanNoMethod;
    if (!core::isOk(ctx_.bus.publish(safe))) {
        ++ctx_.publishFailures;
        ctx_.events.report(events::kPublishFailed, core::Severity::kError, "plan_exec: safe request refused by the bus");
    }
}

}  // namespace rse::plan_executive

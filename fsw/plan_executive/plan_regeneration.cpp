#include "fsw/plan_executive/plan_regeneration.hpp"

#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

namespace {

msg::PlanRegeneration regenerationOf(RegenerationReason r) {
    switch (r) {
        case RegenerationReason::kNone: return msg::PlanRegeneration::kNone;
        case RegenerationReason::kLate: return msg::PlanRegeneration::kLate;
        case RegenerationReason::kMissedWindow: return msg::PlanRegeneration::kMissedWindow;
        case RegenerationReason::kEarly: return msg::PlanRegeneration::kEarly;
        case RegenerationReason::kActivityFailed: return msg::PlanRegeneration::kActivityFailed;
    }
    return msg::PlanRegeneration::kNone;
}

}  // namespace

bool PlanRegeneration::checkComponents() {
    const Tpn& p = ctx_.plan();
    std::uint16_t affected = 0;
    std::uint16_t first = kNoIndex;
    for (std::uint16_t a = 0; a < p.activityCount; ++a) {
        const ActivityState st = ctx_.dispatcher.state(a);
        if (st != ActivityState::kWaiting && st != ActivityState::kRunning) {
            continue;
        }
        const Activity& act = p.activities[a];
        bool holds = true;
        for (std::size_t k = 0; k < act.askCount && k < kMaxAsks; ++k) {
            holds = holds && components_.holds(act.asks[k]);
        }
        if (holds) {
            continue;
        }
        ++affected;
        first = first == kNoIndex ? a : first;
        if (st == ActivityState::kRunning) {
            lifecycle_.cancel(a);  // the device stops what the plan no longer runs
            lifecycle_.failed(a, "a component it asks has failed");
        } else if (act.guard.guarded() && act.guard.choice < kMaxChoices && act.guard.option < kMaxOptions) {
            deprecated_[act.guard.choice][act.guard.option] = true;
        }
    }
    if (affected == 0) {
        return false;
    }
    ctx_.events.report(events::kComponentFailed, core::Severity::kWarning,
                       "plan_exec: %u activit%s ask a component no longer so (first %s): regenerating",
                       static_cast<unsigned>(affected), affected == 1 ? "y" : "ies", p.activities[first].name);
    forComponent_ = true;
    componentActivity_ = first;
    return true;
}

const SelectionInput& PlanRegeneration::prepare(std::int32_t nowMs, const SelectionInput& inForce, double costBefore) {
    const Tpn& p = ctx_.plan();
    const RegenerationReason why =
        ctx_.dispatcher.regenerationNeeded() ? ctx_.dispatcher.reason() : RegenerationReason::kNone;
    input_ = inForce;
    for (bool& s : input_.started) {
        s = false;
    }
    components_.fill(&input_);
    for (std::size_t c = 0; c < kMaxChoices; ++c) {
        for (std::size_t o = 0; o < kMaxOptions; ++o) {
            input_.deprecated[c][o] = input_.deprecated[c][o] || deprecated_[c][o];
        }
    }
    ctx_.dispatcher.regenerationInput(nowMs, &input_);
    ++counters_.regenerations;
    counters_.last = forComponent_ ? msg::PlanRegeneration::kComponentFailed : regenerationOf(why);
    if (lifecycle_.takeLateByDevice() && why == RegenerationReason::kActivityFailed) {
        counters_.last = msg::PlanRegeneration::kLate;  // the instrument's own timeout at the ub
    }
    forComponent_ = false;
    ctx_.changed = true;
    const DispatchSnapshot snap = ctx_.dispatcher.snapshot(nowMs);
    const bool component = counters_.last == msg::PlanRegeneration::kComponentFailed;
    const bool late = counters_.last == msg::PlanRegeneration::kLate;
    const std::uint16_t named = component ? componentActivity_ : snap.reasonActivity;
    ctx_.events.report(events::kRegenerating, core::Severity::kWarning,
                       "plan_exec: %s regenerating at %.1f s: %s (%s), cost before %.2f", p.name,
                       static_cast<double>(nowMs) / 1000.0,
                       component ? "component failed" : (late ? "late" : toString(why)),
                       named < p.activityCount ? p.activities[named].name : "-", costBefore);
    return input_;
}

void PlanRegeneration::clearDeprecations() {
    for (auto& row : deprecated_) {
        for (bool& d : row) {
            d = false;
        }
    }
}

std::uint32_t PlanRegeneration::deprecatedCount(std::size_t choices) const {
    std::uint32_t count = 0;
    for (std::size_t c = 0; c < choices && c < kMaxChoices; ++c) {
        for (std::size_t o = 0; o < kMaxOptions; ++o) {
            count += deprecated_[c][o] ? 1U : 0U;
        }
    }
    return count;
}

}  // namespace rse::plan_executive

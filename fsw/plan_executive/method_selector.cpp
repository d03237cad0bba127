// Method selection's interface (method_selector.hpp): the status names, the
// expected-cost model, the STN of a selection, and the selector's start, its
// sliced steps and their phases (base network, presolve, search). The work
// of each phase is in method_selector_analysis.cpp, method_selector_network.cpp
// and method_selector_search.cpp (method_selector_detail.hpp).
#include "fsw/plan_executive/method_selector.hpp"

#include <cmath>

#include "fsw/plan_executive/method_selector_detail.hpp"

namespace rse::plan_executive {

namespace {

constexpr std::size_t kDriveCount = 6;  // Component::kDriveFL .. kDriveRR

bool timeOk(std::int32_t t) { return t >= 0 && t <= kMaxBoundMs; }

core::Status loadStnFrom(const Tpn& plan, const Selection& s, const SelectionInput* input, Stn* stn) {
    if (stn == nullptr || plan.activityCount > kMaxActivities || plan.constraintCount > kMaxConstraints ||
        (input != nullptr && !selector_detail::executionOk(*input, plan.eventCount))) {
        return core::Status::kInvalidArgument;
    }
    core::Status st = stn->reset(plan.eventCount);
    for (std::size_t e = 1; e < plan.eventCount && core::isOk(st); ++e) {
        st = stn->addBounds(0, e, selector_detail::fromStart(input, e));
    }
    for (std::size_t a = 0; a < plan.activityCount && core::isOk(st); ++a) {
        const Activity& act = plan.activities[a];
        st = exists(act.guard, s) ? stn->addBounds(act.from, act.to, act.duration) : st;
    }
    for (std::size_t k = 0; k < plan.constraintCount && core::isOk(st); ++k) {
        const TemporalConstraint& tc = plan.constraints[k];
        st = exists(tc.guard, s) ? stn->addBounds(tc.from, tc.to, tc.bounds) : st;
    }
    return st;
}

}  // namespace

namespace selector_detail {

// Where execution stands is usable: times after the start, within the bounds' range.
bool executionOk(const SelectionInput& input, std::size_t events) {
    bool ok = timeOk(input.notBeforeMs);
    for (std::size_t e = 1; e < events && e < kMaxEvents; ++e) {
        ok = ok && (input.executedAtMs[e] == kInfiniteMs || timeOk(input.executedAtMs[e])) &&
             timeOk(input.notBeforeEventMs[e]);
    }
    return ok;
}

// The start's bounds to event e (SelectionInput "Regeneration"); input null: [0, inf).
Bounds fromStart(const SelectionInput* input, std::size_t e) {
    if (input == nullptr) {
        return Bounds{0, kInfiniteMs};
    }
    const std::int32_t at = input->executedAtMs[e];
    const std::int32_t floor =
        input->notBeforeEventMs[e] > input->notBeforeMs ? input->notBeforeEventMs[e] : input->notBeforeMs;
    return at == kInfiniteMs ? Bounds{floor, kInfiniteMs} : Bounds{at, at};
}

}  // namespace selector_detail

const char* toString(SelectionStatus s) {
    switch (s) {
        case SelectionStatus::kRunning: return "running";
        case SelectionStatus::kSelected: return "selected";
        case SelectionStatus::kSelectedInBudget: return "selected within budget";
        case SelectionStatus::kNoneExists: return "none exists";
        case SelectionStatus::kNoneFound: return "none found in budget";
        case SelectionStatus::kBadPlan: return "bad plan";
    }
    return "?";
}

double expectedCost(const Activity& a, const SelectionInput& input, const SelectionParams& params) {
    bool asksDegraded = false;
    for (std::size_t k = 0; k < a.askCount && k < kMaxAsks; ++k) {
        const Condition& c = a.asks[k];
        asksDegraded = asksDegraded || (!c.planVariable && c.variable < kComponentCount &&
                                        input.components[c.variable] == ComponentState::kDegraded);
    }
    double factor = asksDegraded ? 1.0 + params.degradedPenalty : 1.0;
    if (a.kind == ActivityKind::kDrive) {
        std::size_t degraded = 0;
        for (std::size_t d = 0; d < kDriveCount; ++d) {
            degraded += input.components[d] == ComponentState::kDegraded ? 1U : 0U;
        }
        factor *= 1.0 + params.drivePenalty * static_cast<double>(degraded);
    }
    return a.cost * factor;
}

double selectionCost(const Tpn& plan, const Selection& s, const SelectionInput& input, const SelectionParams& params) {
    double cost = 0.0;
    for (std::size_t a = 0; a < plan.activityCount && a < kMaxActivities; ++a) {
        cost += exists(plan.activities[a].guard, s) ? expectedCost(plan.activities[a], input, params) : 0.0;
    }
    for (std::size_t c = 0; c < plan.choiceCount && c < kMaxChoices; ++c) {
        const std::uint8_t o = s.option[c];
        cost += o < plan.choices[c].optionCount ? plan.choices[c].options[o].cost : 0.0;
    }
    return cost;
}

core::Status loadStn(const Tpn& plan, const Selection& s, Stn* stn) { return loadStnFrom(plan, s, nullptr, stn); }

core::Status loadStn(const Tpn& plan, const Selection& s, const SelectionInput& input, Stn* stn) {
    return loadStnFrom(plan, s, &input, stn);
}

core::Status MethodSelector::start(const Tpn& plan, const SelectionInput& input, const SelectionParams& params) {
    best_ = SelectionResult{};
    stats_ = SelectionStats{};
    chosen_ = Selection{};
    depth_ = 0;
    cost_ = open_ = 0.0;
    queueSize_ = touchedSize_ = 0;
    candidateCount_ = 0;
    dijkstraRunning_ = false;
    thread_ = ThreadState::kIdle;
    plan_ = &plan;
    params_ = params;
    const bool paramsOk = std::isfinite(params.degradedPenalty) && params.degradedPenalty >= 0.0 &&
                          std::isfinite(params.drivePenalty) && params.drivePenalty >= 0.0 && params.workBudget > 0;
    if (!paramsOk || !validate(plan) || !selector_detail::executionOk(input, plan.eventCount)) {
        finish(SelectionStatus::kBadPlan);
        return core::Status::kInvalidArgument;
    }
    n_ = plan.eventCount;
    analyse(input);
    buildNetwork(input);
    if (!baseOk_) {
        reject(baseWhy_);
        finish(SelectionStatus::kNoneExists);
        return core::Status::kOk;
    }
    phase_ = Phase::kBase;
    beginThread(0);
    return core::Status::kOk;
}

bool MethodSelector::step(std::uint32_t maxUnits) {
    const std::uint64_t limit = stats_.work + maxUnits;
    while (phase_ != Phase::kDone && stats_.work < limit && stats_.work < params_.workBudget) {
        action();
    }
    // The slice that spends the budget ends the selection (not the next one).
    if (phase_ != Phase::kDone && stats_.work >= params_.workBudget) {
        finish(best_.hasSelection ? SelectionStatus::kSelectedInBudget : SelectionStatus::kNoneFound);
    }
    return phase_ == Phase::kDone;
}

SelectionStatus MethodSelector::solve(const Tpn& plan, const SelectionInput& input, const SelectionParams& params,
                                      SelectionResult* out) {
    if (core::isOk(start(plan, input, params))) {
        (void)step(UINT32_MAX);  // the budget fits in 32 bits: one call runs to it, or to the end
    }
    if (out != nullptr) {
        *out = best_;
    }
    return best_.status;
}

void MethodSelector::finish(SelectionStatus status) {
    if (dijkstraRunning_) {
        endDijkstra();
    }
    best_.status = status;
    phase_ = Phase::kDone;
}

void MethodSelector::action() {
    switch (phase_) {
        case Phase::kBase:
            threadAction();
            if (thread_ == ThreadState::kFailed) {
                reject(RejectReason::kInconsistent);
                finish(SelectionStatus::kNoneExists);
            } else if (thread_ == ThreadState::kDone) {
                phase_ = Phase::kPresolve;
                presolvePos_ = presolveOption_ = 0;
            }
            break;
        case Phase::kPresolve:
            presolveAction();
            break;
        case Phase::kSearch:
            searchAction();
            break;
        case Phase::kIdle:
        case Phase::kDone:
            ++stats_.work;
            break;
    }
}

}  // namespace rse::plan_executive

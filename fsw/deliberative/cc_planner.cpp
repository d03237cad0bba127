#include "fsw/deliberative/cc_planner.hpp"

#include <cmath>

namespace rse::deliberative {

namespace {
// With optimised allocation the search stops at this share of the work
// budget, leaving the rest to the allocation rounds.
constexpr std::uint64_t kSearchSharePercent = 80;
// The allocation rounds stop at this share; the rest is the finish's (the
// taut path's certified risk: at N = 24, M = 8 about 0.4 M units).
constexpr std::uint64_t kAllocateSharePercent = 97;
}  // namespace

bool CcPlanner::paramsValid(const CcPlannerParams& params) const {
    return params.nodeBudget > 0 && params.iterationBudget > 0 && params.perLpIterations > 0 &&
           params.relativeGap >= 0.0 && params.relativeGap < 0.5 && params.iraRounds <= 50 &&
           params.searchRiskScale >= 1.0 && params.searchRiskScale <= kMaxSearchRiskScale;
}

core::Status CcPlanner::start(const CcProblem& problem, const CcPlannerParams& params) {
    ws_.incumbent.reset();
    phase_ = Phase::kDone;
    search_.resetCounts();
    seeds_.resetCounts();
    allocation_.reset();
    finish_.reset();
    ws_.certifier.stop();
    if (!paramsValid(params) || checkProblem(problem) != core::Status::kOk) {
        ws_.incumbent.setStatus(CcStatus::kBadProblem);
        return core::Status::kInvalidArgument;
    }
    noPlan_ = CcPlan{};
    noPlan_.steps = problem.steps;
    if (ws_.begin(problem, params) != core::Status::kOk) {
        ws_.incumbent.setStatus(CcStatus::kBadProblem);
        return core::Status::kInvalidArgument;
    }
    search_.prepare(ws_.lp.variables());
    seeds_.resetOrder();
    phase_ = (params.seed && ws_.obstacles() > 0) ? Phase::kSeed : Phase::kRoot;
    return core::Status::kOk;
}

core::Status CcPlanner::setSeedHint(const CcPlan& hint) {
    // Only before the first step, and only faces that exist in this problem.
    if (phase_ != Phase::kSeed || !seeds_.setHint(ws_.problem, hint)) {
        return core::Status::kInvalidArgument;
    }
    return core::Status::kOk;
}

CcStatus CcPlanner::solve(const CcProblem& problem, const CcPlannerParams& params, CcPlan* out) {
    (void)start(problem, params);
    // Each call does at least one unit until the phases run out: bounded by
    // the node budget, the seed's and the allocation's solves.
    const std::uint64_t guard = static_cast<std::uint64_t>(params.nodeBudget) + 4U * kMaxPairs + 64U;
    for (std::uint64_t k = 0; k < guard && !finished(); ++k) {
        (void)step(1000);
    }
    if (!finished()) {
        finish();
    }
    if (out != nullptr) {
        *out = ws_.incumbent.best();
    }
    return ws_.incumbent.best().status;
}

bool CcPlanner::step(std::uint32_t maxNodes) {
    std::uint32_t units = 0;
    // Each pass does one unit or moves to a later phase (at most 5 moves).
    const std::uint64_t guard = static_cast<std::uint64_t>(maxNodes) + 8U;
    for (std::uint64_t pass = 0; pass < guard && units < maxNodes && phase_ != Phase::kDone; ++pass) {
        switch (phase_) {
            case Phase::kSeed:
                seedUnit();
                ++units;
                break;
            case Phase::kRoot:
                rootUnit();
                ++units;
                break;
            case Phase::kSearch:
                units += searchUnit() ? 1U : 0U;
                break;
            case Phase::kAllocate:
                if (allocation_.step(ws_, workLeft(kAllocateSharePercent))) {
                    endAllocation();
                }
                ++units;
                break;
            case Phase::kFinish:
                finishUnit();
                ++units;
                break;
            case Phase::kIdle:
            case Phase::kDone:
                phase_ = Phase::kDone;
                break;
        }
    }
    if (phase_ != Phase::kDone && ws_.incumbent.best().status == CcStatus::kOptimal) {
        ws_.incumbent.setStatus(CcStatus::kFeasible);
    }
    return finished();
}

void CcPlanner::seedUnit() {
    // Out of budget: whatever seed is under way is dropped.
    if (seeds_.hintPending() && budgetLeft()) {
        seeds_.runHintUnit(ws_);
    } else if (budgetLeft()) {
        if (!seeds_.runUnit(ws_)) {
            phase_ = Phase::kRoot;
        }
    } else {
        ws_.run.stop();
        phase_ = Phase::kRoot;
    }
}

void CcPlanner::rootUnit() {
    // The presolve always runs (it can prove there is no plan at no LP
    // cost); the root's LP only within the budget.
    if (!ws_.run.running() || budgetLeft()) {
        if (search_.rootUnit(ws_, seeds_.guide())) {
            phase_ = Phase::kSearch;
        }
    } else {
        search_.abandonNode(ws_.run);
        phase_ = Phase::kAllocate;
    }
}

// One unit of the search, within its budgets; false when none was done (the
// search is over).
bool CcPlanner::searchUnit() {
    if (search_.nodes() >= ws_.params.nodeBudget || !budgetLeft()) {
        if (ws_.run.running()) {
            search_.abandonNode(ws_.run);
        }
        search_.stopIncomplete();
        phase_ = Phase::kAllocate;
        return false;
    }
    if (search_.searchUnit(ws_, seeds_.guide())) {
        return true;
    }
    search_.stopExhausted();
    phase_ = Phase::kAllocate;
    return false;
}

bool CcPlanner::budgetLeft() const {
    if (lpIterations() >= ws_.params.iterationBudget) {
        return false;
    }
    return workLeft(ws_.problem.allocation == RiskAllocation::kOptimised ? kSearchSharePercent : 100U);
}

bool CcPlanner::workLeft(std::uint64_t percent) const {
    return ws_.params.workBudget == 0 || work() < 10ULL * percent * ws_.params.workBudget;
}

// The allocation is over: the finish for a certified plan, else done.
void CcPlanner::endAllocation() {
    ws_.run.stop();
    ws_.certifier.stop();
    const CcStatus status = ws_.incumbent.best().status;
    if (status == CcStatus::kNoPlan || status == CcStatus::kBadProblem) {
        phase_ = Phase::kDone;
        return;
    }
    if (!ws_.incumbent.certified()) {
        // The relaxed search's plan never certified within Delta: no plan.
        ws_.incumbent.keep(noPlan_, false);
        phase_ = Phase::kDone;
        return;
    }
    finish_.begin();
    phase_ = Phase::kFinish;
}

void CcPlanner::finishUnit() {
    if (!finish_.step(ws_, workLeft(100U))) {
        return;
    }
    phase_ = Phase::kDone;
    // A relaxed search's proof is about its own budget, not Delta's.
    const bool proven = search_.exhausted() && !search_.incomplete() && ws_.searchScale() == 1.0;
    ws_.incumbent.setStatus(proven ? CcStatus::kOptimal : CcStatus::kFeasible);
}

void CcPlanner::finish() {
    if (phase_ != Phase::kFinish && phase_ != Phase::kDone) {
        endAllocation();
    }
    // Tautening, then at most N evaluation units.
    for (std::size_t k = 0; k < kMaxPlanSteps + 2 && phase_ == Phase::kFinish; ++k) {
        finishUnit();
    }
    phase_ = Phase::kDone;
}

}  // namespace rse::deliberative

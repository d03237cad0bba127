// What the parts of the chance-constrained planner share while one plan runs
// (cc_planner.hpp): the problem and its parameters, the risk budgets, each
// end's delta and margin, the LP and the one solve under way, the best plan,
// the plan under test and its certification, and the work the parts' own
// arithmetic has done. CcPlanner owns one and hands it to the part whose unit
// runs; each part owns the rest of its state.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_incumbent.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_planner_params.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/cc_risk_certifier.hpp"
#include "fsw/deliberative/cc_sliced_lp.hpp"

namespace rse::deliberative {

struct CcWorkspace {
    CcProblem problem{};
    CcPlannerParams params{};
    double riskBudget = 0.0;    // Delta (1 - kRiskSafety): what a plan is certified within
    double searchBudget = 0.0;  // riskBudget x searchScale(): the search's Boole budget
    CcEndMargins margins;
    CcLp lp;
    CcSlicedLp run;             // the LP under way (seed, root, node or allocation round)
    CcIncumbent incumbent;
    // The plan under test: built by the incumbent's offer, an allocation
    // round (kept across its certification's units) or the taut finish.
    CcPlan candidate{};
    CcRiskCertifier certifier;  // the candidate's certified risk, one segment a unit
    std::uint64_t geometryWork = 0;  // the parts' own work (cc_work_units.hpp)

    // A new plan of a problem that passed checkProblem() and valid
    // parameters: no best plan, the budgets, the margins (their work
    // counted from 0), the LP set up (kInvalidArgument when it cannot be),
    // no LP under way, nothing being certified.
    core::Status begin(const CcProblem& given, const CcPlannerParams& settings);

    std::size_t steps() const { return problem.steps; }
    std::size_t obstacles() const { return problem.obstacleCount; }
    // The wide search's scale (kOptimised only; 1 otherwise).
    double searchScale() const {
        return problem.allocation == RiskAllocation::kOptimised ? params.searchRiskScale : 1.0;
    }
    // Pivots the next LP may run: perLpIterations, within what is left of
    // the plan's iterationBudget.
    std::uint32_t lpCap() const {
        const std::uint32_t used = lp.solver().iterations();
        const std::uint32_t left = used < params.iterationBudget ? params.iterationBudget - used : 0U;
        return left < params.perLpIterations ? left : params.perLpIterations;
    }
};

}  // namespace rse::deliberative

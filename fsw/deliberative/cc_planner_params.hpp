// The settings of one plan of the chance-constrained planner (cc_planner.hpp):
// its budgets, its gap tolerance, the allocation rounds and the seeds.
#pragma once

#include <cstdint>

namespace rse::deliberative {

struct CcPlannerParams {
    std::uint32_t nodeBudget = 100000;         // search nodes (LP solves) per plan
    std::uint32_t iterationBudget = 1000000;   // simplex pivots per plan (seed + search)
    std::uint32_t perLpIterations = 2000;      // pivots per LP solve
    std::uint32_t workBudget = 20000;          // thousands of work units (see work()); 0: none
    double relativeGap = 0.002;                // prune bound >= incumbent (1 - gap); [0, 0.5)
    std::uint8_t iraRounds = 12;               // risk allocation rounds (kOptimised), 0..50
    bool seed = true;                          // the visibility-graph seed
    bool layeredSeed = true;                   // the layered seed when those find none (false: ablation only)
    // kOptimised only: the search (even split, presolve, seeds) runs at a
    // Boole budget of Delta x this, in [1, kMaxSearchRiskScale]; its plans
    // are then not certified by their deltas and are handed out only once the
    // allocation has certified one within Delta (plan_risk.hpp). For narrow
    // passages that Boole's bound refuses at Delta (see "Risk allocation").
    double searchRiskScale = 1.0;
};

}  // namespace rse::deliberative

// Checking a plan against its problem, exactly: what the planner verifies
// before it keeps or hands out any plan (cc_planner.hpp), and what every
// caller can check again. Pure functions: no state.
//
// A plan is: means inside the site, mu_0 = start, mu_N = goal, every end on
// its face's side by its delta's margin exactly (no tolerance), deltas in
// (0, 0.5), a finite cost, and its risk certified: the deltas' sum (Boole's
// certificate) <= Delta with riskUsed no less, or else the certified bound
// (plan_risk.hpp, recomputed) <= Delta with riskUsed no less than it.
#pragma once

#include <cstddef>

#include "fsw/core/status.hpp"
#include "fsw/deliberative/cc_problem.hpp"

namespace rse::deliberative {

// Checks a plan against its problem exactly (see above): its shape and
// margins, and its risk: the deltas' sum <= Delta with riskUsed no less, or
// else the certified bound (plan_risk.hpp, recomputed here) <= Delta with
// riskUsed no less than it. kInvalidArgument names nothing: the plan is
// simply not to be used.
core::Status checkPlan(const CcProblem& problem, const CcPlan& plan);

// Everything checkPlan checks but the risk bound, with riskUsed <= riskLimit
// (the planner's search checks its plans at its own, wider, budget);
// *deltaSum gets the sum of the deltas (Boole's certificate).
core::Status checkPlanShape(const CcProblem& problem, const CcPlan& plan, double riskLimit, double* deltaSum);

// The plan claims its deltas' sum (Boole's certificate): riskUsed and each
// segment's share.
void claimBooleRisk(const CcProblem& problem, CcPlan* plan);

// The plan's cost (16-gon length) and Euclidean length from its means,
// summed segment by segment from the start.
void measurePath(std::size_t steps, CcPlan* plan);

}  // namespace rse::deliberative

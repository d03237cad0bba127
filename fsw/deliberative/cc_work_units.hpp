// The work units the chance-constrained planner charges for its own
// arithmetic (cc_planner.hpp, "Bounded and sliceable"): CcPlanner::work() is
// LpSolver::work() plus these, so a plan's work is proportional to its time
// whatever part of the planner does it. Each is an operation's measured cost
// on the x86-64 development host at ~0.45 ns a unit.
#pragma once

#include <cstdint>

namespace rse::deliberative {

// One face score (a dot product and a compare; also a 2x2 solve building a
// segment's own line in the certified risk).
constexpr std::uint64_t kScoreWork = 20;
// One margin or risk: a normal quantile or an erfc.
constexpr std::uint64_t kMarginWork = 200;
// The certified risk (plan_risk.hpp): one normal tail (an erfc, ~8 ns) and
// one bivariate orthant (~145 ns; bench_cc_risk_bounds prints both).
constexpr std::uint64_t kTailWork = 20;
constexpr std::uint64_t kOrthantWork = 320;

}  // namespace rse::deliberative

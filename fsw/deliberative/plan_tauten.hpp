// Pulling a plan's mean path taut without changing what it was planned under.
//
// The path-length objective (the 16-gon norm, cc_problem.hpp) is flat inside
// each of its 16 cones: every path whose steps all point within 11.25 degrees
// of one polygon normal has the same cost. The LP therefore returns whichever
// vertex of that flat optimal face the simplex lands on, and a straight run may
// come back as a shallow zigzag (e.g. 0.7 m off the line over 10 m). That is
// optimal for the planner but wrong for a rover: the habitual layer drives
// to the leg ends, so the zigzag becomes real detours and odd leg ends.
//
// Tautening moves interior means as far as their constraints allow (the full
// way, else the largest of 1/2, 1/4 ... 1/2^kTautHalvings): every end keeps its
// face, its delta and so its margin, with kSafetyM to spare, and the means stay
// on the site. First every mean together towards the straight line from start
// to goal, each at its share of the path's length, by the largest fraction all
// allow (where nothing is in the way the path becomes that line at once; each
// new segment blends an old one with a piece of the line, so no norm of the
// path grows); then sweeps over t = 1 .. N-1, each mean towards the closest
// point of the segment joining its neighbours (the sum of the two segment
// lengths through it is convex along that move and least at its end). So the
// 16-gon cost never rises; the planner still keeps the result only if
// checkPlan passes and the cost did not rise. Faces, deltas, risk used and the
// status are unchanged. It cannot change a face, so a mean pinned by its
// face's margin stays (the flat norm's zigzag round a vertex can remain).
//
// Bounded: kTautHalvings + 1 trials of N - 1 positions, then at most kTautSweeps
// sweeps of N - 1 moves of at most kTautHalvings + 1 trials; a trial checks 2 M
// face constraints.
// Pure: no state.
#pragma once

#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"

namespace rse::deliberative {

constexpr std::uint32_t kTautSweeps = 32;
constexpr std::uint32_t kTautHalvings = 8;

// Returns the number of positions tried (the work done); plan->cost and
// plan->euclideanLengthM are recomputed. A plan without a path is left alone.
std::uint32_t tautenPlan(const CcProblem& problem, CcPlan* plan);

}  // namespace rse::deliberative

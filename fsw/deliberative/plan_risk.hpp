// The certified collision risk of a mean path: an upper bound on the
// probability that the sampled path of cc_problem.hpp's plant meets an
// obstacle, computed from the means alone (no faces, no deltas), tighter than
// the planner's Boole sum over its face ends.
//
// Why. The planner's certificate is P(collision) <= sum of its deltas, one per
// face end (Boole over 2 N M half-plane events). Monte Carlo on the benchmark
// sets (docs/performance.md) shows where that loses: a half-plane reaches past
// its obstacle (a path passing a corner is mostly "beyond" a face whose line
// it crosses nowhere near the obstacle), and the two ends of a segment on one
// face are one correlated event, not two. This bound keeps Boole only across
// (segment, obstacle) pairs and bounds each pair's event much more closely.
//
// One pair: the sampled segment x_t -> x_{t+1} meets convex obstacle i only if,
// for every face j, an end lies strictly on the obstacle's side of j's line:
// collision(t, i) is inside U_j = E_j(t) u E_j(t+1) for every j, where
// E_j(tau) = {a_j . x_tau < b_j} (a segment whose ends are both in a closed
// half-plane stays in it). So
//   P(collision(t, i)) <= min_j P(U_j),   P(U_j) = P(E) + P(E') - P(E n E')
// with P(E n E') a bivariate normal orthant: a_j . x_t and a_j . x_{t+1} are
// jointly Gaussian, correlation sqrt(v_t / v_{t+1}) (v_tau = a' Sigma_tau a;
// Cov(x_t, x_{t+1}) = Sigma_t for the random walk). And with a second face k,
// collision is inside U_j n U_k, the union of the four E_j(tau) n E_k(tau'):
//   P(collision(t, i)) <= sum over tau, tau' in {t, t + 1} of P(E_j(tau) n E_k(tau'))
// (Cov(a . x_tau, c . x_tau') = a' Sigma_min(tau, tau') c), which is what makes
// a corner cheap: beside a corner a point is beyond both faces' lines only
// with the product-like orthant probability. The anchor j is the face with
// the least P(U_j); every other face k is tried; the least bound wins.
// The faces are not the only separating lines: any supporting line of the
// obstacle is one, and past a corner the faces all fail (each end is on the
// obstacle's side of one of the corner's faces) while the line through the
// corner parallel to the segment separates both ends. So the candidates are
// the F faces and that line, built from the mean segment as a nonnegative
// combination of two faces (valid as computed, by weak duality; no vertices);
// it is a function of the means only, so the bound stays a bound.
// Each orthant is bivariateUpperTail() (gaussian.hpp), whose absolute error
// kBivariateAbsError is added per orthant used, so the bound stays an upper
// bound in floating point. An end with no variance (Sigma_0 = 0 at t = 0, or
// sigma = 0) is certain: its event is 0 or 1 and the pair falls back to
// P(E) + P(E') for that face (no orthants).
//
// The plan: P(collision) <= sum over pairs (Boole across pairs). A planner
// plan whose ends meet their delta margins also has P(collision(t, i)) <=
// delta0 + delta1; certifiedPairRisk takes the smaller. planRiskBound is
// independent of the planner's search: checkPlan (cc_planner.hpp) calls it.
//
// Cost: per pair F faces (2 erfc and at most 1 orthant each); unless the
// best face's bound is already below kNegligibleRisk, the segment's line
// (2 x F (F - 1) / 2 2x2 solves, 2 erfc, 1 orthant) and F line pairs of 4
// orthants: at most 9 + 32 orthants; pairs far from their obstacle cost 2 F
// erfc calls only.
// RiskWork counts the calls; the planner charges them as work units. Pure
// functions: no state, no allocation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"

namespace rse::deliberative {

// A pair's bound below this is not refined with face pairs (its share of any
// Delta the planner accepts, >= 1e-12, is nothing).
constexpr double kNegligibleRisk = 1e-30;

struct RiskWork {
    std::uint32_t tails = 0;      // single-end normal tails (erfc)
    std::uint32_t orthants = 0;   // bivariate orthants
    std::uint32_t lineSolves = 0; // 2x2 solves building a segment's own line
};

// Upper bound on P(the sampled segment t meets obstacle i's interior) for
// the means mx[0..N], my[0..N] (t < N, i < M; the problem passed checkProblem).
double pairRiskBound(const CcProblem& problem, const double* meanX, const double* meanY, std::size_t t,
                     std::size_t obstacle, RiskWork* work);

// Sum over obstacles of pairRiskBound for segment t, each capped by capPerPair
// (nullptr: no cap; else capPerPair[i], e.g. a plan's delta0 + delta1).
double segmentRiskBound(const CcProblem& problem, const double* meanX, const double* meanY, std::size_t t,
                        const double* capPerPair, RiskWork* work);

// Sum over all segments; segmentRisk[t] gets each segment's share when not null.
double planRiskBound(const CcProblem& problem, const double* meanX, const double* meanY, double* segmentRisk,
                     RiskWork* work);

// Segment t's certified risk in a plan: per obstacle min(delta0 + delta1,
// pairRiskBound), summed (one unit of the planner's sliced evaluation).
double certifiedSegmentRisk(const CcProblem& problem, const CcPlan& plan, std::size_t t, RiskWork* work);

// A plan's certified risk: per pair min(delta0 + delta1, pairRiskBound), summed
// (its deltas must meet their margins, which checkPlan checks); segmentRisk[t]
// gets each segment's share when not null.
double certifiedPlanRisk(const CcProblem& problem, const CcPlan& plan, double* segmentRisk, RiskWork* work);

}  // namespace rse::deliberative

// A plan's risk against the whole map, not only the obstacles its problem
// held (docs/deliberative.md, "Obstacles left out of the problem").
//
// Why. The planner's problem holds kMaxPlanObstacles obstacles; a map and the
// seen hazards may hold more (MapObstacles: the coarse map's polygons and the
// habitual layer's discs, grown). Before this check the rest were "dropped,
// farthest from the line" and never looked at again: on a held-out boulder
// field the plan's detour round the rocks it held passed 0.0 m from one it had
// dropped, and the rover drove into it with a certificate that never counted
// that rock. A risk bound is a promise against the whole map.
//
// What. For every candidate, plan_risk.hpp's pairRiskBound of each segment
// of the plan's means, summed: an upper bound on P(the sampled path meets that
// obstacle), as the certifier bounds the ones the problem held. The left-out
// candidates' total is added to the plan's certified risk. PlanMaker plans
// with a reserve of the bound for it (kLeftOutShare) and, when the left-out
// obstacles need more, forces the obstacles that matter into the problem (the
// left-out ones the plan came near, and the held ones it came near, so that
// they keep their places) and plans again, or sends no plan.
//
// Time bound: one unit a candidate, at most kMaxPlanSteps pair bounds,
// each at most kPairMaxWork work units (cc_work_units.hpp): kMaxUnitWork, the
// planner's own unit bound. Static: no allocation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/cc_work_units.hpp"
#include "fsw/deliberative/map_problem.hpp"

namespace rse::deliberative {

// The share of the operator's bound kept for the obstacles left out of the
// problem: the planner plans to (1 - kLeftOutShare) Delta when any is left
// out, and the left-out ones together may take at most kLeftOutShare Delta.
constexpr double kLeftOutShare = 0.01;

// Site mode: the rocks far from the plan (docs/deliberative.md, "Rocks far
// from the plan"). A sampled position is x_t = mu_t + e_t with e_t ~ N(0,
// Sigma_t), Sigma_t = Sigma_0 + t sigma^2 I, and a point of the sampled
// segment t is a convex combination of two of them, so its error is at most
// max(|e_t|, |e_t+1|). The rover's disc (radius rho) meets a rock only where
// its centre comes within rho of it; a rock at least reachM = rho + r from
// every segment of the means is met only if some |e_t| >= r, and
//   P(|e_t| >= r) <= P(e' Sigma_t^-1 e >= r^2 / lambda_t) = exp(-r^2 / (2 lambda_t))
// (lambda_t: Sigma_t's largest eigenvalue; the quadratic form is chi-square
// with 2 degrees of freedom). Boole over t = 0 .. N bounds every such rock of
// the map together, however many, by the sum. farRockBound picks r so that the
// sum is at most share; the plan maker makes every rock within reachM a
// candidate (addRocksNearPath) and adds risk to the plan's certified risk.
struct FarRockBound {
    double reachM = 0.0;   // rho + r: rocks at least this far from every segment of the means
    double risk = 0.0;     // ... together meet the sampled path with at most this probability (<= share)
};
FarRockBound farRockBound(const CcProblem& problem, std::size_t steps, double radiusM, double share);

// The share of the left-out share (kLeftOutShare) the rocks far from the plan take.
constexpr double kFarRockShare = 0.1;

class WholeMapCheck {
public:
    // The most work one pair bound does (plan_risk.hpp, "Cost": 2 x 8 + 2
    // tails, 9 + 32 orthants, 2 x 8 x 7 / 2 line solves) and one unit.
    static constexpr std::uint64_t kPairMaxWork = 18 * kTailWork + 41 * kOrthantWork + 56 * kScoreWork;
    static constexpr std::uint64_t kMaxUnitWork = kMaxPlanSteps * kPairMaxWork;

    // Checks plan (its means; problem's plant) against every candidate of
    // obstacles. Both must outlive the check.
    void start(const CcProblem& problem, const CcPlan& plan, const MapObstacles& obstacles);
    // One candidate; true when every one is done. *work grows by the unit's
    // work units.
    bool unit(std::uint64_t* work);
    bool done() const { return next_ >= count_; }

    // The left-out obstacles' risk, summed (the share the plan's certified risk gains).
    double leftOutRisk() const { return total_; }
    std::size_t leftOutCount() const { return leftOut_; }
    // Candidate i's bound (0 when not checked yet).
    double risk(std::size_t candidate) const { return candidate < count_ ? risk_[candidate] : 0.0; }
    // Forces into *obstacles the candidates whose risk is above floor while
    // the forced ones fit in kMaxPlanObstacles: the left-out ones first, worst
    // first, then the held ones (so the ones the plan came near keep their
    // places). The number of left-out ones newly forced: 0 when the next
    // problem would be the same (nothing left out above the floor, or no room).
    std::size_t force(MapObstacles* obstacles, double floor) const;

private:
    CcProblem single_{};   // the problem's plant with one obstacle, the one being checked
    const CcPlan* plan_ = nullptr;
    const MapObstacles* obstacles_ = nullptr;
    std::size_t count_ = 0;
    std::size_t next_ = 0;
    std::size_t leftOut_ = 0;
    double risk_[MapObstacles::kCapacity] = {};
    double total_ = 0.0;
};

}  // namespace rse::deliberative

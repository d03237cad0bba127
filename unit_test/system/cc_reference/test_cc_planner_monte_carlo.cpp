// The flight planner's own plans (fsw/deliberative/cc_planner.hpp, default
// CcPlannerParams) checked by Monte Carlo in make test, host and aarch64: a
// handful of seeded instances (three of the benchmark's provable set at
// Delta = 0.05, one at 1e-3, the corner-cutting box), each planned, then 20 000
// trajectories sampled from the plan's own Gaussian model (cc_monte_carlo.hpp:
// the true plant, whole segments tested against the obstacles). make bench runs
// the same check on 100 instances with 1e5 and more samples.
//
// The statistical margin: a plan passes when its collision count is at most
//   n Delta + 4 sqrt(n Delta (1 - Delta))
// i.e. the empirical rate within Delta plus four binomial standard deviations.
// A plan whose true collision probability were exactly Delta would fail that by
// sampling noise with probability about 1e-4 (normal approximation; about 2e-4
// for n Delta = 20, where the count is nearer Poisson); the samples are seeded,
// so the verdict is the same on every run of one build. The certified bound
// (plan_risk.hpp) the optimised allocation is stretched to keeps the true risk
// a few times below Delta, so the check has room; what it catches is a plan
// whose margins or certificate do not hold (wrong covariance growth, a sign, a
// segment cutting a corner between two waypoints, a bound below the risk).
//
// The negative control shows the check can fail: the same instance planned as
// if there were no uncertainty (Sigma_0 = 0, sigma = 0) hugs the obstacles,
// and under the true noise it collides far above the threshold.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"
#include "unit_test/bench/cc_instances.hpp"
#include "unit_test/bench/cc_monte_carlo.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::test::cc;
using rse::deliberative::CcPlanner;
using rse::deliberative::CcPlannerParams;
using rse::deliberative::CcStatus;
using rse::deliberative::RiskAllocation;

namespace {

constexpr std::size_t kSamples = 20000;

CcPlanner planner;  // ~450 kB: static storage, as in flight
CcPlan plan;

McResult sample(const CcProblem& problem, const double* meanX, const double* meanY, std::uint64_t seed) {
    McOptions options;
    options.samples = kSamples;
    options.seed = seed;
    return monteCarloCollision(problem, meanX, meanY, options);
}

// Plans `problem` with the flight planner and checks the plan by Monte Carlo;
// returns the sampled rate.
double planAndCheck(const char* name, CcProblem problem, RiskAllocation allocation, std::uint64_t seed,
                    double searchRiskScale = 1.0) {
    problem.allocation = allocation;
    CHECK_TEXT(validateProblem(problem).empty(), name);
    CcPlannerParams params;
    params.searchRiskScale = searchRiskScale;
    const CcStatus status = planner.solve(problem, params, &plan);
    CHECK_TEXT(status == CcStatus::kOptimal || status == CcStatus::kFeasible, name);
    CHECK_TEXT(rse::core::isOk(rse::deliberative::checkPlan(problem, plan)), name);
    CHECK_TEXT(plan.riskUsed <= problem.riskBound * (1.0 + 1e-9), name);
    const McResult r = sample(problem, plan.meanX, plan.meanY, seed);
    LONGS_EQUAL(kSamples, r.samples);
    const std::size_t allowed = allowedCollisions(problem.riskBound, r.samples);
    if (r.collisions > allowed) {
        FAIL_TEST((std::string(name) + ": " + std::to_string(r.collisions) + " collisions in " +
                   std::to_string(r.samples) + " trajectories, more than " + std::to_string(allowed) +
                   " allowed at Delta " + std::to_string(problem.riskBound))
                      .c_str());
    }
    return r.rate;
}

}  // namespace

TEST_GROUP(CcPlannerMonteCarlo){};

TEST(CcPlannerMonteCarlo, FlightPlansOfSeededInstancesStayWithinTheirRiskBound) {
    const std::vector<CcProblem> loose = provableSet(0.05, 3);
    planAndCheck("provable 0, Delta 0.05, optimised", loose[0], RiskAllocation::kOptimised, 11);
    planAndCheck("provable 1, Delta 0.05, optimised", loose[1], RiskAllocation::kOptimised, 12);
    planAndCheck("provable 2, Delta 0.05, optimised", loose[2], RiskAllocation::kOptimised, 13);
    planAndCheck("provable 0, Delta 0.05, even split", loose[0], RiskAllocation::kEvenSplit, 11);
    planAndCheck("provable 0, Delta 1e-3, optimised", provableSet(1e-3, 1)[0], RiskAllocation::kOptimised, 14);
    planAndCheck("diagonal box, Delta 0.05, optimised", diagonalBoxInstance(0.05), RiskAllocation::kOptimised, 15);
}

TEST(CcPlannerMonteCarlo, APlanThatIgnoresTheUncertaintyFailsTheSameCheck) {
    const CcProblem truth = provableSet(0.05, 1)[0];
    CcProblem certain = truth;
    certain.startCov[0] = certain.startCov[1] = certain.startCov[2] = certain.startCov[3] = 0.0;
    certain.processSigmaM = 0.0;
    const CcStatus status = planner.solve(certain, CcPlannerParams{}, &plan);
    CHECK(status == CcStatus::kOptimal || status == CcStatus::kFeasible);
    const McResult r = sample(truth, plan.meanX, plan.meanY, 11);
    const std::size_t allowed = allowedCollisions(truth.riskBound, r.samples);
    CHECK_TEXT(r.collisions > 2 * allowed,
               ("a plan without margins collided only " + std::to_string(r.collisions) + " times").c_str());
}

TEST(CcPlannerMonteCarlo, StretchedAllocationsSpendTheirRiskAndStayWithinIt) {
    // The optimised allocation stretched on the certified bound: its plans
    // within Delta by sampling, and their median rate within 10x of Delta
    // (bench_cc_risk_bounds shows what the deltas' sum alone would certify).
    std::vector<double> ratios;
    const std::vector<CcProblem> loose = provableSet(0.05, 5);
    for (std::size_t k = 0; k < loose.size(); ++k) {
        const std::string name = "provable " + std::to_string(k) + ", Delta 0.05";
        ratios.push_back(0.05 / planAndCheck(name.c_str(), loose[k], RiskAllocation::kOptimised, 20 + k));
    }
    const std::vector<HardInstance> hard = hardSet(4);
    for (std::size_t k = 0; k < hard.size(); ++k) {
        const std::string name = "hard " + std::to_string(k);
        const double rate = planAndCheck(name.c_str(), hard[k].problem, RiskAllocation::kOptimised, 30 + k);
        ratios.push_back(rate > 0.0 ? hard[k].problem.riskBound / rate : 1e9);
    }
    CHECK_TEXT(quantile(ratios, 0.5) <= 10.0, ("median Delta / rate " + std::to_string(quantile(ratios, 0.5))).c_str());
}

TEST(CcPlannerMonteCarlo, ANarrowPassageCertifiedByTheWideSearchStaysWithinItsBound) {
    // A wall with a 0.9 m gap, Delta 1e-3: Boole's even split refuses the gap
    // (no plan at scale 1), the wide search certifies a plan through it.
    CcProblem p;
    p.steps = 10;
    p.startX = 0.0, p.startY = 5.0, p.goalX = 20.0, p.goalY = 5.0;
    p.xMin = -2.0, p.xMax = 22.0, p.yMin = -10.0, p.yMax = 20.0;
    p.startCov[0] = p.startCov[3] = 0.01;
    p.processSigmaM = 0.05;
    p.riskBound = 1e-3;
    p.obstacles[0] = boxObstacle(9.0, -10.0, 11.0, 4.55, 1);
    p.obstacles[1] = boxObstacle(9.0, 5.45, 11.0, 20.0, 2);
    p.obstacles[2] = boxObstacle(3.0, 12.0, 5.0, 14.0, 3);
    p.obstacles[3] = boxObstacle(15.0, -6.0, 17.0, -4.0, 4);
    p.obstacleCount = 4;
    p.allocation = RiskAllocation::kOptimised;
    CHECK(planner.solve(p, CcPlannerParams{}, &plan) == CcStatus::kNoPlan);
    const double rate = planAndCheck("narrow gap, wide search", p, RiskAllocation::kOptimised, 41, 8.0);
    CHECK(rate <= p.riskBound);
}

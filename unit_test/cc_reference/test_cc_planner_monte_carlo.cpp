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
// so the verdict is the same on every run of one build. Boole's bound makes the
// planner's true risk well below Delta, so the check has room; what it catches
// is a plan whose margins do not hold (wrong covariance growth, a sign, a
// segment cutting a corner between two waypoints).
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

// The largest collision count a plan at risk bound Delta may show in n samples.
std::size_t allowedCollisions(double delta, std::size_t n) {
    const double nd = static_cast<double>(n);
    return static_cast<std::size_t>(std::floor(nd * delta + 4.0 * std::sqrt(nd * delta * (1.0 - delta))));
}

McResult sample(const CcProblem& problem, const double* meanX, const double* meanY, std::uint64_t seed) {
    McOptions options;
    options.samples = kSamples;
    options.seed = seed;
    return monteCarloCollision(problem, meanX, meanY, options);
}

// Plans `problem` with the flight planner and checks the plan by Monte Carlo.
void planAndCheck(const char* name, CcProblem problem, RiskAllocation allocation, std::uint64_t seed) {
    problem.allocation = allocation;
    CHECK_TEXT(validateProblem(problem).empty(), name);
    const CcStatus status = planner.solve(problem, CcPlannerParams{}, &plan);
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

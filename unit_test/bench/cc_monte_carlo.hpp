// Monte Carlo check of a chance-constrained plan against the true plant of
// fsw/deliberative/cc_problem.hpp, run open loop on the plan's mean steps:
//   x_0 ~ N(mu_0, Sigma_0),  x_{t+1} = x_t + (mu_{t+1} - mu_t) + w_t,  w_t ~ N(0, sigma^2 I)
// A trajectory collides when any of its sampled SEGMENTS x_t -> x_{t+1} (the
// whole segment, exact segment / convex polygon test) meets any obstacle's
// interior. The waypoint count (some x_t inside an obstacle) is kept beside it
// to show what a waypoint-only check misses.
// std::mt19937_64 + std::normal_distribution, seeded: the same numbers for the
// same seed on one platform (the distribution is the standard library's).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"

namespace rse::test::cc {

struct McOptions {
    std::size_t samples = 100000;
    std::uint64_t seed = 1;
    double confidence = 0.95;  // for the upper bounds
};

struct McResult {
    std::size_t samples = 0;
    std::size_t collisions = 0;          // trajectories with a segment meeting an obstacle
    std::size_t waypointCollisions = 0;  // trajectories with a waypoint x_t inside an obstacle
    double rate = 0.0;                   // collisions / samples
    double upperClopperPearson = 0.0;    // one-sided exact upper bound at `confidence`
    double upperWilson = 0.0;            // one-sided Wilson score upper bound
    std::size_t collisionsPerObstacle[kMaxPlanObstacles] = {};  // a trajectory counts once per obstacle it meets
    double seconds = 0.0;                // wall time of the sampling
};

// meanX / meanY hold mu_0 .. mu_N (N = problem.steps); mu_0 should be the
// problem's start (the plant is sampled around the given mu_0 either way).
McResult monteCarloCollision(const CcProblem& problem, const double* meanX, const double* meanY,
                             const McOptions& options = McOptions{});
McResult monteCarloCollision(const CcProblem& problem, const CcPlan& plan,
                             const McOptions& options = McOptions{});

// How many trajectories to sample for a plan with risk bound Delta: at least
// `minimum` and at least 500 / Delta, so that a plan 100x inside Delta still
// shows about 5 collisions (1e5 at Delta = 0.05, 5e5 at 1e-3).
std::size_t monteCarloSamples(double riskBound, std::size_t minimum = 100000);

// The most collisions a plan at risk bound Delta may show in n samples and
// still pass: n Delta + 4 sqrt(n Delta (1 - Delta)), floored (a plan exactly at
// Delta fails it by sampling noise about once in 10^4).
std::size_t allowedCollisions(double riskBound, std::size_t samples);

// The conservatism of a plan's risk bound, Delta / (empirical collision rate).
// With no collision in the sample the rate says nothing; then the ratio is
// Delta / (the Clopper-Pearson upper bound), a lower bound on the conservatism
// (at that confidence), and lowerBound is true.
struct Conservatism {
    double ratio = 0.0;
    bool lowerBound = false;
};
Conservatism conservatism(double riskBound, const McResult& result);

// One-sided upper confidence bounds on a binomial proportion after k
// successes in n trials. Clopper-Pearson: the p with P(Bin(n, p) <= k) =
// 1 - confidence (1 when k = n), exact (regularised incomplete beta, bisected).
double clopperPearsonUpper(std::size_t k, std::size_t n, double confidence = 0.95);
double wilsonUpper(std::size_t k, std::size_t n, double confidence = 0.95);
// P(Bin(n, p) <= k), for the tests.
double binomialCdf(std::size_t k, std::size_t n, double p);

}  // namespace rse::test::cc

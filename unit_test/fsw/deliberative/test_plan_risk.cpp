// The certified collision risk of a mean path (plan_risk.hpp): an upper bound
// on the sampled path's collision probability, checked against seeded Monte
// Carlo of the same plant, much tighter than one half-plane where a path
// passes a corner, exact where the plant is deterministic, never above the
// Boole sum of a plan's deltas.
#include <cmath>
#include <cstddef>
#include <random>

#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/gaussian.hpp"
#include "fsw/deliberative/plan_risk.hpp"
#include "unit_test/fsw/deliberative/cc_test_maps.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::makeBox;
using rse::test::makePolygon;
using rse::test::makeProblem;
using rse::test::segmentPenetration;

namespace {

// The fraction of sampled paths (x_0 ~ N(mu_0, Sigma_0), x_{t+1} = x_t + mu_{t+1}
// - mu_t + w_t) whose segment t meets obstacle i (or, with t = N, any segment
// any obstacle).
double sampledRate(const CcProblem& p, const double* mx, const double* my, std::size_t onlyT, std::size_t samples,
                   std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    const double a = std::sqrt(p.startCov[0]);
    const double b = a > 0.0 ? p.startCov[1] / a : 0.0;
    const double c = std::sqrt(p.startCov[3] - b * b);
    std::size_t hits = 0;
    for (std::size_t s = 0; s < samples; ++s) {
        const double z1 = g(rng), z2 = g(rng);
        double x = mx[0] + a * z1, y = my[0] + b * z1 + c * z2;
        bool hit = false;
        for (std::size_t t = 0; t < p.steps; ++t) {
            const double nx = x + mx[t + 1] - mx[t] + p.processSigmaM * g(rng);
            const double ny = y + my[t + 1] - my[t] + p.processSigmaM * g(rng);
            if (onlyT == p.steps || onlyT == t) {
                for (std::size_t i = 0; i < p.obstacleCount; ++i) {
                    hit = hit || segmentPenetration(p.obstacles[i], x, y, nx, ny) > 0.0;
                }
            }
            x = nx;
            y = ny;
        }
        hits += hit ? 1U : 0U;
    }
    return static_cast<double>(hits) / static_cast<double>(samples);
}

// A straight mean path of N steps from (x0, y0) to (x1, y1).
void straightPath(std::size_t n, double x0, double y0, double x1, double y1, double* mx, double* my) {
    for (std::size_t t = 0; t <= n; ++t) {
        mx[t] = x0 + (x1 - x0) * static_cast<double>(t) / static_cast<double>(n);
        my[t] = y0 + (y1 - y0) * static_cast<double>(t) / static_cast<double>(n);
    }
}

CcProblem noisyProblem(std::uint8_t steps, double sigma, double startVar) {
    CcProblem p = makeProblem(steps, 0.0, 0.0, 10.0, 0.0, -20.0, 30.0, -20.0, 20.0);
    p.processSigmaM = sigma;
    p.startCov[0] = p.startCov[3] = startVar;
    return p;
}

// The bound against Monte Carlo: never below the sampled rate by more than
// four standard deviations (the samples' own noise).
void boundHoldsAgainstSampling(const CcProblem& p, const double* mx, const double* my, std::uint64_t seed) {
    const std::size_t samples = 40000;
    const double bound = planRiskBound(p, mx, my, nullptr, nullptr);
    const double rate = sampledRate(p, mx, my, p.steps, samples, seed);
    const double sd = std::sqrt(rate * (1.0 - rate) / static_cast<double>(samples)) + 1.0 / samples;
    CHECK(bound <= 1.0 * p.steps * p.obstacleCount);
    CHECK(rate <= bound + 4.0 * sd);
}

// Segment 0's least Boole bound over obstacle 0's faces: min over j of
// P(E_j(0)) + P(E_j(1)), the two ends counted apart.
double leastFaceEnds(const CcProblem& p, const double* mx, const double* my) {
    const PlanObstacle& o = p.obstacles[0];
    double least = 1.0;
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        const double v0 = faceVariance(o.normalX[j], o.normalY[j], p.startCov, p.processSigmaM, 0);
        const double v1 = faceVariance(o.normalX[j], o.normalY[j], p.startCov, p.processSigmaM, 1);
        const double r = endRisk(endSlack(o, j, mx[0], my[0], 0.0), v0) + endRisk(endSlack(o, j, mx[1], my[1], 0.0), v1);
        least = r < least ? r : least;
    }
    return least;
}

}  // namespace

TEST_GROUP(PlanRisk){};

TEST(PlanRisk, FarFromEveryObstacleIsNoRisk) {
    CcProblem p = noisyProblem(10, 0.05, 0.01);
    p.obstacles[0] = makeBox(1, 4.0, 6.0, 3.0, 5.0);  // 3 m beside a path with sigma <= 0.18 m
    p.obstacleCount = 1;
    double mx[11], my[11];
    straightPath(10, 0.0, 0.0, 10.0, 0.0, mx, my);
    double segment[10];
    RiskWork work;
    CHECK(planRiskBound(p, mx, my, segment, &work) < 1e-30);
    CHECK(work.tails > 0U);
    for (double s : segment) {
        CHECK(s >= 0.0 && s < 1e-30);
    }
}

TEST(PlanRisk, DeterministicPlantIsExact) {
    CcProblem p = noisyProblem(4, 0.0, 0.0);
    p.obstacles[0] = makeBox(1, 4.0, 6.0, -1.0, 1.0);
    p.obstacleCount = 1;
    double mx[5], my[5];
    straightPath(4, 0.0, 2.0, 10.0, 2.0, mx, my);  // clear by 1 m
    DOUBLES_EQUAL(0.0, planRiskBound(p, mx, my, nullptr, nullptr), 0.0);
    straightPath(4, 0.0, 0.0, 10.0, 0.0, mx, my);  // through the box
    RiskWork work;
    const double through = planRiskBound(p, mx, my, nullptr, &work);
    CHECK(through >= 1.0);
    CHECK_EQUAL(0U, work.orthants);  // certain ends: no orthant is needed
}

TEST(PlanRisk, BoundHoldsAgainstMonteCarlo) {
    // Past a box's corner, alongside a face, past a hexagon, a diagonal past
    // two boxes; noise large enough to sample the risk.
    CcProblem p = noisyProblem(8, 0.12, 0.02);
    double mx[kMaxPlanSteps + 1], my[kMaxPlanSteps + 1];
    p.obstacles[0] = makeBox(1, 4.0, 6.0, -3.0, -0.35);
    p.obstacleCount = 1;
    straightPath(8, 0.0, 0.0, 10.0, 0.0, mx, my);
    boundHoldsAgainstSampling(p, mx, my, 11);
    straightPath(8, 0.0, -0.6, 10.0, 0.3, mx, my);  // across the box's top-left corner's neighbourhood
    mx[4] = 4.0 - 0.3;
    my[4] = -0.05;
    boundHoldsAgainstSampling(p, mx, my, 12);
    p.obstacles[0] = makePolygon(1, 5.0, -1.0, 0.7, 6, 0.3);
    boundHoldsAgainstSampling(p, mx, my, 13);
    p.obstacles[0] = makeBox(1, 2.0, 3.0, 1.0, 3.0);
    p.obstacles[1] = makeBox(2, 6.0, 8.0, 4.0, 5.0);
    p.obstacleCount = 2;
    straightPath(8, 0.0, 0.0, 10.0, 8.0, mx, my);
    boundHoldsAgainstSampling(p, mx, my, 14);
    // Diagonally past a box's corner, where no face separates a segment's ends.
    p.obstacles[0] = makeBox(1, 2.0, 6.0, -4.0, 1.0);
    p.obstacleCount = 1;
    straightPath(8, 0.0, 3.5, 8.0, -4.5, mx, my);
    boundHoldsAgainstSampling(p, mx, my, 15);
}

TEST(PlanRisk, ACornerCostsFarLessThanItsHalfPlane) {
    // A segment leaving a box's corner diagonally from 0.25 m outside it (a
    // waypoint by a corner: both faces bind there): its first end is 1.25
    // sigma from each face's line (a half-plane risk of ~10 %), but beyond
    // both lines at once only with the orthant's probability (~1 %).
    CcProblem p = noisyProblem(2, 0.1, 0.02);
    p.obstacles[0] = makeBox(1, -5.0, 0.0, -5.0, 0.0);
    p.obstacleCount = 1;
    const double d = 0.25 / std::sqrt(2.0);
    double mx[3] = {d, d + 0.5, d + 1.0};
    double my[3] = {d, d + 0.5, d + 1.0};
    RiskWork work;
    const double pair = pairRiskBound(p, mx, my, 0, 0, &work);
    CHECK(work.orthants > 0U);
    const double leastFace = leastFaceEnds(p, mx, my);
    CHECK(pair < 0.2 * leastFace);
    const double rate = sampledRate(p, mx, my, 0, 100000, 21);
    CHECK(rate <= pair + 4.0 * std::sqrt(pair / 100000.0));
}

TEST(PlanRisk, PlansCertifyNoMoreThanTheirDeltas) {
    // Even-split plans: the certified risk is the Boole sum at most, and for
    // a plan passing one box it is far below it.
    CcProblem p = makeProblem(10, 0.0, 0.0, 20.0, 0.0, -5.0, 25.0, -10.0, 10.0);
    p.obstacles[0] = makeBox(1, 8.0, 12.0, -4.0, 3.0);
    p.obstacleCount = 1;
    p.processSigmaM = 0.05;
    p.startCov[0] = p.startCov[3] = 0.01;
    p.riskBound = 1e-3;
    static CcPlanner planner;
    static CcPlan plan;
    CHECK(planner.solve(p, CcPlannerParams{}, &plan) != CcStatus::kNoPlan);
    double deltas = 0.0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        deltas += plan.delta[t][0][0] + plan.delta[t][0][1];
    }
    double segment[kMaxPlanSteps];
    const double certified = certifiedPlanRisk(p, plan, segment, nullptr);
    CHECK(certified <= deltas);
    CHECK(certified < 0.5 * deltas);
    DOUBLES_EQUAL(certified, plan.riskUsed, 1e-12 * p.riskBound);
    CHECK(certified <= planRiskBound(p, plan.meanX, plan.meanY, nullptr, nullptr) * (1.0 + 1e-12));
}

TEST(PlanRisk, ASegmentPassingACornerIsBoundedByItsOwnLine) {
    // A segment passing a box's corner diagonally, 0.28 m outside it: each
    // end lies on the box's side of one face's line (no face separates both
    // ends, so every face's bound is ~1), but the line through the corner
    // parallel to the segment has both ends 0.28 m beyond it.
    CcProblem p = noisyProblem(1, 0.05, 0.01);
    p.obstacles[0] = makeBox(1, -5.0, 0.0, -5.0, 0.0);
    p.obstacleCount = 1;
    double mx[2] = {-1.0, 1.4};
    double my[2] = {1.4, -1.0};
    const double leastFace = leastFaceEnds(p, mx, my);
    CHECK(leastFace > 0.9);
    const double pair = pairRiskBound(p, mx, my, 0, 0, nullptr);
    CHECK(pair < 0.05);
    const double rate = sampledRate(p, mx, my, 0, 100000, 31);
    CHECK(rate > 0.0);  // the risk is real: it is sampled
    CHECK(rate <= pair + 4.0 * std::sqrt(pair / 100000.0));
    // The same segment turned round, and mirrored past the box's other corner.
    double rx[2] = {mx[1], mx[0]};
    double ry[2] = {my[1], my[0]};
    DOUBLES_EQUAL(pair, pairRiskBound(p, rx, ry, 0, 0, nullptr), 0.5 * pair);
    double sx[2] = {-4.0, -6.4};
    double sy[2] = {1.4, -1.0};
    CHECK(pairRiskBound(p, sx, sy, 0, 0, nullptr) < 0.05);
}

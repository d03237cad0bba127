// The fixed-face LP of the chance-constrained planner: problem checks, the
// open map (the 16-gon length of start -> goal), a box on the line against a
// hand computation, the diagonal box (both ends of a segment on one face keep
// every segment out; waypoints alone let a segment cross), random face
// assignments whose every segment is checked against every obstacle, margins
// that grow with the step as sqrt(a' (Sigma_0 + t sigma^2 I) a), the
// active/slack report, the pair stack, and no heap use.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <random>

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/gaussian.hpp"
#include "unit_test/fsw/deliberative/cc_test_maps.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using rse::deliberative::CcLp;
using rse::deliberative::CcLpSolution;
using rse::deliberative::CcProblem;
using rse::deliberative::checkProblem;
using rse::deliberative::faceMargin;
using rse::deliberative::kMaxPlanObstacles;
using rse::deliberative::kMaxPlanSteps;
using rse::deliberative::kSafetyM;
using rse::deliberative::LpStatus;
using rse::deliberative::polygonLength;
using rse::deliberative::solveFixedFaces;
using rse::test::makeBox;
using rse::test::makePolygon;
using rse::test::makeProblem;
using rse::test::segmentPenetration;

namespace {

CcLp ccLp;  // 152 KB: static storage
CcLpSolution solution;
std::uint8_t faces[kMaxPlanSteps][kMaxPlanObstacles];
double deltas[kMaxPlanSteps][kMaxPlanObstacles][2];

constexpr std::size_t kRight = 0;
constexpr std::size_t kTop = 1;
constexpr std::size_t kLeft = 2;
constexpr std::size_t kBottom = 3;

void fillDeltas(const CcProblem& p, double delta) {
    for (std::size_t t = 0; t < kMaxPlanSteps; ++t) {
        for (std::size_t i = 0; i < kMaxPlanObstacles; ++i) {
            deltas[t][i][0] = delta;
            deltas[t][i][1] = delta;
            faces[t][i] = 0;
        }
    }
    (void)p;
}

// The LP's s_t are the 16-gon lengths of its segments and sum to its cost.
void checkCostIsPathLength(const CcLp& lp, const CcProblem& p) {
    double sum = 0.0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        const double len = polygonLength(lp.meanX(t + 1) - lp.meanX(t), lp.meanY(t + 1) - lp.meanY(t));
        DOUBLES_EQUAL(len, lp.solver().value(lp.sIndex(t)), 1e-9);
        sum += len;
    }
    DOUBLES_EQUAL(sum, lp.cost(), 1e-9);
}

double maxPenetration(const CcProblem& p, const double* mx, const double* my) {
    double worst = -INFINITY;
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        for (std::size_t t = 0; t < p.steps; ++t) {
            const double d = segmentPenetration(p.obstacles[i], mx[t], my[t], mx[t + 1], my[t + 1]);
            worst = d > worst ? d : worst;
        }
    }
    return worst;
}

}  // namespace

TEST_GROUP(CcLp){};

TEST(CcLp, ProblemChecks) {
    CcProblem p = makeProblem(10, 0.0, 0.0, 10.0, 0.0, -5.0, 15.0, -5.0, 5.0);
    p.obstacles[0] = makeBox(0, 4.0, 6.0, -1.0, 1.0);
    p.obstacleCount = 1;
    CHECK(checkProblem(p) == Status::kOk);
    CcProblem q = p;
    q.steps = 0;
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.steps = kMaxPlanSteps + 1;
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.obstacleCount = kMaxPlanObstacles + 1;
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.obstacles[0].faceCount = 2;
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.obstacles[0].normalX[0] = 2.0;  // not a unit normal
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.riskBound = 0.5;
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.riskBound = 0.0;
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.startCov[1] = 0.1;  // not symmetric
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.startCov[0] = 1.0;
    q.startCov[3] = 1.0;
    q.startCov[1] = q.startCov[2] = 2.0;  // not positive semidefinite
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.goalX = 20.0;  // outside the site
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.processSigmaM = NAN;
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    q = p;
    q.allocation = static_cast<rse::deliberative::RiskAllocation>(7);
    CHECK(checkProblem(q) == Status::kInvalidArgument);
    CHECK(ccLp.setup(q) == Status::kInvalidArgument);
}

TEST(CcLp, PolygonLength) {
    DOUBLES_EQUAL(1.0, polygonLength(1.0, 0.0), 1e-15);
    DOUBLES_EQUAL(1.0, polygonLength(0.0, -1.0), 1e-15);
    // Half-way between two directions: cos(pi / 16) of the Euclidean length.
    const double a = M_PI / 16.0;
    DOUBLES_EQUAL(std::cos(a), polygonLength(std::cos(a), std::sin(a)), 1e-15);
    DOUBLES_EQUAL(0.0, polygonLength(0.0, 0.0), 0.0);
}

// No obstacles: every path whose segments stay in one cone of the 16-gon is
// optimal; the cost is the 16-gon length of goal - start.
TEST(CcLp, OpenMapCostIsThePolygonLengthOfTheLine) {
    for (std::uint8_t steps : {1, 2, 10, 24}) {
        const CcProblem p = makeProblem(steps, 1.0, 2.0, 13.0, 7.0, 0.0, 20.0, 0.0, 10.0);
        CHECK(ccLp.setup(p) == Status::kOk);
        CHECK(ccLp.solve(1000) == LpStatus::kOptimal);
        DOUBLES_EQUAL(polygonLength(12.0, 5.0), ccLp.cost(), 1e-9);
        checkCostIsPathLength(ccLp, p);
        CHECK_EQUAL(static_cast<std::size_t>(3 * steps - 2), ccLp.variables());
    }
}

// A 2 x 2 box on the line from (0, 0) to (10, 0), N = 3, faces left, top,
// right: the path wraps the box's top corners, mu_1 = (4, 1), mu_2 = (6, 1)
// (plus kSafetyM), cost |(4, 1)| + 2 + |(4, -1)| in the 16-gon norm.
TEST(CcLp, BoxOnTheLineDetourMatchesTheHandComputation) {
    CcProblem p = makeProblem(3, 0.0, 0.0, 10.0, 0.0, -5.0, 15.0, -5.0, 5.0);
    p.obstacles[0] = makeBox(0, 4.0, 6.0, -1.0, 1.0);
    p.obstacleCount = 1;
    fillDeltas(p, 0.01 / 6.0);
    faces[0][0] = kLeft;
    faces[1][0] = kTop;
    faces[2][0] = kRight;
    CHECK(solveFixedFaces(p, faces, deltas, 1000, &ccLp, &solution) == Status::kOk);
    CHECK(solution.status == LpStatus::kOptimal);
    const double hand = polygonLength(4.0, 1.0) + 2.0 + polygonLength(4.0, -1.0);
    DOUBLES_EQUAL(hand, solution.cost, 1e-5);
    CHECK(solution.cost > hand);  // kSafetyM only lengthens
    DOUBLES_EQUAL(4.0, solution.meanX[1], 1e-5);
    DOUBLES_EQUAL(1.0, solution.meanY[1], 1e-5);
    DOUBLES_EQUAL(6.0, solution.meanX[2], 1e-5);
    DOUBLES_EQUAL(1.0, solution.meanY[2], 1e-5);
    // Through the bottom instead: the mirror image, the same cost.
    faces[1][0] = kBottom;
    CHECK(solveFixedFaces(p, faces, deltas, 1000, &ccLp, &solution) == Status::kOk);
    DOUBLES_EQUAL(hand, solution.cost, 1e-5);
    DOUBLES_EQUAL(-1.0, solution.meanY[1], 1e-5);
    // The top face for the first segment is impossible (the start is below it).
    faces[0][0] = kTop;
    CHECK(solveFixedFaces(p, faces, deltas, 1000, &ccLp, &solution) == Status::kOk);
    CHECK(solution.status == LpStatus::kInfeasible);
    // Faces left, right for N = 2 ask mu_1 for x <= 4 and x >= 6.
    p.steps = 2;
    faces[0][0] = kLeft;
    faces[1][0] = kRight;
    CHECK(solveFixedFaces(p, faces, deltas, 1000, &ccLp, &solution) == Status::kOk);
    CHECK(solution.status == LpStatus::kInfeasible);
}

// A box on the diagonal from (0, 0) to (10, 10). Waypoints outside the box are
// not enough: with mu_1 left of it and mu_2 above it the LP keeps the straight
// line and its middle segment crosses the box. One face per segment for both
// ends sends the path round the corner (3, 7) and no segment enters the box.
TEST(CcLp, DiagonalBoxBothEndsKeepSegmentsOut) {
    CcProblem p = makeProblem(3, 0.0, 0.0, 10.0, 10.0, -5.0, 15.0, -5.0, 15.0);
    p.obstacles[0] = makeBox(0, 3.0, 7.0, 3.0, 7.0);
    p.obstacleCount = 1;
    const double margin = 0.0;  // deterministic: Sigma_0 = 0, sigma = 0
    // Waypoints only: mu_1 on the left face, mu_2 on the top face.
    CHECK(ccLp.setup(p) == Status::kOk);
    bool feasible = false;
    CHECK(ccLp.addPair(0, 0, kLeft, margin, margin, &feasible, CcLp::kEndFinish) == Status::kOk);
    CHECK(feasible);
    CHECK(ccLp.addPair(1, 0, kTop, margin, margin, &feasible, CcLp::kEndFinish) == Status::kOk);
    CHECK(ccLp.solve(1000) == LpStatus::kOptimal);
    DOUBLES_EQUAL(polygonLength(10.0, 10.0), ccLp.cost(), 1e-9);
    double mx[4], my[4];
    for (std::size_t tau = 0; tau <= 3; ++tau) {
        mx[tau] = ccLp.meanX(tau);
        my[tau] = ccLp.meanY(tau);
    }
    CHECK(mx[1] <= 3.0 && my[2] >= 7.0);  // each waypoint is outside the box ...
    CHECK(segmentPenetration(p.obstacles[0], mx[1], my[1], mx[2], my[2]) > 0.5);  // ... the segment is not
    // Both ends: segment 0 left, segments 1 and 2 top.
    fillDeltas(p, 0.01 / 6.0);
    faces[0][0] = kLeft;
    faces[1][0] = kTop;
    faces[2][0] = kTop;
    CHECK(solveFixedFaces(p, faces, deltas, 1000, &ccLp, &solution) == Status::kOk);
    CHECK(solution.status == LpStatus::kOptimal);
    DOUBLES_EQUAL(polygonLength(3.0, 7.0) + polygonLength(7.0, 3.0), solution.cost, 1e-5);
    CHECK(solution.cost > polygonLength(10.0, 10.0) + 0.5);
    CHECK(maxPenetration(p, solution.meanX, solution.meanY) < 0.0);
}

// Random maps and random face assignments, margins zero: whenever the LP is
// feasible, no segment of its path enters any obstacle (kSafetyM clear).
TEST(CcLp, RandomAssignmentsNeverCutAnObstacle) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int feasibleCount = 0;
    for (int trial = 0; trial < 300; ++trial) {
        CcProblem p = makeProblem(static_cast<std::uint8_t>(2 + trial % 9), 0.0, 10.0 * u(rng), 20.0, 10.0 * u(rng),
                                  -2.0, 22.0, -2.0, 12.0);
        p.obstacleCount = static_cast<std::uint8_t>(1 + trial % 3);
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            const double cx = 4.0 + 12.0 * u(rng);
            const double cy = 1.0 + 8.0 * u(rng);
            if (u(rng) < 0.5) {
                p.obstacles[i] = makeBox(static_cast<std::uint8_t>(i), cx - 1.0, cx + 1.5, cy - 2.0, cy + 1.0);
            } else {
                p.obstacles[i] = makePolygon(static_cast<std::uint8_t>(i), cx, cy, 1.5,
                                             static_cast<std::uint8_t>(3 + rng() % 6), 6.0 * u(rng));
            }
        }
        fillDeltas(p, 0.001);
        // Random faces, those of the first and last segments among the faces
        // the start and the goal meet (else nearly every draw is infeasible).
        for (std::size_t t = 0; t < p.steps; ++t) {
            for (std::size_t i = 0; i < p.obstacleCount; ++i) {
                const rse::deliberative::PlanObstacle& o = p.obstacles[i];
                for (int draw = 0; draw < 20; ++draw) {
                    const std::size_t j = rng() % o.faceCount;
                    faces[t][i] = static_cast<std::uint8_t>(j);
                    const bool startOk = t != 0 || rse::deliberative::endSlack(o, j, p.startX, p.startY, 0.0) >= 0.0;
                    const bool goalOk =
                        t + 1 != p.steps || rse::deliberative::endSlack(o, j, p.goalX, p.goalY, 0.0) >= 0.0;
                    if (startOk && goalOk) {
                        break;
                    }
                }
            }
        }
        CHECK(solveFixedFaces(p, faces, deltas, 5000, &ccLp, &solution) == Status::kOk);
        CHECK(solution.status == LpStatus::kOptimal || solution.status == LpStatus::kInfeasible);
        if (solution.status != LpStatus::kOptimal) {
            continue;
        }
        ++feasibleCount;
        CHECK(maxPenetration(p, solution.meanX, solution.meanY) <= -kSafetyM * 0.5);
        checkCostIsPathLength(ccLp, p);
        for (std::size_t tau = 0; tau <= p.steps; ++tau) {
            CHECK(solution.meanX[tau] >= p.xMin && solution.meanX[tau] <= p.xMax);
            CHECK(solution.meanY[tau] >= p.yMin && solution.meanY[tau] <= p.yMax);
        }
    }
    CHECK(feasibleCount > 50);
}

TEST(CcLp, MarginsGrowWithTheStep) {
    CcProblem p = makeProblem(6, 0.0, 5.0, 10.0, 5.0, -5.0, 15.0, -10.0, 15.0);
    p.startCov[0] = 0.04;
    p.startCov[1] = p.startCov[2] = 0.01;
    p.startCov[3] = 0.09;
    p.processSigmaM = 0.1;
    p.obstacles[0] = makeBox(0, 2.0, 8.0, 0.0, 10.0);
    p.obstacleCount = 1;
    const double delta = 0.001;
    const double q = rse::deliberative::upperQuantile(delta);
    for (std::size_t tau = 0; tau <= 6; ++tau) {
        // Bottom face a = (0, -1): a' Sigma_tau a = 0.09 + tau 0.01.
        DOUBLES_EQUAL(q * std::sqrt(0.09 + 0.01 * static_cast<double>(tau)), faceMargin(p, 0, kBottom, tau, delta),
                      1e-14);
        DOUBLES_EQUAL(q * std::sqrt(0.04 + 0.01 * static_cast<double>(tau)), faceMargin(p, 0, kRight, tau, delta),
                      1e-14);
        if (tau > 0) {
            CHECK(faceMargin(p, 0, kBottom, tau, delta) > faceMargin(p, 0, kBottom, tau - 1, delta));
        }
    }
    // N = 3 round the bottom of a wall: segment 0 left, 1 bottom, 2 right.
    // The corners are mu_1 = (2 - m_1, -m_1), mu_2 = (8 + m_2, -m_2), every
    // margin at its own step.
    p.steps = 3;
    fillDeltas(p, delta);
    faces[0][0] = kLeft;
    faces[1][0] = kBottom;
    faces[2][0] = kRight;
    CHECK(solveFixedFaces(p, faces, deltas, 1000, &ccLp, &solution) == Status::kOk);
    CHECK(solution.status == LpStatus::kOptimal);
    const double left1 = faceMargin(p, 0, kLeft, 1, delta);
    const double bottom1 = faceMargin(p, 0, kBottom, 1, delta);
    const double bottom2 = faceMargin(p, 0, kBottom, 2, delta);
    const double right2 = faceMargin(p, 0, kRight, 2, delta);
    CHECK(bottom2 > bottom1 + 0.01);
    DOUBLES_EQUAL(2.0 - left1, solution.meanX[1], 2e-6);
    DOUBLES_EQUAL(-bottom1, solution.meanY[1], 2e-6);
    DOUBLES_EQUAL(8.0 + right2, solution.meanX[2], 2e-6);
    DOUBLES_EQUAL(-bottom2, solution.meanY[2], 2e-6);
    const double hand = polygonLength(2.0 - left1, -bottom1 - 5.0) +
                        polygonLength(6.0 + right2 + left1, bottom1 - bottom2) +
                        polygonLength(2.0 - right2, 5.0 + bottom2);
    DOUBLES_EQUAL(hand, solution.cost, 1e-5);
    // Active: the ends at the corners; slack: the start's and goal's ends.
    CHECK(solution.active[0][0][1] && solution.active[1][0][0] && solution.active[1][0][1] &&
          solution.active[2][0][0]);
    CHECK_FALSE(solution.active[0][0][0]);
    CHECK_FALSE(solution.active[2][0][1]);
    // The start's end: a . mu_0 - b = -0 + 2, less its margin at step 0.
    DOUBLES_EQUAL(2.0 - faceMargin(p, 0, kLeft, 0, delta), solution.slack[0][0][0], 1e-12);
    CHECK(solution.slack[2][0][1] > 1.0);
    for (std::size_t t = 0; t < 3; ++t) {
        for (std::size_t e = 0; e < 2; ++e) {
            CHECK(solution.slack[t][0][e] >= 0.0);
        }
    }
}

// The pair stack: pushing and popping pairs with saved bases gives the same
// optima as building each LP from scratch.
TEST(CcLp, PairStackWithBasesMatchesFreshBuilds) {
    CcProblem p = makeProblem(5, 0.0, 0.0, 10.0, 0.0, -5.0, 15.0, -5.0, 5.0);
    p.obstacles[0] = makeBox(0, 4.0, 6.0, -3.0, 3.0);
    p.obstacles[1] = makeBox(1, 7.0, 8.0, -3.0, 0.5);
    p.obstacleCount = 2;
    CHECK(ccLp.setup(p) == Status::kOk);
    CHECK(ccLp.solve(1000) == LpStatus::kOptimal);
    rse::deliberative::LpBasis root;
    ccLp.solver().saveBasis(&root);
    const double rootCost = ccLp.cost();
    bool feasible = false;
    CHECK(ccLp.addPair(2, 0, kTop, 0.0, 0.0, &feasible) == Status::kOk);
    CHECK(feasible);
    CHECK(ccLp.addPair(3, 1, kTop, 0.0, 0.0, &feasible) == Status::kOk);
    CHECK(ccLp.solve(1000) == LpStatus::kOptimal);
    const double deeper = ccLp.cost();
    CHECK(deeper > rootCost + 0.1);
    CHECK_EQUAL(2U, ccLp.pairCount());
    CHECK(ccLp.popPairs(0) == Status::kOk);
    CHECK(ccLp.solver().restoreBasis(root) == Status::kOk);
    CHECK(ccLp.solve(1000) == LpStatus::kOptimal);
    CHECK_EQUAL(0U, ccLp.solver().lastIterations());
    DOUBLES_EQUAL(rootCost, ccLp.cost(), 1e-12);
    CHECK(ccLp.popPairs(1) == Status::kInvalidArgument);
    // An end at the goal that misses its face is refused, nothing pushed.
    CHECK(ccLp.addPair(4, 0, kLeft, 0.0, 0.0, &feasible) == Status::kOk);
    CHECK_FALSE(feasible);
    CHECK_EQUAL(0U, ccLp.pairCount());
    CHECK(ccLp.addPair(5, 0, kLeft, 0.0, 0.0, &feasible) == Status::kInvalidArgument);
    CHECK(ccLp.addPair(0, 2, 0, 0.0, 0.0, &feasible) == Status::kInvalidArgument);
}

TEST(CcLp, NoHeapUse) {
    CcProblem p = makeProblem(10, 0.0, 0.0, 10.0, 0.0, -5.0, 15.0, -5.0, 5.0);
    p.obstacles[0] = makeBox(0, 4.0, 6.0, -1.0, 1.0);
    p.obstacleCount = 1;
    fillDeltas(p, 0.0005);
    for (std::size_t t = 0; t < 10; ++t) {
        faces[t][0] = t < 4 ? kLeft : (t < 6 ? kTop : kRight);
    }
    rse::test::AllocationWatch watch;
    CHECK(solveFixedFaces(p, faces, deltas, 1000, &ccLp, &solution) == Status::kOk);
    CHECK(solution.status == LpStatus::kOptimal);
    CHECK_EQUAL(0U, watch.count());
}

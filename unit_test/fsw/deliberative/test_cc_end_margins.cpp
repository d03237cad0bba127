// Each end's risk and margin (cc_end_margins.hpp): the even split, the fixed
// ends raised to their need with the optimised allocation (the rest shared,
// the sum within the budget), and the even split kept when the fixed ends
// alone need more than the budget.
#include <cmath>
#include <cstdint>

#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_work_units.hpp"
#include "fsw/deliberative/gaussian.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::makeBox;
using rse::test::wallWithGap;

namespace {

CcEndMargins margins;

// The goal 0.4 m west of a box (test_cc_planner.cpp): at step 10 its end
// needs about 0.016 of the risk.
CcProblem goalNearABox(double riskBound, RiskAllocation allocation) {
    CcProblem p = wallWithGap(10);
    p.obstacles[1] = makeBox(1, 20.4, 21.5, 3.0, 7.0);
    p.riskBound = riskBound;
    p.allocation = allocation;
    return p;
}

double sumOfEnds(const CcProblem& p, const CcEndMargins& m) {
    double sum = 0.0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            sum += m.endDelta(t, i) + m.endDelta(t + 1, i);
        }
    }
    return sum;
}

}  // namespace

TEST_GROUP(CcEndMargins){};

TEST(CcEndMargins, TheEvenSplitGivesEveryEndTheSameRiskAndItsMargin) {
    const CcProblem p = wallWithGap(10);
    const double budget = p.riskBound * (1.0 - kRiskSafety);
    std::uint64_t work = 0;
    margins.build(p, budget, &work);
    const double even = budget / (2.0 * 10.0 * 2.0);
    DOUBLES_EQUAL(even, margins.evenDelta(), 0.0);
    LONGS_EQUAL(0, margins.raised());
    LONGS_EQUAL(0, work);  // the even split computes no fixed-end risk
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        DOUBLES_EQUAL(even, margins.endDelta(0, i), 0.0);
        DOUBLES_EQUAL(even, margins.endDelta(p.steps, i), 0.0);
        for (std::size_t j = 0; j < p.obstacles[i].faceCount; ++j) {
            for (std::size_t tau = 0; tau <= p.steps; ++tau) {
                DOUBLES_EQUAL(faceMargin(p, i, j, tau, even), margins.margin(tau, i, j), 0.0);
            }
        }
    }
    // Margins grow with the step (the covariance does).
    CHECK(margins.margin(p.steps, 0, 0) > margins.margin(0, 0, 0));
    // Delta' keeps the sum of the 2 N M deltas within Delta, rounding included.
    CHECK(sumOfEnds(p, margins) <= p.riskBound);
}

TEST(CcEndMargins, TheOptimisedSplitGivesAFixedEndWhatItNeeds) {
    const CcProblem p = goalNearABox(0.05, RiskAllocation::kOptimised);
    const double budget = p.riskBound * (1.0 - kRiskSafety);
    std::uint64_t work = 0;
    margins.build(p, budget, &work);
    LONGS_EQUAL(1, margins.raised());
    // The goal's end on the box: its best face's need, 1 um inside its slack.
    const double need = endRisk(0.4 - kSafetyM, faceVariance(-1.0, 0.0, p.startCov, p.processSigmaM, 10));
    DOUBLES_EQUAL(need, margins.endDelta(p.steps, 1), 1e-12);
    CHECK(margins.endDelta(p.steps, 1) > 0.015);
    // Everyone else shares the rest; the sum stays within the budget.
    CHECK(margins.evenDelta() < budget / 40.0);
    DOUBLES_EQUAL(margins.evenDelta(), margins.endDelta(0, 1), 0.0);
    DOUBLES_EQUAL(margins.evenDelta(), margins.endDelta(p.steps, 0), 0.0);
    CHECK(sumOfEnds(p, margins) <= budget);
    // Each fixed end's faces' risks are charged.
    LONGS_EQUAL(2 * (4 + 4) * kMarginWork, work);
}

TEST(CcEndMargins, FixedEndsNeedingMoreThanTheBudgetKeepTheEvenSplit) {
    const CcProblem p = goalNearABox(0.01, RiskAllocation::kOptimised);  // the goal alone needs 0.016
    const double budget = p.riskBound * (1.0 - kRiskSafety);
    std::uint64_t work = 0;
    margins.build(p, budget, &work);
    LONGS_EQUAL(0, margins.raised());
    DOUBLES_EQUAL(budget / 40.0, margins.endDelta(p.steps, 1), 0.0);
}

TEST(CcEndMargins, NoObstaclesNoRisk) {
    CcProblem p = wallWithGap(6);
    p.obstacleCount = 0;
    std::uint64_t work = 0;
    margins.build(p, p.riskBound, &work);
    DOUBLES_EQUAL(0.0, margins.evenDelta(), 0.0);
    LONGS_EQUAL(0, margins.raised());
}

// Checking a plan exactly (cc_plan_checks.hpp): a hand-made plan past a box
// passes; each thing checked, broken alone, fails it; Boole's claim and the
// path's lengths; the certified route when the deltas' sum passes Delta.
#include <cmath>

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/plan_risk.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::core::Status;
using rse::test::boxAboveTheWay;
using rse::test::kBoxBottom;

namespace {

// The straight line from start to goal under the box, every pair on the
// box's bottom face, every delta 1e-3 (sum 8e-3 < Delta 0.01).
CcPlan straightPlan(const CcProblem& p) {
    CcPlan plan{};
    plan.status = CcStatus::kFeasible;
    plan.steps = p.steps;
    for (std::size_t tau = 0; tau <= p.steps; ++tau) {
        const double s = static_cast<double>(tau) / p.steps;
        plan.meanX[tau] = p.startX + s * (p.goalX - p.startX);
        plan.meanY[tau] = p.startY + s * (p.goalY - p.startY);
    }
    for (std::size_t t = 0; t < p.steps; ++t) {
        plan.face[t][0] = kBoxBottom;
        plan.delta[t][0][0] = 1e-3;
        plan.delta[t][0][1] = 1e-3;
    }
    claimBooleRisk(p, &plan);
    measurePath(p.steps, &plan);
    return plan;
}

}  // namespace

TEST_GROUP(CcPlanChecks){};

TEST(CcPlanChecks, BooleClaimAndLengths) {
    const CcProblem p = boxAboveTheWay(4);
    const CcPlan plan = straightPlan(p);
    DOUBLES_EQUAL(8e-3, plan.riskUsed, 1e-15);
    for (std::size_t t = 0; t < p.steps; ++t) {
        DOUBLES_EQUAL(2e-3, plan.segmentRisk[t], 1e-15);
    }
    // Along a polygon normal (c_0 = (1, 0)) the 16-gon length is the Euclidean one.
    DOUBLES_EQUAL(8.0, plan.cost, 1e-12);
    DOUBLES_EQUAL(8.0, plan.euclideanLengthM, 1e-12);
}

TEST(CcPlanChecks, AGoodPlanPassesAndEachFaultFailsIt) {
    const CcProblem p = boxAboveTheWay(4);
    const CcPlan good = straightPlan(p);
    double deltaSum = 0.0;
    CHECK(checkPlanShape(p, good, p.riskBound, &deltaSum) == Status::kOk);
    DOUBLES_EQUAL(8e-3, deltaSum, 1e-15);
    CHECK(checkPlan(p, good) == Status::kOk);

    CcPlan bad = good;
    bad.meanX[0] += 1e-9;  // not the start
    CHECK(checkPlanShape(p, bad, p.riskBound, &deltaSum) == Status::kInvalidArgument);
    bad = good;
    bad.meanY[2] = 1.9;  // inside the bottom face's margin
    CHECK(checkPlanShape(p, bad, p.riskBound, &deltaSum) == Status::kInvalidArgument);
    bad = good;
    bad.meanY[2] = -6.0;  // off the site
    CHECK(checkPlanShape(p, bad, p.riskBound, &deltaSum) == Status::kInvalidArgument);
    bad = good;
    bad.delta[1][0][1] = 0.5;  // deltas lie in (0, 0.5)
    CHECK(checkPlanShape(p, bad, p.riskBound, &deltaSum) == Status::kInvalidArgument);
    bad = good;
    bad.face[1][0] = 4;  // a box has four faces
    CHECK(checkPlanShape(p, bad, p.riskBound, &deltaSum) == Status::kInvalidArgument);
    bad = good;
    bad.steps = 5;
    CHECK(checkPlanShape(p, bad, p.riskBound, &deltaSum) == Status::kInvalidArgument);
    bad = good;
    bad.cost = NAN;
    CHECK(checkPlanShape(p, bad, p.riskBound, &deltaSum) == Status::kInvalidArgument);
    // riskUsed within the limit given, whatever Delta is.
    CHECK(checkPlanShape(p, good, 7e-3, &deltaSum) == Status::kInvalidArgument);
}

TEST(CcPlanChecks, TheCertifiedBoundStandsWhereTheDeltasPassDelta) {
    CcProblem p = boxAboveTheWay(4);
    p.riskBound = 5e-3;  // below the deltas' 8e-3
    CcPlan plan = straightPlan(p);
    const double certified = certifiedPlanRisk(p, plan, nullptr, nullptr);
    CHECK(certified < p.riskBound);  // the path is 2 m from the box
    plan.riskUsed = certified;
    CHECK(checkPlan(p, plan) == Status::kOk);
    plan.riskUsed = 0.5 * certified;  // claims less than can be certified
    CHECK(checkPlan(p, plan) == Status::kInvalidArgument);
    plan.riskUsed = 8e-3;  // the deltas' sum: over Delta
    CHECK(checkPlan(p, plan) == Status::kInvalidArgument);
}

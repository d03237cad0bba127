// Pulling a plan taut (plan_tauten.hpp): zigzags inside the 16-gon norm's flat
// cones straightened, constraints kept, the cost never up.
#include <cmath>

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/plan_tauten.hpp"
#include "unit_test/fsw/deliberative/cc_test_maps.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::core::Status;
using rse::test::makeBox;
using rse::test::makeProblem;

namespace {

CcPlanner g_planner;  // 450 KB: static storage

// The largest distance of a mean from the straight line start-goal.
double offLine(const CcProblem& p, const CcPlan& plan) {
    const double dx = p.goalX - p.startX, dy = p.goalY - p.startY;
    const double l = std::hypot(dx, dy);
    double worst = 0.0;
    for (std::size_t t = 0; t <= plan.steps; ++t) {
        const double d = std::fabs((plan.meanX[t] - p.startX) * dy - (plan.meanY[t] - p.startY) * dx) / l;
        worst = d > worst ? d : worst;
    }
    return worst;
}

CcPlan zigzag(const CcProblem& p) {
    CcPlan plan{};
    plan.status = CcStatus::kOptimal;
    plan.steps = p.steps;
    for (std::size_t t = 0; t <= p.steps; ++t) {
        const double s = static_cast<double>(t) / p.steps;
        plan.meanX[t] = p.startX + s * (p.goalX - p.startX);
        plan.meanY[t] = p.startY + s * (p.goalY - p.startY) + ((t % 2 == 1 && t < p.steps) ? 0.15 : 0.0);
    }
    for (std::size_t t = 0; t < p.steps; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            plan.face[t][i] = 3;  // below the box (normal -y)
            plan.delta[t][i][0] = plan.delta[t][i][1] = p.riskBound / (4.0 * p.steps * p.obstacleCount);
            plan.riskUsed += 2.0 * plan.delta[t][i][0];
        }
    }
    return plan;
}

}  // namespace

TEST_GROUP(PlanTauten){};

TEST(PlanTauten, AZigzagWithNothingInTheWayBecomesTheStraightLineAtNoExtraCost) {
    CcProblem p = makeProblem(6, 0.0, 0.0, 12.0, 0.0, -5.0, 20.0, -5.0, 5.0);
    CcPlan plan = zigzag(p);
    double before = 0.0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        before += polygonLength(plan.meanX[t + 1] - plan.meanX[t], plan.meanY[t + 1] - plan.meanY[t]);
    }
    CHECK(offLine(p, plan) > 0.1);
    CHECK(tautenPlan(p, &plan) > 0);
    CHECK(offLine(p, plan) < 1e-6);
    CHECK(plan.cost <= before + 1e-12);
    DOUBLES_EQUAL(12.0, plan.euclideanLengthM, 1e-6);
    CHECK(Status::kOk == checkPlan(p, plan));
}

TEST(PlanTauten, ConstraintsStillHoldAndMeansOnlyMoveTowardsTheLine) {
    // A box above the line: every end must stay below it by its growing margin.
    CcProblem p = makeProblem(6, 0.0, -2.0, 12.0, -2.0, -5.0, 20.0, -5.0, 5.0);
    p.processSigmaM = 0.1;
    p.obstacles[0] = makeBox(1, 2.0, 10.0, -0.6, 2.0);
    p.obstacleCount = 1;
    CcPlan plan = zigzag(p);
    // Start the zigzag below the box's margin: it is a valid plan.
    for (std::size_t t = 1; t < p.steps; ++t) {
        plan.meanY[t] = -2.0 - ((t % 2 == 1) ? 0.3 : 0.0);
    }
    CHECK_TRUE(Status::kOk == checkPlan(p, plan));
    const CcPlan before = plan;
    (void)tautenPlan(p, &plan);
    CHECK(Status::kOk == checkPlan(p, plan));
    CHECK(plan.cost <= before.cost + 1e-12 || before.cost == 0.0);
    DOUBLES_EQUAL(12.0, plan.euclideanLengthM, 1e-6);
    // Nothing rose above the box's tightened face.
    for (std::size_t t = 1; t < p.steps; ++t) {
        const double margin = faceMargin(p, 0, 3, t, plan.delta[t][0][0]);
        CHECK(-plan.meanY[t] - 0.6 - margin >= 0.0);
        CHECK(plan.meanY[t] >= before.meanY[t] - 1e-12);  // only towards the line
    }
}

TEST(PlanTauten, APlanWithoutAPathIsLeftAlone) {
    CcProblem p = makeProblem(4, 0.0, 0.0, 8.0, 0.0, -5.0, 20.0, -5.0, 5.0);
    CcPlan plan = zigzag(p);
    plan.status = CcStatus::kNoPlan;
    const double y1 = plan.meanY[1];
    LONGS_EQUAL(0, tautenPlan(p, &plan));
    DOUBLES_EQUAL(y1, plan.meanY[1], 0.0);
}

// The planner hands out tautened plans: with no obstacle every optimal path is
// the same 16-gon length, and the one handed out is the straight line.
TEST(PlanTauten, ThePlannersPlanWithNoObstacleIsTheStraightLine) {
    CcProblem p = makeProblem(10, 0.0, 0.0, 10.0, 1.5, -5.0, 20.0, -5.0, 5.0);
    p.processSigmaM = 0.05;
    CcPlan plan;
    const CcStatus s = g_planner.solve(p, CcPlannerParams{}, &plan);
    CHECK(s == CcStatus::kOptimal || s == CcStatus::kFeasible);
    CHECK(offLine(p, plan) < 1e-6);
    DOUBLES_EQUAL(std::hypot(10.0, 1.5), plan.euclideanLengthM, 1e-6);
    LONGS_EQUAL(0, g_planner.tautenRefused());
}

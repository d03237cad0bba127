// The finish (cc_taut_finish.hpp): a zigzag plan pulled taut and certified
// (one unit, then a segment a unit) replaces the plan; a taut plan whose
// claim is over Delta (its certification cut short by the budget) is refused
// and the plan kept as planned.
#include <cmath>

#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_taut_finish.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "fsw/deliberative/plan_risk.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::core::Status;
using rse::test::boxAboveTheWay;
using rse::test::kBoxBottom;
using rse::test::prepareWorkspace;

namespace {

CcWorkspace ws;  // static storage
CcTautFinish finish;

// Under the box, every other mean 0.15 m below the line; deltas `delta`.
CcPlan zigzag(const CcProblem& p, double delta) {
    CcPlan plan{};
    plan.status = CcStatus::kFeasible;
    plan.steps = p.steps;
    for (std::size_t tau = 0; tau <= p.steps; ++tau) {
        plan.meanX[tau] = 8.0 * static_cast<double>(tau) / static_cast<double>(p.steps);
        plan.meanY[tau] = (tau % 2 == 1 && tau < p.steps) ? -0.15 : 0.0;
    }
    for (std::size_t t = 0; t < p.steps; ++t) {
        plan.face[t][0] = kBoxBottom;
        plan.delta[t][0][0] = plan.delta[t][0][1] = delta;
    }
    claimBooleRisk(p, &plan);
    measurePath(p.steps, &plan);
    return plan;
}

double lowest(const CcPlan& plan) {
    double y = INFINITY;
    for (std::size_t tau = 0; tau <= plan.steps; ++tau) {
        y = plan.meanY[tau] < y ? plan.meanY[tau] : y;
    }
    return y;
}

}  // namespace

TEST_GROUP(CcTautFinish){};

TEST(CcTautFinish, AZigzagIsPulledTautAndCertified) {
    const CcProblem p = boxAboveTheWay(6);
    CHECK(prepareWorkspace(ws, p));
    const CcPlan zig = zigzag(p, 5e-4);
    CHECK(checkPlan(p, zig) == Status::kOk);
    ws.incumbent.keep(zig, true);
    finish.reset();
    finish.begin();
    CHECK_FALSE(finish.step(ws, true));  // tautened
    const std::uint64_t afterTauten = ws.geometryWork;
    CHECK(afterTauten > 0);
    std::uint32_t units = 0;
    while (!finish.step(ws, true) && units < 100) {
        ++units;
    }
    LONGS_EQUAL(p.steps - 1, units);  // a segment a unit, the last one ends it
    LONGS_EQUAL(0, finish.refused());
    const CcPlan& best = ws.incumbent.best();
    CHECK(best.cost <= zig.cost);
    CHECK(lowest(best) > -0.15 + 1e-3);
    DOUBLES_EQUAL(certifiedPlanRisk(p, best, nullptr, nullptr), best.riskUsed, 1e-15);
    CHECK(best.riskUsed < 6e-3);
    CHECK(checkPlan(p, best) == Status::kOk);
    CHECK(ws.incumbent.certified());
}

TEST(CcTautFinish, ATautPlanClaimingMoreThanDeltaIsRefused) {
    const CcProblem p = boxAboveTheWay(6);
    CHECK(prepareWorkspace(ws, p));
    const CcPlan zig = zigzag(p, 1e-3);  // the deltas' sum 0.012 passes Delta 0.01
    ws.incumbent.keep(zig, true);
    finish.reset();
    finish.begin();
    CHECK_FALSE(finish.step(ws, true));
    CHECK(finish.step(ws, false));  // no work left: Boole's claim, over Delta
    LONGS_EQUAL(1, finish.refused());
    DOUBLES_EQUAL(zig.cost, ws.incumbent.best().cost, 0.0);
    DOUBLES_EQUAL(-0.15, lowest(ws.incumbent.best()), 0.0);
}

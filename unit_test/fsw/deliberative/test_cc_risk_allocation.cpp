// The risk allocation alone (cc_risk_allocation.hpp), after a search with no
// seed: round a tall box it shortens the even split's plan and certifies it
// within Delta; the even split and a spent work share end it at once.
#include <cmath>

#include "fsw/deliberative/cc_face_search.hpp"
#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_risk_allocation.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::core::Status;
using rse::test::makeBox;
using rse::test::makeProblem;
using rse::test::prepareWorkspace;

namespace {

CcWorkspace ws;  // static storage
CcFaceSearch search;
CcRiskAllocation allocation;

// A tall box on the straight line: the path wraps its corner steeply, where
// moving risk to the corner's ends shortens it (test_cc_planner.cpp).
CcProblem tallBox(RiskAllocation allocationKind) {
    CcProblem p = makeProblem(10, 0.0, 0.0, 20.0, 0.0, -2.0, 22.0, -10.0, 10.0);
    p.obstacles[0] = makeBox(0, 8.0, 12.0, -5.0, 4.0);
    p.obstacleCount = 1;
    p.processSigmaM = 0.05;
    p.startCov[0] = p.startCov[3] = 0.01;
    p.allocation = allocationKind;
    return p;
}

// The search's plan (the incumbent), then the allocation reset.
void searchThenReset(const CcProblem& p) {
    CHECK(prepareWorkspace(ws, p));
    search.resetCounts();
    search.prepare(ws.lp.variables());
    std::uint32_t units = 0;
    while (units < 100000 && !search.rootUnit(ws, nullptr)) {
        ++units;
    }
    while (units < 100000 && search.searchUnit(ws, nullptr)) {
        ++units;
    }
    CHECK(ws.incumbent.certified());
    allocation.reset();
}

}  // namespace

TEST_GROUP(CcRiskAllocation){};

TEST(CcRiskAllocation, RoundATallBoxItShortensThePlanWithinDelta) {
    const CcProblem p = tallBox(RiskAllocation::kOptimised);
    searchThenReset(p);
    const double even = ws.incumbent.best().cost;
    std::uint32_t units = 0;
    bool over = false;
    while (units < 100000 && !over) {
        over = allocation.step(ws, true);
        ++units;
    }
    CHECK(over);
    CHECK(allocation.rounds() > 0);
    CHECK(allocation.rounds() <= CcPlannerParams{}.iraRounds);
    const CcPlan& best = ws.incumbent.best();
    CHECK(ws.incumbent.certified());
    CHECK(best.cost < even - 1e-3);
    CHECK(best.riskUsed <= ws.riskBudget);
    CHECK(checkPlan(p, best) == Status::kOk);
    CHECK_FALSE(ws.run.running());
    CHECK_FALSE(ws.certifier.running());
}

TEST(CcRiskAllocation, TheEvenSplitHasNoRounds) {
    searchThenReset(tallBox(RiskAllocation::kEvenSplit));
    const double even = ws.incumbent.best().cost;
    CHECK(allocation.step(ws, true));
    LONGS_EQUAL(0, allocation.rounds());
    DOUBLES_EQUAL(even, ws.incumbent.best().cost, 0.0);
}

TEST(CcRiskAllocation, ASpentWorkShareEndsIt) {
    searchThenReset(tallBox(RiskAllocation::kOptimised));
    CHECK_FALSE(allocation.step(ws, true));  // the best plan's LP started
    CHECK(ws.run.running());
    CHECK(allocation.step(ws, false));  // dropped
    CHECK_FALSE(ws.run.running());
    LONGS_EQUAL(0, allocation.rounds());
}

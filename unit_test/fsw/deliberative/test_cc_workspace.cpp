// The planner's shared workspace (cc_workspace.hpp): begin() prepares a plan
// as CcPlanner::start() does: no best plan, the budgets, the margins, the LP.
#include <cmath>

#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::wallWithGap;

namespace {

CcWorkspace ws;  // static storage

}  // namespace

TEST_GROUP(CcWorkspace){};

TEST(CcWorkspace, BeginPreparesAPlan) {
    CcProblem p = wallWithGap(10);
    p.allocation = RiskAllocation::kOptimised;
    CcPlannerParams params;
    params.searchRiskScale = 4.0;
    ws.geometryWork = 12345;
    ws.run.begin(HUGE_VAL, 10);
    ws.certifier.start();
    CHECK(ws.begin(p, params) == rse::core::Status::kOk);
    CHECK(ws.incumbent.best().status == CcStatus::kNoPlan);
    LONGS_EQUAL(10, ws.incumbent.best().steps);
    CHECK_FALSE(ws.run.running());
    CHECK_FALSE(ws.certifier.running());
    DOUBLES_EQUAL(0.01 * (1.0 - kRiskSafety), ws.riskBudget, 0.0);
    DOUBLES_EQUAL(4.0, ws.searchScale(), 0.0);
    DOUBLES_EQUAL(4.0 * ws.riskBudget, ws.searchBudget, 0.0);
    DOUBLES_EQUAL(ws.searchBudget / 40.0, ws.margins.evenDelta(), 0.0);
    LONGS_EQUAL(3 * 10 - 2, ws.lp.variables());
    LONGS_EQUAL(0, ws.lp.pairCount());
    // The even split has no wide search.
    p.allocation = RiskAllocation::kEvenSplit;
    CHECK(ws.begin(p, params) == rse::core::Status::kOk);
    DOUBLES_EQUAL(1.0, ws.searchScale(), 0.0);
}

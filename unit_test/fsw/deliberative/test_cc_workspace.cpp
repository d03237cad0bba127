// The planner's shared workspace (cc_workspace.hpp): begin() prepares a plan
// as CcPlanner::start() does: no best plan, the budgets, the margins, the LP.
// The figures expected are worked out by hand (the quantile from mpmath).
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

// The wall with a gap in 10 steps (two boxes, x 9..11; start (0, 5), goal
// (20, 5)), Delta 0.01, optimised allocation, a wide search of scale 4. The
// figures by hand:
//   riskBudget   = Delta (1 - 1e-12)            = 9.99999999999e-3
//   searchBudget = 4 x riskBudget                = 3.999999999996e-2
//   the start and the goal are 9 m (90 and 48 sigma) from their nearest
//   face: they need nothing, no end is raised, and every end gets
//   searchBudget / (2 N M = 40)                  = 9.99999999999e-4
//   its margin: PhiInv(1 - 9.99999999999e-4) = 3.0902323061681105 (mpmath)
//   times sqrt(0.01 + 0.0025 tau): 0.30902323061681105 m at tau 0,
//   0.57812952676106914 m at tau 10 (sqrt 0.035)
//   the fixed ends' risks: 2 ends x 2 obstacles x 4 faces x kMarginWork (200) = 3200
//   the LP's variables: s_0..s_9 and mu_1..mu_9 (x, y): 10 + 18 = 28
// The even split has no wide search: its ends get riskBudget / 40 = 2.4999999999975e-4.
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
    DOUBLES_EQUAL(9.99999999999e-3, ws.riskBudget, 1e-17);  // a few ulps; 1e-14 without the safety
    DOUBLES_EQUAL(4.0, ws.searchScale(), 0.0);
    DOUBLES_EQUAL(3.999999999996e-2, ws.searchBudget, 1e-16);
    LONGS_EQUAL(0, ws.margins.raised());
    DOUBLES_EQUAL(9.99999999999e-4, ws.margins.evenDelta(), 1e-18);
    DOUBLES_EQUAL(9.99999999999e-4, ws.margins.endDelta(0, 0), 1e-18);
    DOUBLES_EQUAL(9.99999999999e-4, ws.margins.endDelta(10, 1), 1e-18);
    DOUBLES_EQUAL(0.30902323061681105, ws.margins.margin(0, 0, rse::test::kBoxLeft), 1e-13);
    DOUBLES_EQUAL(0.57812952676106914, ws.margins.margin(10, 1, rse::test::kBoxRight), 1e-13);
    LONGS_EQUAL(3200, ws.geometryWork);
    LONGS_EQUAL(28, ws.lp.variables());
    LONGS_EQUAL(0, ws.lp.pairCount());
    p.allocation = RiskAllocation::kEvenSplit;
    CHECK(ws.begin(p, params) == rse::core::Status::kOk);
    DOUBLES_EQUAL(1.0, ws.searchScale(), 0.0);
    DOUBLES_EQUAL(9.99999999999e-3, ws.searchBudget, 1e-17);
    DOUBLES_EQUAL(2.4999999999975e-4, ws.margins.evenDelta(), 1e-18);
    LONGS_EQUAL(0, ws.geometryWork);  // an even split computes no fixed end's risk
}

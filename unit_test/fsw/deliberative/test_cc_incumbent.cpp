// The best plan so far (cc_incumbent.hpp): an LP's plan kept when it
// verifies and is shorter, with its faces and the search's deltas; certified
// by Boole at scale 1, not in a wide search.
#include <cmath>

#include "fsw/deliberative/cc_incumbent.hpp"
#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_work_units.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::core::Status;
using rse::test::boxAboveTheWay;
using rse::test::fillFaces;
using rse::test::kBoxBottom;
using rse::test::kBoxLeft;
using rse::test::kBoxRight;
using rse::test::kBoxTop;
using rse::test::prepareWorkspace;
using rse::test::solveFaces;
using rse::test::wallWithGap;

namespace {

CcWorkspace ws;  // static storage
CcFaceTable faces;

// Straight through the gap: box 0 (below) on its top face, box 1 on its bottom.
void throughTheGap() {
    fillFaces(faces, 0);
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        faces[t][0] = kBoxTop;
        faces[t][1] = kBoxBottom;
    }
}

}  // namespace

TEST_GROUP(CcIncumbent){};

TEST(CcIncumbent, AResetIncumbentHasNoPlan) {
    CHECK(prepareWorkspace(ws, wallWithGap(10)));
    CHECK(ws.incumbent.best().status == CcStatus::kNoPlan);
    LONGS_EQUAL(10, ws.incumbent.best().steps);
    CHECK(std::isinf(ws.incumbent.evenCost()));
    CHECK_FALSE(ws.incumbent.certified());
    LONGS_EQUAL(0, ws.incumbent.improvements());
}

TEST(CcIncumbent, AShorterVerifiedPlanIsKept) {
    CHECK(prepareWorkspace(ws, boxAboveTheWay(6)));
    // Over the box first (a detour: beside its left face, over its top,
    // beside its right face), then under it (the straight line).
    const std::uint8_t over[6] = {kBoxLeft, kBoxLeft, kBoxTop, kBoxTop, kBoxRight, kBoxRight};
    fillFaces(faces, 0);
    for (std::size_t t = 0; t < 6; ++t) {
        faces[t][0] = over[t];
    }
    CHECK(solveFaces(ws, faces) == LpStatus::kOptimal);
    const double overCost = ws.lp.cost();
    const std::uint64_t work0 = ws.geometryWork;
    ws.incumbent.offerFromLp(ws.problem, ws.margins, ws.lp, faces, ws.searchScale(), 3, &ws.candidate,
                             &ws.geometryWork);
    LONGS_EQUAL(work0 + kMarginWork * 2U * 6U * 1U, ws.geometryWork);
    LONGS_EQUAL(1, ws.incumbent.improvements());
    DOUBLES_EQUAL(overCost, ws.incumbent.evenCost(), 1e-9);
    fillFaces(faces, kBoxBottom);
    CHECK(solveFaces(ws, faces) == LpStatus::kOptimal);
    const double underCost = ws.lp.cost();
    CHECK(underCost < overCost - 1.0);
    ws.incumbent.offerFromLp(ws.problem, ws.margins, ws.lp, faces, ws.searchScale(), 7, &ws.candidate,
                             &ws.geometryWork);
    const CcPlan& best = ws.incumbent.best();
    CHECK(best.status == CcStatus::kFeasible);
    LONGS_EQUAL(2, ws.incumbent.improvements());
    DOUBLES_EQUAL(underCost, ws.incumbent.evenCost(), 1e-9);
    DOUBLES_EQUAL(best.cost, ws.incumbent.evenCost(), 0.0);
    LONGS_EQUAL(7, ws.incumbent.lastNode());
    CHECK(ws.incumbent.certified());
    CHECK(checkPlan(ws.problem, best) == Status::kOk);
    LONGS_EQUAL(kBoxBottom, best.face[3][0]);
    DOUBLES_EQUAL(ws.margins.endDelta(0, 0), best.delta[0][0][0], 0.0);
    // The same plan again is not shorter: not counted.
    ws.incumbent.offerFromLp(ws.problem, ws.margins, ws.lp, faces, ws.searchScale(), 9, &ws.candidate,
                             &ws.geometryWork);
    LONGS_EQUAL(2, ws.incumbent.improvements());
    LONGS_EQUAL(7, ws.incumbent.lastNode());
}

TEST(CcIncumbent, AWideSearchsPlanIsNotCertified) {
    CcProblem p = wallWithGap(10);
    p.allocation = RiskAllocation::kOptimised;
    CcPlannerParams params;
    params.searchRiskScale = 8.0;
    CHECK(prepareWorkspace(ws, p, params));
    throughTheGap();
    CHECK(solveFaces(ws, faces) == LpStatus::kOptimal);
    ws.incumbent.offerFromLp(ws.problem, ws.margins, ws.lp, faces, ws.searchScale(), 0, &ws.candidate,
                             &ws.geometryWork);
    CHECK(ws.incumbent.best().status == CcStatus::kFeasible);  // kept: within Delta x 8
    CHECK_FALSE(ws.incumbent.certified());                    // its deltas pass Delta
    CHECK(ws.incumbent.best().riskUsed > p.riskBound);
}

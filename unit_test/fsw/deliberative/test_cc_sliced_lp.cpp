// One LP in slices (cc_sliced_lp.hpp): kPivotsPerUnit pivots a call, the
// same optimum as one solve; the LP's own pivot cap ends it; the workspace's
// cap of pivots left (cc_workspace.hpp).
#include <cmath>

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_sliced_lp.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::fillFaces;
using rse::test::kBoxBottom;
using rse::test::kBoxTop;
using rse::test::prepareWorkspace;
using rse::test::wallWithGap;

namespace {

CcWorkspace ws;  // ~240 KB: static storage
CcFaceTable faces;

// Through the gap: box 0 (below) on its top face, box 1 (above) on its bottom.
void gapFaces(std::size_t steps) {
    fillFaces(faces, 0);
    for (std::size_t t = 0; t < steps; ++t) {
        faces[t][0] = kBoxTop;
        faces[t][1] = kBoxBottom;
    }
}

void pushFaces() {
    (void)ws.lp.popPairs(0);
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            const std::size_t j = faces[t][i];
            bool feasible = false;
            CHECK(ws.lp.addPair(t, i, j, ws.margins.margin(t, i, j), ws.margins.margin(t + 1, i, j), &feasible) ==
                  rse::core::Status::kOk);
            CHECK(feasible);
        }
    }
}

}  // namespace

TEST_GROUP(CcSlicedLp){};

TEST(CcSlicedLp, SlicesReachTheOptimumOfOneSolve) {
    CHECK(prepareWorkspace(ws, wallWithGap(20)));
    gapFaces(20);
    pushFaces();
    CHECK(ws.lp.solve(100000) == LpStatus::kOptimal);
    const double cost = ws.lp.cost();
    const std::uint32_t pivots = ws.lp.solver().lastIterations();
    CHECK(pivots > 2 * CcSlicedLp::kPivotsPerUnit);  // enough to need several slices
    // The same LP cold, in slices.
    CHECK(prepareWorkspace(ws, wallWithGap(20)));
    pushFaces();
    ws.run.begin(HUGE_VAL, 100000);
    LpStatus st = LpStatus::kNotSolved;
    std::uint32_t calls = 1;
    while (!ws.run.resume(ws.lp, &st)) {
        CHECK(ws.lp.solver().lastIterations() <= CcSlicedLp::kPivotsPerUnit);
        CHECK(ws.run.running());
        ++calls;
    }
    CHECK_FALSE(ws.run.running());
    CHECK(st == LpStatus::kOptimal);
    // Each slice resumes from its basis (x recomputed, so the pivots may
    // differ from one solve's): several slices, the same optimum.
    CHECK(calls > 2);
    DOUBLES_EQUAL(cost, ws.lp.cost(), 1e-9);
}

TEST(CcSlicedLp, TheLpsCapEndsIt) {
    CHECK(prepareWorkspace(ws, wallWithGap(20)));
    gapFaces(20);
    pushFaces();
    ws.run.begin(HUGE_VAL, 20);
    LpStatus st = LpStatus::kNotSolved;
    CHECK_FALSE(ws.run.resume(ws.lp, &st));  // 16 of its 20
    CHECK(ws.run.resume(ws.lp, &st));        // the last 4
    CHECK(st == LpStatus::kIterationLimit);
    LONGS_EQUAL(20, ws.lp.solver().iterations());
    CHECK_FALSE(ws.run.running());
}

TEST(CcSlicedLp, TheWorkspaceCapsAnLpByWhatIsLeftOfThePlansPivots) {
    CcPlannerParams params;
    params.iterationBudget = 50;
    params.perLpIterations = 30;
    CHECK(prepareWorkspace(ws, wallWithGap(20), params));
    LONGS_EQUAL(30, ws.lpCap());
    gapFaces(20);
    pushFaces();
    ws.run.begin(HUGE_VAL, ws.lpCap());
    LpStatus st = LpStatus::kNotSolved;
    while (!ws.run.resume(ws.lp, &st)) {
    }
    LONGS_EQUAL(30, ws.lp.solver().iterations());
    LONGS_EQUAL(20, ws.lpCap());
}

// The seeds (cc_seeds.hpp): the visibility variants give the first
// incumbent and the guide; the layered seed runs when they give nothing (a
// start whose margin at step N swallows it); the hint is taken only before
// the first unit and only when its faces exist, and its cost is recorded.
#include <cmath>

#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_seeds.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::core::Status;
using rse::test::kBoxBottom;
using rse::test::kBoxTop;
using rse::test::makeBox;
using rse::test::prepareWorkspace;
using rse::test::wallWithGap;

namespace {

CcWorkspace ws;  // static storage
CcSeeds seeds;
CcPlan hint;

void startSeeds(const CcProblem& p) {
    CHECK(prepareWorkspace(ws, p));
    seeds.resetCounts();
    seeds.resetOrder();
}

// Every unit until the seeds are over; the units run.
std::uint32_t runSeeds() {
    std::uint32_t units = 0;
    while (units < 100000 && seeds.runUnit(ws)) {
        ++units;
    }
    return units;
}

}  // namespace

TEST_GROUP(CcSeeds){};

TEST(CcSeeds, TheVisibilitySeedsGiveTheFirstPlanAndTheGuide) {
    startSeeds(wallWithGap(10));
    CHECK(seeds.guide() == nullptr);
    CHECK(runSeeds() > 4);
    CHECK(seeds.found());
    CHECK(seeds.solves() >= 4);  // four variants, and their polish where faces moved
    DOUBLES_EQUAL(ws.incumbent.evenCost(), seeds.cost(), 0.0);
    CHECK(ws.incumbent.certified());
    CHECK(checkPlan(ws.problem, ws.incumbent.best()) == Status::kOk);
    DOUBLES_EQUAL(20.0, seeds.cost(), 0.05);
    LONGS_EQUAL(0, seeds.layered().layers());  // not needed
    const CcFaceTable* guide = seeds.guide();
    CHECK(guide != nullptr);
    LONGS_EQUAL(kBoxTop, (*guide)[4][0]);     // over the lower box through the gap
    LONGS_EQUAL(kBoxBottom, (*guide)[4][1]);  // under the upper one
    CHECK(std::isinf(seeds.hintCost()));
}

TEST(CcSeeds, TheLayeredSeedRunsWhenTheVisibilitySeedsFindNothing) {
    CcProblem p = wallWithGap(10);
    p.processSigmaM = 0.2;  // margins at step N and N / 2 over 0.5 m
    p.obstacles[0] = makeBox(0, -1.0, 1.0, 0.0, 4.5);  // 0.5 m below the start
    startSeeds(p);
    (void)runSeeds();
    CHECK(seeds.layered().layers() > 0);
    CHECK(seeds.found());
    CHECK(checkPlan(ws.problem, ws.incumbent.best()) == Status::kOk);
}

TEST(CcSeeds, AHintIsTakenBeforeTheFirstUnitOnlyAndItsCostRecorded) {
    startSeeds(wallWithGap(10));
    (void)runSeeds();
    hint = ws.incumbent.best();
    startSeeds(wallWithGap(12));
    CHECK_FALSE(seeds.setHint(ws.problem, hint));  // 10 steps, not 12
    startSeeds(wallWithGap(10));
    hint.face[2][1] = 4;  // a box has four faces
    CHECK_FALSE(seeds.setHint(ws.problem, hint));
    hint.face[2][1] = kBoxBottom;
    CHECK(seeds.setHint(ws.problem, hint));
    CHECK(seeds.hintPending());
    seeds.runHintUnit(ws);
    CHECK_FALSE(seeds.hintPending());
    CHECK(ws.run.running());  // the hint's LP
    (void)runSeeds();
    CHECK(std::isfinite(seeds.hintCost()));
    DOUBLES_EQUAL(hint.cost, seeds.hintCost(), 1e-6);
    // After a unit has run the seeds take no hint.
    startSeeds(wallWithGap(10));
    CHECK(seeds.runUnit(ws));
    CHECK(seeds.runUnit(ws));
    CHECK_FALSE(seeds.setHint(ws.problem, hint));
}

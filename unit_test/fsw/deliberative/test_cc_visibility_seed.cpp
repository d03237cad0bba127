// The visibility seed (cc_visibility_seed.hpp): the shortest path round the
// inflated obstacles, through a gap; cut into N segments by length or
// front-loaded; none when the start is inside an inflated obstacle or the
// goal is walled in; its work counted.
#include <cmath>

#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_visibility_seed.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::boxAboveTheWay;
using rse::test::goalWalledIn;
using rse::test::makeBox;
using rse::test::segmentPenetration;
using rse::test::wallWithGap;

namespace {

CcEndMargins margins;
CcVisibilitySeed seed;
double px[kMaxPlanSteps + 1];
double py[kMaxPlanSteps + 1];

// Builds at step tauInflate and settles to the end; the vertices settled.
std::size_t shortestPath(const CcProblem& p, std::size_t tauInflate, std::uint64_t* work) {
    margins.build(p, p.riskBound, work);
    if (!seed.build(p, margins, tauInflate, work)) {
        return 0;
    }
    std::size_t settled = 0;
    while (!seed.settleOne(p, work) && settled <= CcVisibilitySeed::kMaxVertices) {
        ++settled;
    }
    return settled;
}

}  // namespace

TEST_GROUP(CcVisibilitySeed){};

TEST(CcVisibilitySeed, ThroughTheGapAndCutIntoSegments) {
    const CcProblem p = wallWithGap(10);
    std::uint64_t work = 0;
    CHECK(shortestPath(p, p.steps, &work) > 0);
    CHECK(work > 0);
    // Start, goal, and the corners of the two inflated boxes inside the site.
    CHECK(seed.vertexCount() > 2);
    CHECK(std::isfinite(seed.distance()));
    CHECK(seed.distance() >= 20.0 && seed.distance() < 20.5);
    CHECK(seed.cutPath(p, false, px, py));
    DOUBLES_EQUAL(p.startX, px[0], 0.0);
    DOUBLES_EQUAL(p.startY, py[0], 0.0);
    DOUBLES_EQUAL(p.goalX, px[p.steps], 0.0);
    DOUBLES_EQUAL(p.goalY, py[p.steps], 0.0);
    for (std::size_t t = 0; t < p.steps; ++t) {
        CHECK(px[t + 1] > px[t]);  // shared by length: no segment parked
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            CHECK(segmentPenetration(p.obstacles[i], px[t], py[t], px[t + 1], py[t + 1]) < 0.0);
        }
    }
}

TEST(CcVisibilitySeed, FrontLoadedParksTheRestAtTheGoal) {
    const CcProblem p = boxAboveTheWay(6);  // the straight line is free: one leg
    std::uint64_t work = 0;
    CHECK(shortestPath(p, p.steps, &work) > 0);
    DOUBLES_EQUAL(polygonLength(8.0, 0.0), seed.distance(), 1e-12);
    CHECK(seed.cutPath(p, true, px, py));
    for (std::size_t t = 1; t <= p.steps; ++t) {
        DOUBLES_EQUAL(p.goalX, px[t], 0.0);
        DOUBLES_EQUAL(p.goalY, py[t], 0.0);
    }
    CHECK(seed.cutPath(p, false, px, py));
    for (std::size_t t = 0; t <= p.steps; ++t) {
        DOUBLES_EQUAL(8.0 * static_cast<double>(t) / 6.0, px[t], 1e-12);
    }
}

TEST(CcVisibilitySeed, AStartInsideAnInflatedObstacleHasNoGraph) {
    CcProblem p = wallWithGap(10);
    p.obstacles[0] = makeBox(0, -1.0, 1.0, 0.0, 4.8);  // 0.2 m below the start: inside its margin at step N
    std::uint64_t work = 0;
    margins.build(p, p.riskBound, &work);
    CHECK_FALSE(seed.build(p, margins, p.steps, &work));
}

TEST(CcVisibilitySeed, AWalledGoalHasNoPath) {
    const CcProblem p = goalWalledIn();
    std::uint64_t work = 0;
    (void)shortestPath(p, 0, &work);
    CHECK(std::isinf(seed.distance()));
    CHECK_FALSE(seed.cutPath(p, false, px, py));
}

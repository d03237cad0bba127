// The layered seed (cc_layered_seed.hpp): the goal at the first layer when
// the way is open; through a gap, a path whose every segment holds one face
// per obstacle at its margins; no path to a walled goal; each layer sliced
// into units of kLayerPairsPerUnit line pairs.
#include <cmath>
#include <cstdint>

#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_layered_seed.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::boxAboveTheWay;
using rse::test::goalWalledIn;
using rse::test::wallWithGap;

namespace {

CcEndMargins margins;
CcLayeredSeed seed;
double px[kMaxPlanSteps + 1];
double py[kMaxPlanSteps + 1];

// Runs the seed to its end; its outcome, the units it took in *units.
CcLayeredSeed::Progress runToEnd(const CcProblem& p, std::uint64_t* work, std::uint32_t* units) {
    margins.build(p, p.riskBound, work);
    seed.clear();
    seed.begin();
    CcLayeredSeed::Progress progress = CcLayeredSeed::Progress::kRunning;
    for (*units = 0; *units < 100000 && progress == CcLayeredSeed::Progress::kRunning; ++*units) {
        progress = seed.step(p, margins, work);
    }
    return progress;
}

// Some face of obstacle i holds both ends of segment t at their margins
// (kSafetyM more for an end the LP holds, as the seed's lines are drawn).
bool segmentHeld(const CcProblem& p, std::size_t t, std::size_t i) {
    for (std::size_t j = 0; j < p.obstacles[i].faceCount; ++j) {
        bool both = true;
        for (std::size_t e = 0; e < 2; ++e) {
            const std::size_t tau = t + e;
            const double extra = (tau == 0 || tau == p.steps) ? 0.0 : kSafetyM;
            both = both && endSlack(p.obstacles[i], j, px[tau], py[tau], margins.margin(tau, i, j)) >= extra;
        }
        if (both) {
            return true;
        }
    }
    return false;
}

}  // namespace

TEST_GROUP(CcLayeredSeed){};

TEST(CcLayeredSeed, AnOpenWayReachesTheGoalAtTheFirstLayer) {
    const CcProblem p = boxAboveTheWay(6);
    std::uint64_t work = 0;
    std::uint32_t units = 0;
    CHECK(runToEnd(p, &work, &units) == CcLayeredSeed::Progress::kFound);
    LONGS_EQUAL(1, seed.layers());
    const double length = seed.path(p, margins, px, py);
    DOUBLES_EQUAL(polygonLength(8.0, 0.0), length, 1e-12);
    for (std::size_t t = 1; t <= p.steps; ++t) {
        DOUBLES_EQUAL(p.goalX, px[t], 0.0);  // the goal at once, then parked
        DOUBLES_EQUAL(p.goalY, py[t], 0.0);
    }
}

TEST(CcLayeredSeed, ThroughTheGapEverySegmentHoldsAFacePerObstacle) {
    // From below the lower box to above the upper one: no face of the lower
    // box holds both the start and the goal.
    CcProblem p = wallWithGap(10);
    p.startY = -5.0;
    p.goalY = 15.0;
    std::uint64_t work = 0;
    std::uint32_t units = 0;
    CHECK(runToEnd(p, &work, &units) == CcLayeredSeed::Progress::kFound);
    CHECK(seed.layers() >= 2);
    LONGS_EQUAL(0, seed.fullLayers());
    CHECK(units > seed.layers());  // (4 x 2 + 4) lines: several slices a layer
    CHECK(work > 0);
    const double length = seed.path(p, margins, px, py);
    CHECK(length >= polygonLength(20.0, 20.0));
    DOUBLES_EQUAL(p.startX, px[0], 0.0);
    DOUBLES_EQUAL(p.goalX, px[p.steps], 0.0);
    for (std::size_t t = 0; t < p.steps; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            CHECK(segmentHeld(p, t, i));
        }
    }
}

TEST(CcLayeredSeed, AWalledGoalHasNoPath) {
    const CcProblem p = goalWalledIn();
    std::uint64_t work = 0;
    std::uint32_t units = 0;
    CHECK(runToEnd(p, &work, &units) == CcLayeredSeed::Progress::kNoPath);
    CHECK(seed.layers() >= 1);
}

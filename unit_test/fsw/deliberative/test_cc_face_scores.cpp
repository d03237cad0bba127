// The pair score and the best faces of a path (cc_face_scores.hpp): the
// score is the least slack of the pair's two ends at their margins, less
// the LP's safety for the ends the LP holds; the best face is the one the
// path clears best. The scores expected are worked out by hand from the
// margins' Gaussian quantile (mpmath), not from the code's formula.
#include "fsw/deliberative/cc_face_scores.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::boxAboveTheWay;
using rse::test::kBoxBottom;
using rse::test::kBoxLeft;

namespace {

CcEndMargins margins;
CcFaceTable faces;

}  // namespace

TEST_GROUP(CcFaceScores){};

// The box (x 3..5, y 2..4) above the way from (0, 0) to (8, 0) in 4 steps,
// Delta 0.01 split evenly over its 2 N M = 8 ends: delta = 1.25e-3 each, so
// every end's margin is PhiInv(1 - 1.25e-3) sqrt(0.01 + 0.0025 tau) =
// 3.0233414397391474 x 0.05 sqrt(4 + tau) m (mpmath, 40 digits). An end the LP
// holds (tau 1..3) is scored less kSafetyM - 2 kPrimalTol = 1e-6 - 2e-9 m.
// The means: (0, 0), (2, -0.5), (4, 1), (6, -0.5), (8, 0). On the bottom face
// (y <= 2) an end's slack is 2 - y - margin; on the left face (x <= 3) 3 - x - margin.
TEST(CcFaceScores, TheScoreIsTheLeastSlackOfThePairsEnds) {
    const CcProblem p = boxAboveTheWay(4);
    std::uint64_t work = 0;
    margins.build(p, p.riskBound, &work);
    const double mx[5] = {0.0, 2.0, 4.0, 6.0, 8.0};
    const double my[5] = {0.0, -0.5, 1.0, -0.5, 0.0};
    // Segment 0: the start, fixed, scored exactly: 2 - 0.30233414397391474 =
    // 1.6976658560260853; mu_1 (2.5 - 0.33801 - 9.98e-7 = 2.16198) is clearer.
    DOUBLES_EQUAL(1.6976658560260853, pairScore(p, margins, 0, 0, kBoxBottom, mx, my), 1e-12);
    // Segment 1: mu_2, held by the LP: 1 - 3.0233414397391474 x 0.05 sqrt 6
    // - 9.98e-7 = 0.62971680972138163.
    DOUBLES_EQUAL(0.62971680972138163, pairScore(p, margins, 1, 0, kBoxBottom, mx, my), 1e-12);
    // Segment 3: the goal, fixed, scored exactly: 2 - 3.0233414397391474 x
    // 0.05 sqrt 8 = 1.5724349532236298; mu_3 (2.5 - 0.39993 - 9.98e-7 = 2.10005) is clearer.
    DOUBLES_EQUAL(1.5724349532236298, pairScore(p, margins, 3, 0, kBoxBottom, mx, my), 1e-12);
    // The left face holds the first segment's ends: mu_1, 1 m clear, less its
    // margin 3.0233414397391474 x 0.05 sqrt 5 and the LP's safety: 0.66197915307755912.
    DOUBLES_EQUAL(0.66197915307755912, pairScore(p, margins, 0, 0, kBoxLeft, mx, my), 1e-12);
    // ... and not the third's: mu_3 is 3 m beyond it, so -3 - 0.05 sqrt 7 x
    // 3.0233414397391474 - 9.98e-7 = -3.3999514768992878.
    DOUBLES_EQUAL(-3.3999514768992878, pairScore(p, margins, 2, 0, kBoxLeft, mx, my), 1e-12);
}

TEST(CcFaceScores, EachPairGetsTheFaceItsEndsClearBest) {
    const CcProblem p = boxAboveTheWay(4);
    std::uint64_t work = 0;
    margins.build(p, p.riskBound, &work);
    // Up beside the box's left face, then under it.
    const double mx[5] = {0.0, 2.5, 4.0, 6.0, 8.0};
    const double my[5] = {0.0, 3.0, -0.5, -0.5, 0.0};
    chooseFacesAt(p, margins, mx, my, faces);
    LONGS_EQUAL(kBoxLeft, faces[0][0]);
    LONGS_EQUAL(kBoxBottom, faces[3][0]);
    LONGS_EQUAL(kBoxBottom, faces[2][0]);
}

// The pair score and the best faces of a path (cc_face_scores.hpp): the
// score is the least slack of the pair's two ends at their margins, less
// the LP's safety for the ends the LP holds; the best face is the one the
// path clears best.
#include <cmath>

#include "fsw/deliberative/cc_face_scores.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/lp_solver.hpp"
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

TEST(CcFaceScores, TheScoreIsTheLeastSlackOfThePairsEnds) {
    const CcProblem p = boxAboveTheWay(4);
    std::uint64_t work = 0;
    margins.build(p, p.riskBound, &work);
    const double mx[5] = {0.0, 2.0, 4.0, 6.0, 8.0};
    const double my[5] = {0.0, 0.5, 1.0, 0.5, 0.0};
    const PlanObstacle& box = p.obstacles[0];
    const double lp = kSafetyM - 2.0 * LpSolver::kPrimalTol;  // what the LP's rows take off an interior end
    // Segment 0: the start (fixed, scored exactly) and mu_1 (held by the LP).
    const double start = endSlack(box, kBoxBottom, mx[0], my[0], margins.margin(0, 0, kBoxBottom));
    const double first = endSlack(box, kBoxBottom, mx[1], my[1], margins.margin(1, 0, kBoxBottom)) - lp;
    DOUBLES_EQUAL(start < first ? start : first, pairScore(p, margins, 0, 0, kBoxBottom, mx, my), 1e-12);
    // Segment 1: mu_2 is closer to the box and later (a larger margin).
    const double second = endSlack(box, kBoxBottom, mx[2], my[2], margins.margin(2, 0, kBoxBottom)) - lp;
    DOUBLES_EQUAL(second, pairScore(p, margins, 1, 0, kBoxBottom, mx, my), 1e-12);
    // Segment 3 ends at the goal: scored exactly there.
    const double goal = endSlack(box, kBoxBottom, mx[4], my[4], margins.margin(4, 0, kBoxBottom));
    const double third = endSlack(box, kBoxBottom, mx[3], my[3], margins.margin(3, 0, kBoxBottom)) - lp;
    DOUBLES_EQUAL(goal < third ? goal : third, pairScore(p, margins, 3, 0, kBoxBottom, mx, my), 1e-12);
    // The box's left face (x <= 3) holds only the first segment's ends.
    CHECK(pairScore(p, margins, 0, 0, kBoxLeft, mx, my) > 0.0);
    CHECK(pairScore(p, margins, 2, 0, kBoxLeft, mx, my) < 0.0);
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

// The shared checks of the chance-constrained planning benchmark
// (unit_test/bench/cc_common.hpp): the Gaussian quantile and margins, the
// 16-gon length, the exact segment / convex polygon test, the polygon
// conversions and the plan constraint checks.
#include <cmath>
#include <cstdint>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::test::cc;

namespace {

constexpr double kPi = 3.14159265358979323846;

CcProblem openSite(double startX, double startY, double goalX, double goalY, std::uint8_t steps) {
    CcProblem p;
    p.steps = steps;
    p.startX = startX;
    p.startY = startY;
    p.goalX = goalX;
    p.goalY = goalY;
    p.xMin = -20.0;
    p.xMax = 20.0;
    p.yMin = -20.0;
    p.yMax = 20.0;
    p.riskBound = 0.05;
    return p;
}

}  // namespace

TEST_GROUP(CcCommon){};

TEST(CcCommon, NormalQuantileMatchesKnownValuesAndInvertsTheCdf) {
    DOUBLES_EQUAL(0.0, normalQuantile(0.5), 1e-15);
    DOUBLES_EQUAL(1.959963984540054, normalQuantile(0.975), 1e-12);
    DOUBLES_EQUAL(-1.644853626951472, normalQuantile(0.05), 1e-12);
    DOUBLES_EQUAL(3.090232306167813, normalQuantile(0.999), 1e-11);
    DOUBLES_EQUAL(4.264890793922825, normalUpperQuantile(1e-5), 1e-10);
    DOUBLES_EQUAL(5.997807015007688, normalUpperQuantile(1e-9), 1e-9);
    const double ps[] = {1e-12, 1e-7, 1e-3, 0.02, 0.1, 0.3, 0.5, 0.7, 0.97, 0.9999};
    for (double p : ps) {
        DOUBLES_EQUAL(p, normalCdf(normalQuantile(p)), 1e-12 * p + 1e-15);
        if (p >= 1e-3) {  // below that 1 - p has lost the digits
            DOUBLES_EQUAL(-normalQuantile(p), normalQuantile(1.0 - p), 1e-9);
        }
    }
    CHECK(std::isinf(normalQuantile(0.0)) && normalQuantile(0.0) < 0.0);
    CHECK(std::isnan(normalQuantile(1.5)));
}

TEST(CcCommon, MarginsFollowTheGrowingCovariance) {
    CcProblem p = openSite(0, 0, 1, 0, 10);
    p.startCov[0] = 0.04;
    p.startCov[3] = 0.01;
    p.processSigmaM = 0.05;
    double cov[4];
    stepCovariance(p, 4, cov);
    DOUBLES_EQUAL(0.04 + 4 * 0.0025, cov[0], 1e-15);
    DOUBLES_EQUAL(0.01 + 4 * 0.0025, cov[3], 1e-15);
    const double k = normalUpperQuantile(1e-3);
    // Along x the variance is Sigma_xx, along y Sigma_yy, diagonally their mean.
    DOUBLES_EQUAL(k * std::sqrt(0.05), faceMargin(p, 4, 1.0, 0.0, 1e-3), 1e-12);
    DOUBLES_EQUAL(k * std::sqrt(0.02), faceMargin(p, 4, 0.0, -1.0, 1e-3), 1e-12);
    const double h = std::sqrt(0.5);
    DOUBLES_EQUAL(k * std::sqrt(0.035), faceMargin(p, 4, h, h, 1e-3), 1e-12);
    CHECK(faceMargin(p, 5, 1.0, 0.0, 1e-3) > faceMargin(p, 4, 1.0, 0.0, 1e-3));
    CHECK(faceMargin(p, 4, 1.0, 0.0, 1e-6) > faceMargin(p, 4, 1.0, 0.0, 1e-3));
}

TEST(CcCommon, EvenSplitSharesDeltaOverEveryEnd) {
    CcProblem p = openSite(0, 0, 1, 0, 7);
    p.obstacleCount = 3;
    const RiskSplit s = evenSplit(p);
    DOUBLES_EQUAL(0.05 / 42.0, s.delta[6][2][1], 1e-18);
    DOUBLES_EQUAL(0.05, s.total(p), 1e-15);
    DOUBLES_EQUAL(0.0, s.delta[7][0][0], 0.0);
    p.obstacleCount = 0;
    DOUBLES_EQUAL(0.0, evenSplit(p).total(p), 0.0);
}

TEST(CcCommon, KgonLengthIsExactAlongItsNormalsAndCosPiOverKShortOfEuclideanBetween) {
    const double x[] = {0.0, 3.0, 3.0, 3.0 + 2.0 * std::cos(kPi / 8.0)};
    const double y[] = {0.0, 0.0, -4.0, -4.0 + 2.0 * std::sin(kPi / 8.0)};
    // Steps along c_0, c_12 (down), c_1: all normals of the 16-gon.
    DOUBLES_EQUAL(9.0, kgonLength(x, y, 3), 1e-12);
    DOUBLES_EQUAL(9.0, euclideanLength(x, y, 3), 1e-12);
    // Half-way between two normals the 16-gon length is |d| cos(pi / 16).
    const double a = kPi / 16.0;
    const double x2[] = {1.0, 1.0 + 5.0 * std::cos(a)};
    const double y2[] = {2.0, 2.0 + 5.0 * std::sin(a)};
    DOUBLES_EQUAL(5.0 * std::cos(kPi / 16.0), kgonLength(x2, y2, 1), 1e-12);
    DOUBLES_EQUAL(5.0, euclideanLength(x2, y2, 1), 1e-12);
}

TEST(CcCommon, PolygonRoundTripAndBox) {
    const std::vector<Point> v = {{0, 0}, {4, 0}, {5, 2}, {2, 4}, {-1, 2}};
    const PlanObstacle o = obstacleFromVertices(v, 9);
    LONGS_EQUAL(5, o.faceCount);
    LONGS_EQUAL(9, o.id);
    for (std::size_t j = 0; j < 5; ++j) {
        DOUBLES_EQUAL(1.0, std::hypot(o.normalX[j], o.normalY[j]), 1e-15);
    }
    const std::vector<Point> back = obstacleVertices(o);
    LONGS_EQUAL(5, back.size());
    for (std::size_t k = 0; k < 5; ++k) {
        DOUBLES_EQUAL(v[k].x, back[k].x, 1e-12);
        DOUBLES_EQUAL(v[k].y, back[k].y, 1e-12);
    }
    CHECK(pointInObstacle(o, 2, 2));
    CHECK(!pointInObstacle(o, 5, 0));
    CHECK(!pointInObstacle(o, 2, 0));  // on a face: the obstacle is open
    CHECK(obstacleSlack(o, 2, 2) < 0.0);
    DOUBLES_EQUAL(1.0, obstacleSlack(o, 2, -1), 1e-12);  // 1 m below the bottom face

    const PlanObstacle box = boxObstacle(1, 2, 3, 5, 1);
    const std::vector<Point> corners = obstacleVertices(box);
    LONGS_EQUAL(4, corners.size());
    DOUBLES_EQUAL(1.0, corners[0].x, 1e-15);
    DOUBLES_EQUAL(2.0, corners[0].y, 1e-15);
    DOUBLES_EQUAL(3.0, corners[2].x, 1e-15);
    DOUBLES_EQUAL(5.0, corners[2].y, 1e-15);

    // Clockwise faces, or a face that is no edge, are not a polygon.
    const std::vector<Point> cw = {{0, 0}, {0, 4}, {4, 0}};
    CHECK(obstacleVertices(obstacleFromVertices(cw, 1)).empty());
    PlanObstacle redundant = box;
    redundant.faceCount = 5;
    redundant.normalX[4] = 1.0;  // x < 10: a face that never bounds the box
    redundant.normalY[4] = 0.0;
    redundant.offset[4] = 10.0;
    CHECK(obstacleVertices(redundant).empty());
}

TEST(CcCommon, SegmentPolygonTestIsExact) {
    const PlanObstacle box = boxObstacle(0, 0, 2, 2, 1);
    CHECK(segmentIntersectsObstacle(box, -1, 1, 3, 1));     // straight through
    CHECK(segmentIntersectsObstacle(box, 1, 1, 1, 1));      // a point inside
    CHECK(segmentIntersectsObstacle(box, 1, 1, 5, 5));      // starts inside
    CHECK(segmentIntersectsObstacle(box, -0.5, 1.0, 1.0, 2.5));  // cuts the corner (0, 2)
    CHECK(!segmentIntersectsObstacle(box, 1, 3, 3, 1));      // touches the corner (2, 2) only
    CHECK(!segmentIntersectsObstacle(box, -1, 2, 3, 2));     // along the top face
    CHECK(!segmentIntersectsObstacle(box, -1, 3, 1, 5));     // beside, bounding boxes apart
    CHECK(!segmentIntersectsObstacle(box, -0.5, 1.8, 0.2, 2.5));  // 0.21 m off the corner (0, 2)
    CHECK(!segmentIntersectsObstacle(box, 3, 3, 2, 2));      // ends on the corner
    CHECK(segmentIntersectsObstacle(box, 3, 3, 1.999, 1.999));  // ... and a hair beyond
    // A triangle: a segment whose bounding box overlaps it but which misses.
    const PlanObstacle tri = obstacleFromVertices({{0, 0}, {4, 0}, {0, 4}}, 2);
    CHECK(!segmentIntersectsObstacle(tri, 2.5, 4, 4, 2.5));
    CHECK(segmentIntersectsObstacle(tri, 1, 3.5, 3, 0.5));
}

TEST(CcCommon, SegmentSlackSeesACornerCutThatWaypointSlackMisses) {
    // Zero noise: margins 0. Box [2, 6] x [-2, 4]; the step (0, 0) -> (10, 10)
    // cuts its top-left corner; (0, 0) -> (1, 5) -> (10, 10) goes around it.
    CcProblem p = openSite(0, 0, 10, 10, 1);
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(2, -2, 6, 4, 1);
    const RiskSplit split = evenSplit(p);
    const double sx[] = {0.0, 10.0}, sy[] = {0.0, 10.0};
    CHECK(waypointConstraintSlack(p, sx, sy, split) > 0.0);
    CHECK(segmentConstraintSlack(p, sx, sy, split) < 0.0);
    CHECK(meanPathHitsObstacle(p, sx, sy));
    p.steps = 2;
    const RiskSplit split2 = evenSplit(p);
    const double ax[] = {0.0, 1.0, 10.0}, ay[] = {0.0, 5.0, 10.0};
    std::size_t worstT = 99, worstI = 99;
    // Segment 0 stays left of x = 2 (slack 1 at its end), segment 1 above y = 4.
    DOUBLES_EQUAL(1.0, segmentConstraintSlack(p, ax, ay, split2, &worstT, &worstI), 1e-12);
    LONGS_EQUAL(0, worstI);
    CHECK(!meanPathHitsObstacle(p, ax, ay));
    DOUBLES_EQUAL(-15.0, siteBoundViolation(p, ax, ay), 1e-12);  // (1, 5) is 15 m inside y <= 20

    // With noise the margins eat into the slack: Sigma_0 = 0.01 I, delta = 0.05 / 4.
    p.startCov[0] = 0.01;
    p.startCov[3] = 0.01;
    const RiskSplit noisy = evenSplit(p);
    DOUBLES_EQUAL(1.0 - normalUpperQuantile(0.0125) * 0.1,
                  segmentConstraintSlack(p, ax, ay, noisy), 1e-12);

    // The plan's own faces and deltas: face 3 (left) then face 2 (top).
    CcPlan plan;
    plan.steps = 2;
    for (int t = 0; t <= 2; ++t) {
        plan.meanX[t] = ax[t];
        plan.meanY[t] = ay[t];
    }
    plan.face[0][0] = 3;
    plan.face[1][0] = 2;
    for (int t = 0; t < 2; ++t) {
        plan.delta[t][0][0] = noisy.delta[t][0][0];
        plan.delta[t][0][1] = noisy.delta[t][0][1];
    }
    DOUBLES_EQUAL(segmentConstraintSlack(p, ax, ay, noisy), planReportedSlack(p, plan), 1e-12);
    plan.face[1][0] = 0;  // the bottom face does not hold for segment 1
    CHECK(planReportedSlack(p, plan) < -5.0);
}

TEST(CcCommon, ValidateProblemNamesWhatIsWrong) {
    CcProblem p = openSite(0, 0, 10, 10, 4);
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(2, -2, 6, 4, 1);
    STRCMP_EQUAL("", validateProblem(p).c_str());
    CcProblem bad = p;
    bad.steps = 0;
    CHECK(validateProblem(bad).find("steps") != std::string::npos);
    bad = p;
    bad.riskBound = 0.5;
    CHECK(validateProblem(bad).find("riskBound") != std::string::npos);
    bad = p;
    bad.startCov[1] = 0.1;  // not symmetric
    CHECK(validateProblem(bad).find("startCov") != std::string::npos);
    bad = p;
    bad.obstacles[0].normalX[1] = 2.0;
    CHECK(validateProblem(bad).find("non-unit") != std::string::npos);
    bad = p;
    bad.goalX = 30.0;
    CHECK(validateProblem(bad).find("goal outside") != std::string::npos);
}

TEST(CcCommon, QuantileInterpolatesBetweenOrderStatistics) {
    CHECK(std::isnan(quantile({}, 0.5)));
    DOUBLES_EQUAL(7.0, quantile({7.0}, 0.9), 0.0);
    const std::vector<double> v = {4.0, 1.0, 3.0, 2.0};  // unsorted on purpose
    DOUBLES_EQUAL(1.0, quantile(v, 0.0), 0.0);
    DOUBLES_EQUAL(4.0, quantile(v, 1.0), 0.0);
    DOUBLES_EQUAL(2.5, quantile(v, 0.5), 1e-15);    // median of an even count: the midpoint
    DOUBLES_EQUAL(1.75, quantile(v, 0.25), 1e-15);  // position 0.75 between 1 and 2
    DOUBLES_EQUAL(3.0, quantile({5.0, 3.0, 1.0}, 0.5), 0.0);
    DOUBLES_EQUAL(1.0, quantile(v, -1.0), 0.0);     // clamped
    DOUBLES_EQUAL(4.0, quantile(v, 2.0), 0.0);
    // An infinite value does not spoil the order statistics below it.
    const std::vector<double> w = {1.0, 2.0, INFINITY};
    DOUBLES_EQUAL(2.0, quantile(w, 0.5), 0.0);
    CHECK(std::isinf(quantile(w, 1.0)));
}

namespace {

ProofPass provenAt(double optimum) {
    ProofPass p;
    p.ran = true;
    p.proven = true;
    p.cost = optimum;
    p.bound = optimum;
    return p;
}

ProofPass boundOnly(double bound, double incumbent = INFINITY) {
    ProofPass p;
    p.ran = true;
    p.cost = incumbent;
    p.bound = bound;
    return p;
}

ProofPass noneBelow(double cutoff) {
    ProofPass p;
    p.ran = true;
    p.noneBelowCutoff = true;
    p.cutoff = cutoff;
    p.bound = cutoff;
    p.cost = INFINITY;
    return p;
}

}  // namespace

TEST(CcCommon, CombineProofsTakesTheUnaidedOptimumThenTheAidedOptimumThenTheCutoffThenTheBound) {
    const ProofPass notRun;
    // The unaided proof comes first even when the aided pass proved something too.
    GapVerdict v = combineProofs(10.2, provenAt(10.0), provenAt(10.1));
    CHECK(v.source == GapSource::kProvenUnaided);
    CHECK(v.proven());
    DOUBLES_EQUAL(10.0, v.reference, 0.0);
    DOUBLES_EQUAL(0.02, v.gap, 1e-12);
    // Unaided at its limit: the aided optimum.
    v = combineProofs(10.2, boundOnly(9.0, 10.5), provenAt(10.0));
    CHECK(v.source == GapSource::kProvenAided);
    DOUBLES_EQUAL(0.02, v.gap, 1e-12);
    // Nothing below the cutoff 10.2 (1 + 1e-7): optimal within 1e-7, gap 0.
    v = combineProofs(10.2, boundOnly(9.0), noneBelow(10.2 * (1.0 + 1e-7)));
    CHECK(v.source == GapSource::kProvenByCutoff);
    CHECK(v.proven());
    DOUBLES_EQUAL(0.0, v.gap, 0.0);
    // A cutoff below the cost proves a positive gap bound only, never a negative one.
    v = combineProofs(10.2, notRun, noneBelow(10.0));
    CHECK(v.source == GapSource::kProvenByCutoff);
    DOUBLES_EQUAL(0.02, v.gap, 1e-12);
    // Neither proved: the larger of the two bounds.
    v = combineProofs(10.2, boundOnly(9.0, 10.4), boundOnly(10.0));
    CHECK(v.source == GapSource::kBound);
    CHECK(!v.proven());
    DOUBLES_EQUAL(10.0, v.reference, 0.0);
    DOUBLES_EQUAL(0.02, v.gap, 1e-12);
    v = combineProofs(10.2, boundOnly(10.0), boundOnly(9.0));
    DOUBLES_EQUAL(10.0, v.reference, 0.0);
    // A pass that did not run does not count, whatever its fields say.
    ProofPass ghost = provenAt(5.0);
    ghost.ran = false;
    v = combineProofs(10.2, boundOnly(9.0), ghost);
    CHECK(v.source == GapSource::kBound);
    DOUBLES_EQUAL(9.0, v.reference, 0.0);
    // No plan on our side: an infinite gap; no optimum and no positive bound: no gap.
    v = combineProofs(INFINITY, provenAt(10.0), notRun);
    CHECK(std::isinf(v.gap));
    v = combineProofs(10.2, boundOnly(-INFINITY), notRun);
    CHECK(v.source == GapSource::kNone);
    CHECK(std::isnan(v.gap));
    v = combineProofs(10.2, boundOnly(0.0), boundOnly(NAN));
    CHECK(v.source == GapSource::kNone);
}

TEST(CcCommon, ProofsConsistentCatchesAnOptimumBelowTheOtherPassesBound) {
    const ProofPass notRun;
    CHECK(proofsConsistent(provenAt(10.0), provenAt(10.0 * (1.0 + 1e-8)), 1e-6));
    CHECK(!proofsConsistent(provenAt(10.0), provenAt(10.1), 1e-6));
    CHECK(proofsConsistent(provenAt(10.0), boundOnly(9.5, 10.3), 1e-6));
    CHECK(!proofsConsistent(provenAt(10.0), boundOnly(10.5), 1e-6));  // a bound above an optimum
    CHECK(!proofsConsistent(noneBelow(10.5), provenAt(10.0), 1e-6));  // "none below 10.5" but 10 proven
    CHECK(proofsConsistent(noneBelow(10.0 * (1.0 + 1e-7)), provenAt(10.0), 1e-6));
    CHECK(proofsConsistent(provenAt(10.0), notRun, 1e-6));
    CHECK(proofsConsistent(boundOnly(9.0), boundOnly(9.5), 1e-6));  // bounds alone never disagree
}

TEST(CcCommon, CutoffForScalesTheCost) {
    DOUBLES_EQUAL(10.000001, cutoffFor(10.0, 1e-7), 1e-12);
    DOUBLES_EQUAL(33.0, cutoffFor(33.0, 0.0), 0.0);
    CHECK(cutoffFor(33.0, 1e-7) > 33.0);
}

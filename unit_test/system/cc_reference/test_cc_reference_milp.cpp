// The exact MILP reference (unit_test/bench/cc_reference_milp.hpp, COIN-OR
// CBC; host only: this file is left out of the aarch64 build) on cases with a
// hand-computed optimum, the corner-cutting fact, its search shortcuts against
// the plain search, infeasible and bad problems, and a generated instance's
// plan checked independently (constraints, Monte Carlo risk within Delta).
#include <cmath>
#include <cstdint>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"
#include "unit_test/bench/cc_instances.hpp"
#include "unit_test/bench/cc_monte_carlo.hpp"
#include "unit_test/bench/cc_reference_milp.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::test::cc;
using rse::deliberative::CcStatus;

namespace {

constexpr double kPi = 3.14159265358979323846;

CcProblem site(double startX, double startY, double goalX, double goalY, std::uint8_t steps) {
    CcProblem p;
    p.steps = steps;
    p.startX = startX;
    p.startY = startY;
    p.goalX = goalX;
    p.goalY = goalY;
    p.xMin = -1.0;
    p.xMax = 11.0;
    p.yMin = -5.0;
    p.yMax = 5.0;
    p.riskBound = 0.05;
    return p;
}

MilpOptions options(double seconds = 60.0) {
    MilpOptions o;
    o.timeLimitS = seconds;
    return o;
}

void checkEnds(const CcProblem& p, const CcPlan& plan) {
    LONGS_EQUAL(p.steps, plan.steps);
    DOUBLES_EQUAL(p.startX, plan.meanX[0], 0.0);
    DOUBLES_EQUAL(p.startY, plan.meanY[0], 0.0);
    DOUBLES_EQUAL(p.goalX, plan.meanX[p.steps], 0.0);
    DOUBLES_EQUAL(p.goalY, plan.meanY[p.steps], 0.0);
    DOUBLES_EQUAL(kgonLength(plan.meanX, plan.meanY, p.steps), plan.cost, 1e-12);
    DOUBLES_EQUAL(euclideanLength(plan.meanX, plan.meanY, p.steps), plan.euclideanLengthM, 1e-12);
}

}  // namespace

// CBC keeps some allocations (message handlers, ...) past a solve; they are not
// the code under test's, so the leak check is off in this group.
TEST_GROUP(CcReferenceMilp) {
    void setup() override { MemoryLeakWarningPlugin::saveAndDisableNewDeleteOverloads(); }
    void teardown() override { MemoryLeakWarningPlugin::restoreNewDeleteOverloads(); }
};

TEST(CcReferenceMilp, WithoutObstaclesTheStraightLineAtItsKgonLength) {
    CcProblem p = site(1, 2, 9, 5, 6);
    p.startCov[0] = 0.01;
    p.startCov[3] = 0.01;
    p.processSigmaM = 0.05;
    const MilpResult r = solveReferenceMilp(p, options());
    CHECK(r.plan.status == CcStatus::kOptimal);
    checkEnds(p, r.plan);
    // (8, 3) is 20.6 deg from the x axis, nearest the 16-gon normal at 22.5 deg.
    const double expected = 8.0 * std::cos(kPi / 8.0) + 3.0 * std::sin(kPi / 8.0);
    DOUBLES_EQUAL(expected, r.cost, 1e-9);
    DOUBLES_EQUAL(expected, r.bestBound, 1e-6);
    CHECK(r.gap <= 1e-6);
    DOUBLES_EQUAL(0.0, r.plan.riskUsed, 0.0);
    LONGS_EQUAL(0, r.binaries);
}

TEST(CcReferenceMilp, OneBoxOnTheLineIsPassedAtItsCornersWithoutNoise) {
    CcProblem p = site(0, 0, 10, 0, 4);
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(4, -1, 6, 1, 1);
    const MilpResult r = solveReferenceMilp(p, options());
    CHECK(r.plan.status == CcStatus::kOptimal);
    checkEnds(p, r.plan);
    // (0,0) -> (4,1) -> (6,1) -> (10,0): (4, 1) is 14 deg up, nearest the 22.5 deg normal.
    const double expected = 2.0 * (4.0 * std::cos(kPi / 8.0) + std::sin(kPi / 8.0)) + 2.0;
    DOUBLES_EQUAL(expected, r.cost, 1e-6);
    CHECK(!meanPathHitsObstacle(p, r.plan.meanX, r.plan.meanY));
    CHECK(r.constraintSlack >= -1e-7);
    CHECK(planReportedSlack(p, r.plan) >= -1e-7);
    DOUBLES_EQUAL(0.05, r.plan.riskUsed, 1e-15);
}

TEST(CcReferenceMilp, StartUncertaintyInflatesTheBoxByTheMargin) {
    // Sigma_0 = 0.2^2 I, sigma = 0: every margin is PhiInv(1 - Delta / 8) 0.2.
    CcProblem p = site(0, 0, 10, 0, 4);
    p.startCov[0] = 0.04;
    p.startCov[3] = 0.04;
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(4, -1, 6, 1, 1);
    const double m = normalUpperQuantile(0.05 / 8.0) * 0.2;
    const MilpResult r = solveReferenceMilp(p, options());
    CHECK(r.plan.status == CcStatus::kOptimal);
    // Around the inflated box: (4 - m, 1 + m) is 23 deg up, still nearest 22.5 deg.
    const double expected =
        2.0 * ((4.0 - m) * std::cos(kPi / 8.0) + (1.0 + m) * std::sin(kPi / 8.0)) + 2.0 + 2.0 * m;
    DOUBLES_EQUAL(expected, r.cost, 1e-6);
    CHECK(r.constraintSlack >= -1e-7);
    // The given split is used: halve every delta and the detour grows.
    RiskSplit tighter = evenSplit(p);
    for (auto& t : tighter.delta) {
        for (auto& i : t) {
            i[0] *= 0.5;
            i[1] *= 0.5;
        }
    }
    const MilpResult t = solveReferenceMilp(p, tighter, options());
    CHECK(t.plan.status == CcStatus::kOptimal);
    const double m2 = normalUpperQuantile(0.05 / 16.0) * 0.2;
    DOUBLES_EQUAL(2.0 * ((4.0 - m2) * std::cos(kPi / 8.0) + (1.0 + m2) * std::sin(kPi / 8.0)) + 2.0 + 2.0 * m2,
                  t.cost, 1e-6);
    DOUBLES_EQUAL(0.025, t.plan.riskUsed, 1e-15);
}

TEST(CcReferenceMilp, WaypointOnlyConstraintsCutTheCornerSegmentConstraintsDoNot) {
    const CcProblem p = diagonalBoxInstance(0.05);
    MilpOptions waypoint = options();
    waypoint.mode = ConstraintMode::kWaypointOnly;
    const MilpResult w = solveReferenceMilp(p, waypoint);
    const MilpResult s = solveReferenceMilp(p, options());
    CHECK(w.plan.status == CcStatus::kOptimal);
    CHECK(s.plan.status == CcStatus::kOptimal);
    checkEnds(p, w.plan);
    checkEnds(p, s.plan);
    // Waypoint-only: the straight diagonal's length, and a segment through the box.
    DOUBLES_EQUAL(10.0 * std::sqrt(2.0), w.cost, 1e-6);
    CHECK(w.constraintSlack >= -1e-7);  // its waypoints are outside (with margins)
    CHECK(meanPathHitsObstacle(p, w.plan.meanX, w.plan.meanY));
    // Segment constraints: around the corner, longer, no segment meets the box.
    CHECK(!meanPathHitsObstacle(p, s.plan.meanX, s.plan.meanY));
    CHECK(s.cost > w.cost + 0.1);
    CHECK(s.constraintSlack >= -1e-7);
    // What that means for the true plant.
    McOptions mc;
    mc.samples = 20000;
    const McResult cut = monteCarloCollision(p, w.plan, mc);
    const McResult safe = monteCarloCollision(p, s.plan, mc);
    CHECK(cut.rate > 0.9);
    CHECK(cut.waypointCollisions < cut.collisions);
    CHECK(safe.upperClopperPearson < p.riskBound);
}

TEST(CcReferenceMilp, RegionSearchAndFixedFaceLpAgreeWithThePlainSearch) {
    InstanceParams params;
    params.steps = 5;
    params.obstacles = 3;
    params.riskBound = 0.01;
    for (std::uint64_t seed = 7; seed < 10; ++seed) {
        const CcProblem p = generateInstance(seed, params);
        MilpOptions plain = options();
        plain.regionTightening = false;
        MilpOptions region = options();
        region.firstPhaseS = 0.0;  // straight to the region search after the first solution
        const MilpResult a = solveReferenceMilp(p, plain);
        const MilpResult b = solveReferenceMilp(p, region);
        CHECK(a.plan.status == CcStatus::kOptimal);
        CHECK(b.plan.status == CcStatus::kOptimal);
        DOUBLES_EQUAL(a.cost, b.cost, 1e-6 * a.cost);
        CHECK(b.bestBound <= b.cost + 1e-9);
        CHECK(b.bestBound >= b.cost * (1.0 - 1e-6) - 1e-7);
        // The LP with the faces the MILP chose has the same optimum.
        std::uint8_t faces[rse::deliberative::kMaxPlanSteps + 1][rse::deliberative::kMaxPlanObstacles] = {};
        for (std::size_t t = 0; t < p.steps; ++t) {
            for (std::size_t i = 0; i < p.obstacleCount; ++i) {
                faces[t][i] = a.plan.face[t][i];
            }
        }
        const MilpResult lp = solveFixedFaceLp(p, evenSplit(p), faces);
        CHECK(lp.plan.status == CcStatus::kOptimal);
        DOUBLES_EQUAL(a.cost, lp.cost, 1e-6 * a.cost);
        CHECK(planReportedSlack(p, a.plan) >= -1e-7);
    }
}

TEST(CcReferenceMilp, AStartPlanIsUsedOnlyWhenItIsAPlan) {
    CcProblem p = site(0, 0, 10, 0, 4);
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(4, -1, 6, 1, 1);
    const double expected = 2.0 * (4.0 * std::cos(kPi / 8.0) + std::sin(kPi / 8.0)) + 2.0;
    // A longer plan (high round the box) seeds the search; the optimum comes out.
    CcPlan around;
    around.steps = 4;
    const double x[] = {0, 3, 7, 10, 10}, y[] = {0, 2, 2, 0, 0};
    for (int t = 0; t <= 4; ++t) {
        around.meanX[t] = x[t];
        around.meanY[t] = y[t];
    }
    MilpOptions o = options();
    o.startPlan = &around;
    MilpResult r = solveReferenceMilp(p, o);
    CHECK(r.startPlanUsed);
    CHECK(r.plan.status == CcStatus::kOptimal);
    DOUBLES_EQUAL(expected, r.cost, 1e-6);
    // Through the box: not a plan, ignored.
    CcPlan through = around;
    through.meanY[1] = 0.0;
    through.meanY[2] = 0.0;
    o.startPlan = &through;
    r = solveReferenceMilp(p, o);
    CHECK(!r.startPlanUsed);
    DOUBLES_EQUAL(expected, r.cost, 1e-6);
    // The optimum itself: kept, and proven.
    const MilpResult first = solveReferenceMilp(p, options());
    o.startPlan = &first.plan;
    r = solveReferenceMilp(p, o);
    CHECK(r.startPlanUsed);
    CHECK(r.plan.status == CcStatus::kOptimal);
    DOUBLES_EQUAL(first.cost, r.cost, 1e-9);
}

TEST(CcReferenceMilp, ACutoffProvesOrRefutesAPlanCost) {
    CcProblem p = site(0, 0, 10, 0, 4);
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(4, -1, 6, 1, 1);
    const double expected = 2.0 * (4.0 * std::cos(kPi / 8.0) + std::sin(kPi / 8.0)) + 2.0;
    for (bool region : {true, false}) {
        MilpOptions o = options();
        o.regionTightening = region;
        // Just above the optimum: the optimum is found below it and proven.
        o.cutoff = cutoffFor(expected, 1e-7);
        MilpResult r = solveReferenceMilp(p, o);
        CHECK(r.plan.status == CcStatus::kOptimal);
        CHECK(!r.noneBelowCutoff);
        DOUBLES_EQUAL(expected, r.cost, 1e-6);
        CHECK(r.cost < o.cutoff);
        CHECK(r.plan.cost < o.cutoff);
        CHECK(segmentConstraintSlack(p, r.plan.meanX, r.plan.meanY, evenSplit(p)) >= -1e-7);
        // A plan 1 % longer than the optimum (a cutoff 1 % above): refuted, the optimum comes out.
        o.cutoff = expected * 1.01;
        r = solveReferenceMilp(p, o);
        CHECK(r.plan.status == CcStatus::kOptimal);
        DOUBLES_EQUAL(expected, r.cost, 1e-6);
        // Just below the optimum: proven that nothing is shorter; no plan, and it is not "infeasible".
        o.cutoff = expected * (1.0 - 1e-4);
        r = solveReferenceMilp(p, o);
        CHECK(r.plan.status == CcStatus::kNoPlan);
        CHECK(r.noneBelowCutoff);
        CHECK(!r.provenInfeasible);
        DOUBLES_EQUAL(o.cutoff, r.bestBound, 1e-12);
        // Below the straight line (10 m): nothing can be that short.
        o.cutoff = 9.0;
        r = solveReferenceMilp(p, o);
        CHECK(r.plan.status == CcStatus::kNoPlan);
        CHECK(r.noneBelowCutoff);
        DOUBLES_EQUAL(9.0, r.bestBound, 1e-12);
    }
    // Without a cutoff nothing is claimed about one.
    const MilpResult plain = solveReferenceMilp(p, options());
    CHECK(!plain.noneBelowCutoff);
    DOUBLES_EQUAL(expected, plain.cost, 1e-6);
}

TEST(CcReferenceMilp, AWallAcrossTheSiteIsProvenInfeasible) {
    CcProblem p = site(0, 0, 10, 0, 4);
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(4, -6, 6, 6, 1);  // wider than the site
    const MilpResult r = solveReferenceMilp(p, options());
    CHECK(r.plan.status == CcStatus::kNoPlan);
    CHECK(r.provenInfeasible);
    CHECK(!r.noneBelowCutoff);
    CHECK(std::isinf(r.cost));
    // Under a cutoff it is "nothing below the cutoff", not a proof of infeasibility.
    MilpOptions o = options();
    o.cutoff = 50.0;
    const MilpResult c = solveReferenceMilp(p, o);
    CHECK(c.plan.status == CcStatus::kNoPlan);
    CHECK(c.noneBelowCutoff);
    CHECK(!c.provenInfeasible);
}

TEST(CcReferenceMilp, BadProblemsAndSplitsAreRefused) {
    CcProblem p = site(0, 0, 10, 0, 4);
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(4, -1, 6, 1, 1);
    CcProblem bad = p;
    bad.steps = 0;
    CHECK(solveReferenceMilp(bad, options()).plan.status == CcStatus::kBadProblem);
    RiskSplit split = evenSplit(p);
    split.delta[3][0][1] = 0.0;
    CHECK(solveReferenceMilp(p, split, options()).plan.status == CcStatus::kBadProblem);
    std::uint8_t faces[rse::deliberative::kMaxPlanSteps + 1][rse::deliberative::kMaxPlanObstacles] = {};
    faces[2][0] = 4;  // a box has faces 0..3
    CHECK(solveFixedFaceLp(p, evenSplit(p), faces).plan.status == CcStatus::kBadProblem);
}

TEST(CcReferenceMilp, GeneratedInstancePlanMeetsEveryConstraintAndTheRiskBound) {
    const CcProblem p = provableSet(0.05, 2)[1];
    const MilpResult r = solveReferenceMilp(p, options(120.0));
    CHECK(r.plan.status == CcStatus::kOptimal);
    checkEnds(p, r.plan);
    CHECK(r.constraintSlack >= -1e-7);
    DOUBLES_EQUAL(r.constraintSlack, segmentConstraintSlack(p, r.plan.meanX, r.plan.meanY, evenSplit(p)), 1e-12);
    CHECK(planReportedSlack(p, r.plan) >= -1e-7);
    CHECK(siteBoundViolation(p, r.plan.meanX, r.plan.meanY) <= 1e-9);
    CHECK(!meanPathHitsObstacle(p, r.plan.meanX, r.plan.meanY));
    DOUBLES_EQUAL(p.riskBound, r.plan.riskUsed, 1e-12);
    CHECK(r.cost >= r.bestBound - 1e-9);
    // The instance blocks the straight path: the plan goes around (longer in
    // Euclidean terms; the 16-gon length of a detour within 11.25 deg of one
    // normal can equal the straight line's).
    const double straightX[] = {p.startX, p.goalX}, straightY[] = {p.startY, p.goalY};
    CHECK(meanPathHitsObstacle(p, straightX, straightY));
    CHECK(r.plan.euclideanLengthM > euclideanLength(straightX, straightY, 1) + 1e-3);
    CHECK(r.cost >= kgonLength(straightX, straightY, 1) - 1e-9);
    // Boole's bound: the true collision probability stays within Delta.
    const McResult mc = monteCarloCollision(p, r.plan);
    CHECK(mc.upperClopperPearson < p.riskBound);
}

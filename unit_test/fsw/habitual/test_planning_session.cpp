// A planning session (fsw/habitual/planning_session.hpp): the straight line
// taken without sampling, RRT* sliced over runs round a mapped rock, the
// query budget of a leg and of a local replan, the cut at a goal region, the
// wait for the rover to come to rest, the repairs, and backing out of a
// remembered hazard's disc. On the default tables and coarse map (rock 0 the
// square x 5..6.5, y 1.8..3.2).
#include <cmath>

#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/habitual/escape_search.hpp"
#include "fsw/habitual/planning_session.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "unit_test/fsw/habitual/habitual_parts.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using habitual::PlanningSession;
using habitual::PlanStep;
using habitual::PlanTrigger;
namespace ev = habitual::events;

namespace {

msg::PoseEstimateMsg pose(double x, double y, double heading = 0.0) {
    msg::PoseEstimateMsg p{};
    p.xM = x;
    p.yM = y;
    p.headingRad = heading;
    p.initialised = 1;
    return p;
}

msg::LegCommandMsg leg(std::uint32_t id, double gx, double gy, double arriveWithinM = 0.0) {
    msg::LegCommandMsg l{};
    l.legId = id;
    l.goalXM = gx;
    l.goalYM = gy;
    l.maxPathLengthM = 50.0;
    l.maxEnergyJ = 50000.0;
    l.arriveWithinM = arriveWithinM;
    return l;
}

// The rest of a run: RRT* slices until the run is over (at most `runs`).
PlanStep runToEnd(PlanningSession& session, const msg::LegCommandMsg& l, PlanStep step, int runs) {
    for (int i = 0; i < runs && step == PlanStep::kQuerying; ++i) {
        step = session.iterate(l);
    }
    return step;
}

}  // namespace

TEST_GROUP(PlanningSession) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    test::EventReader seen{events};
    tables::HabitualTable habitual = test::defaultTable<tables::HabitualTable>();
    tables::CoarseMapTable coarse = test::defaultTable<tables::CoarseMapTable>();
    tables::RoverGeometryTable geometry = test::defaultTable<tables::RoverGeometryTable>();
    habitual::HazardMemory* memory = nullptr;
    PlanningSession* session = nullptr;

    void setup() override {
        // The planner is about 1 MB: not on the stack.
        memory = new habitual::HazardMemory(events, coarse);
        session = new PlanningSession(*memory, events, habitual, coarse, geometry);
        session->beginLeg();
        session->begin(PlanTrigger::kNewLeg, 0);
    }
    void teardown() override {
        delete session;
        delete memory;
    }
};

TEST(PlanningSession, AFreeStraightSegmentIsTakenWithoutSampling) {
    const msg::LegCommandMsg l = leg(1, 4.0, 0.0);
    CHECK(PlanStep::kFinished == session->start(l, pose(0.0, 0.0)));
    LONGS_EQUAL(2, session->pathCount());
    DOUBLES_EQUAL(4.0, session->path()[1].x, 0.0);
    CHECK_TRUE(session->lastQuery().straightLine);
    LONGS_EQUAL(0, session->lastQuery().iterations);
    DOUBLES_EQUAL(4.0, session->lastQuery().lengthM, 1e-9);
    LONGS_EQUAL(1, session->counters().planningRuns);
    CHECK_FALSE(session->querying());
}

TEST(PlanningSession, RrtStarRoundARockIsSlicedOverRunsAndTheResultIsFree) {
    const msg::LegCommandMsg l = leg(1, 9.0, 2.5);
    PlanStep step = session->start(l, pose(3.0, 2.5));
    CHECK(PlanStep::kQuerying == step);
    CHECK_TRUE(session->querying());
    step = runToEnd(*session, l, step, 10);
    CHECK(PlanStep::kFinished == step);
    CHECK_FALSE(session->querying());
    const std::size_t n = session->pathCount();
    CHECK(n >= 3);
    CHECK(n <= msg::kMaxTrajectoryPoints);
    DOUBLES_EQUAL(3.0, session->path()[0].x, 0.0);
    DOUBLES_EQUAL(9.0, session->path()[n - 1].x, 0.0);
    DOUBLES_EQUAL(2.5, session->path()[n - 1].y, 0.0);
    for (std::size_t i = 0; i + 1 < n; ++i) {
        CHECK_TRUE(memory->checkMap().segmentFree(session->path()[i], session->path()[i + 1]));
    }
    const habitual::PlannerQueryStats& q = session->lastQuery();
    CHECK_FALSE(q.straightLine);
    CHECK(q.iterations > 0);
    CHECK(q.iterations <= habitual.rrt_iterations);
    CHECK(q.taskRuns >= 1);
    CHECK(q.taskRuns <= (habitual.rrt_iterations + habitual::kRrtIterationsPerRun - 1) / habitual::kRrtIterationsPerRun);
    LONGS_EQUAL(1, session->counters().planningRuns);
}

TEST(PlanningSession, APlanningRunAllocatesNothing) {
    const msg::LegCommandMsg l = leg(1, 9.0, 2.5);
    test::AllocationWatch watch;
    const PlanStep step = runToEnd(*session, l, session->start(l, pose(3.0, 2.5)), 10);
    LONGS_EQUAL(0, watch.count());
    CHECK(PlanStep::kFinished == step);
}

TEST(PlanningSession, ALegsFirstRunHasTheWholeBudgetAReplanTheTimedOne) {
    habitual.replan_budget_ms = 1;
    LONGS_EQUAL(habitual.rrt_iterations, session->queryBudget());  // a new leg's first run: untimed
    session->begin(PlanTrigger::kPathBlocked, 0);
    LONGS_EQUAL(habitual::kRrtIterationsPerMs, session->queryBudget());
    session->begin(PlanTrigger::kNewLeg, 1);  // a repair of a new leg's session
    LONGS_EQUAL(habitual::kRrtIterationsPerMs, session->queryBudget());
    habitual.replan_budget_ms = 50;  // 37 500 iterations: the table's total caps it
    LONGS_EQUAL(habitual.rrt_iterations, session->queryBudget());
}

TEST(PlanningSession, AGoalRegionsPathEndsWhereItEntersTheRegion) {
    const msg::LegCommandMsg l = leg(1, 20.0, 0.0, 3.0);
    const double tolerance = static_cast<double>(habitual.goal_tolerance_m);
    DOUBLES_EQUAL(3.0, habitual::legArrivalM(habitual, l), 0.0);
    DOUBLES_EQUAL(3.0 - tolerance, habitual::legStopShortM(habitual, l), 1e-6);
    CHECK(PlanStep::kFinished == session->start(l, pose(0.0, 0.0)));
    LONGS_EQUAL(2, session->pathCount());
    DOUBLES_EQUAL(20.0 - (3.0 - tolerance), session->path()[1].x, 1e-6);
    // A radius under the tolerance is the point.
    const msg::LegCommandMsg point = leg(2, 20.0, 0.0, 0.2);
    DOUBLES_EQUAL(tolerance, habitual::legArrivalM(habitual, point), 0.0);
    DOUBLES_EQUAL(0.0, habitual::legStopShortM(habitual, point), 0.0);
}

TEST(PlanningSession, TheRoverMustComeToRestOrTheWaitRunOut) {
    msg::PoseEstimateMsg moving = pose(0.0, 0.0);
    moving.speedMS = 0.1;
    CHECK_TRUE(session->settling(moving));
    CHECK_FALSE(session->settling(pose(0.0, 0.0)));
    for (std::uint32_t i = 0; i < habitual::kMaxRestWaitRuns; ++i) {
        CHECK_TRUE(session->settling(moving));
        session->waitForRest();
    }
    CHECK_FALSE(session->settling(moving));
    session->restartRestWait();
    CHECK_TRUE(session->settling(moving));
    session->begin(PlanTrigger::kPathBlocked, 0);
    moving.speedMS = 0.0;
    moving.yawRateRadS = 0.05;
    CHECK_TRUE(session->settling(moving));
}

TEST(PlanningSession, RepairsRunUpToTheTablesCount) {
    LONGS_EQUAL(habitual.repair_attempts, session->lastAttempt());
    LONGS_EQUAL(0, session->attempt());
    for (unsigned i = 0; i < habitual.repair_attempts; ++i) {
        CHECK_TRUE(session->repairLeft());
        session->nextAttempt();
    }
    CHECK_FALSE(session->repairLeft());
    LONGS_EQUAL(habitual.repair_attempts, session->attempt());
    session->begin(PlanTrigger::kEnergy, 1);  // new power factors: the first run is already a repair
    LONGS_EQUAL(1, session->attempt());
    CHECK(PlanTrigger::kEnergy == session->trigger());
    STRCMP_EQUAL("energy", habitual::triggerName(session->trigger()));
}

TEST(PlanningSession, AStartInsideARememberedDiscBacksOutFirstAtMostThreeTimesALeg) {
    msg::HazardMsg hazards{};
    hazards.count = 1;
    hazards.sightings[0] = test::sighting(6, 1.6, 0.0, 0.4);  // disc centre (20, -6) from (18, -6)
    memory->remember(hazards, Point2{18.0, -6.0}, 0.0);
    const msg::LegCommandMsg l = leg(1, 25.0, -6.0);
    CHECK(PlanStep::kEscape == session->start(l, pose(19.0, -6.0, 0.0)));
    CHECK_FALSE(session->escapeOffSite());
    DOUBLES_EQUAL(-6.0, session->escapeExit().y, 1e-9);
    CHECK(session->escapeExit().x < 19.0);
    DOUBLES_EQUAL(19.0, session->queryStart().x, 0.0);
    LONGS_EQUAL(1, session->escapesThisLeg());
    LONGS_EQUAL(0, session->counters().planningRuns);  // a back-out is no planning run
    CHECK(PlanStep::kEscape == session->start(l, pose(19.0, -6.0, 0.0)));
    CHECK(PlanStep::kEscape == session->start(l, pose(19.0, -6.0, 0.0)));
    LONGS_EQUAL(habitual::kMaxEscapesPerLeg, session->escapesThisLeg());
    // No more this leg: RRT* refuses the start, the run finds no path.
    seen.take();
    CHECK(PlanStep::kFinished == session->start(l, pose(19.0, -6.0, 0.0)));
    LONGS_EQUAL(0, session->pathCount());
    LONGS_EQUAL(1, session->counters().plannerRefused);
    LONGS_EQUAL(1, session->counters().noPathRuns);
    LONGS_EQUAL(3, session->counters().escapes);
    seen.take();
    CHECK_TRUE(seen.says(ev::kPlannerRefused, "habitual: leg 1: RRT* refused"));
    CHECK_TRUE(seen.says(ev::kPlannerRefused, "start blocked, goal free (1 so far)"));
    session->beginLeg();
    CHECK(PlanStep::kEscape == session->start(l, pose(19.0, -6.0, 0.0)));
}

TEST(PlanningSession, AStartOffTheSiteDrivesBackOntoIt) {
    const msg::LegCommandMsg l = leg(1, 2.0, 0.0);
    CHECK(PlanStep::kEscape == session->start(l, pose(-6.0, 0.0)));
    CHECK_TRUE(session->escapeOffSite());
    const double footprint = geometry::clearanceRadiusM(geometry);
    DOUBLES_EQUAL(-5.0 + footprint + habitual::kPlanMarginM + habitual::kEscapeExtraM, session->escapeExit().x, 1e-9);
}

TEST(PlanningSession, TheMarginIsCutOnlyAsFarAsTheStartNeeds) {
    // 0.2 m beyond the footprint west of rock 0 (x 5..6.5, y 1.8..3.2): inside
    // the margin, outside half of it.
    const double footprint = geometry::clearanceRadiusM(geometry);
    const double x = 5.0 - footprint - 0.2;
    CHECK(PlanStep::kFinished == session->start(leg(1, x, -3.0), pose(x, 2.5)));
    LONGS_EQUAL(2, session->pathCount());
    CHECK_TRUE(session->lastQuery().marginDropped);
    // A start clear of the margin keeps it.
    session->begin(PlanTrigger::kNewLeg, 0);
    CHECK(PlanStep::kFinished == session->start(leg(2, 3.0, 0.0), pose(0.0, 0.0)));
    CHECK_FALSE(session->lastQuery().marginDropped);
}

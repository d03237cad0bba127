// The habitual task's part in recoveries (issue 13), on the bus
// (habitual_rig.hpp): the hazards it remembers published for the deliberative
// layer, fault protection's mission hold, backing out of a seen hazard's
// footprint, and HABITUAL.replan_budget_ms bounding a local replan.
#include <cmath>
#include <cstring>

#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "unit_test/fsw/habitual/habitual_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using msg::HabitualState;
using msg::LegConstraint;
using test::HabitualRig;
namespace ev = habitual::events;

namespace {

constexpr std::uint8_t kAutonomous = 2;

bool trajectoryFree(const habitual::LocalMap& map, const msg::TrajectoryMsg& t) {
    for (std::size_t i = 0; i + 1 < t.count; ++i) {
        if (!map.segmentFree(Point2{t.points[i].xM, t.points[i].yM}, Point2{t.points[i + 1].xM, t.points[i + 1].yM})) {
            return false;
        }
    }
    return t.count >= 2;
}

}  // namespace

TEST_GROUP(HabitualRecovery) {
    HabitualRig* rig = nullptr;
    double footprint = 0.0;
    void setup() override {
        rig = new HabitualRig();
        CHECK_TRUE(rig->init());
        // The energy model of test_habitual_task.cpp: legs of tens of metres fit.
        tables::HabitualTable pinned = rig->tables.habitual();
        pinned.drive_energy_j_per_m = 60.0F;
        pinned.turn_energy_j_per_rad = 40.0F;
        CHECK_TRUE(rig->loadTable(tables::TableId::kHabitual, pinned, 99));
        rig->setMode(kAutonomous);
        rig->run();
        rig->clearSeen();
        footprint = static_cast<double>(rig->tables.roverGeometry().footprint_radius_m);
    }
    void teardown() override { delete rig; }

    bool driving() { return rig->task.state() == HabitualState::kDriving; }
    bool inState(HabitualState s) { return rig->task.state() == s; }
    void setReplanBudget(std::uint16_t ms) {
        tables::HabitualTable t = rig->tables.habitual();
        t.replan_budget_ms = ms;
        CHECK_TRUE(rig->loadTable(tables::TableId::kHabitual, t, 100 + ms));
    }
};

// ---- the remembered hazards on the bus --------------------------------------------

TEST(HabitualRecovery, RememberedHazardsArePublishedWhenTheyChangeAndAtOneHertz) {
    rig->runFor(10);
    CHECK(rig->hazardMaps >= 1);
    LONGS_EQUAL(0, rig->lastHazards.count);
    rig->addHiddenDisc(3, 12.6, 0.05, 0.65);
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return rig->task.counters().pathBlocked > 0; }, 400));
    LONGS_EQUAL(1, rig->lastHazards.count);
    const habitual::RememberedHazard* h = nullptr;
    for (std::size_t k = 0; k < habitual::kMaxMapDiscs; ++k) {
        h = rig->task.mapBuilder().slot(k).used ? &rig->task.mapBuilder().slot(k) : h;
    }
    CHECK(h != nullptr);
    LONGS_EQUAL(3, rig->lastHazards.hazards[0].obstacleId);
    // The deliberative layer is told the seen disc, not the habitual layer's
    // cover (map_builder.hpp): the estimate of the rock, inside the cover's reach.
    DOUBLES_EQUAL(h->seenCentre.x, static_cast<double>(rig->lastHazards.hazards[0].xM), 1e-5);
    DOUBLES_EQUAL(h->seenCentre.y, static_cast<double>(rig->lastHazards.hazards[0].yM), 1e-5);
    DOUBLES_EQUAL(h->seenRadiusM, static_cast<double>(rig->lastHazards.hazards[0].radiusM), 1e-5);
    CHECK(h->seenRadiusM < h->radiusM);
    LONGS_EQUAL(rig->task.mapBuilder().revision(), rig->lastHazards.revision);
    // Unchanged: once a second, not every run.
    rig->follow = false;
    rig->hazardRangeM = 0.0;
    const unsigned before = rig->hazardMaps;
    rig->runFor(30);
    CHECK(rig->hazardMaps - before >= 2);
    CHECK(rig->hazardMaps - before <= 4);
}

// ---- mission hold ------------------------------------------------------------------

TEST(HabitualRecovery, AHoldStopsTheRoverKeepsTheLegAndNeverFailsUpUntilReleased) {
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    rig->runFor(20);
    const unsigned stops = rig->stops;
    const unsigned plans = rig->plans;
    rig->sendHold(1U << msg::hold::kDriveRecovery, 0, 1);
    rig->run();
    CHECK_TRUE(rig->task.held());
    LONGS_EQUAL(stops + 1, rig->stops);
    LONGS_EQUAL(0, rig->trajectory.count);
    LONGS_EQUAL(1, rig->seenCount(ev::kMissionHeld));
    const double heldAt = rig->x;
    // The follower gives up on the held drives: no fail-up, no replan.
    rig->sendFollower(msg::FollowerState::kCannotFollow, msg::FollowReason::kDrivesHeld);
    rig->runFor(50);
    CHECK(driving());  // the leg is kept
    LONGS_EQUAL(1, rig->lastReport.legId);
    LONGS_EQUAL(0, rig->task.counters().failUps);
    LONGS_EQUAL(plans, rig->plans);
    DOUBLES_EQUAL(heldAt, rig->x, 1e-12);
    CHECK(rig->task.counters().heldRuns >= 50);
    // Released: stopped until the deliberative layer re-sends the leg, then driven.
    rig->sendHold(0, 1);
    rig->run();
    CHECK_FALSE(rig->task.held());
    LONGS_EQUAL(1, rig->seenCount(ev::kMissionReleased));
    LONGS_EQUAL(plans, rig->plans);
    rig->sendLeg(2, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving() && rig->plans > plans; }, 10));
    DOUBLES_EQUAL(heldAt, rig->trajectory.points[0].xM, 1e-9);
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 900));
}

TEST(HabitualRecovery, AHoldDuringPlanningSendsNoTrajectoryUntilReleased) {
    rig->addHiddenDisc(3, 6.0, 0.0, 0.6);  // close: the first plan must go round it
    rig->run();
    rig->sendHold(1U << msg::hold::kPoseUncertain, 0);
    rig->sendLeg(1, 12.0, 0.0, 40.0, 5000.0);
    rig->runFor(20);
    LONGS_EQUAL(0, rig->plans);
    CHECK(inState(HabitualState::kPlanning));
    rig->sendHold(0, 1);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 20));
    LONGS_EQUAL(1, rig->plans);
}

TEST(HabitualRecovery, AHoldWithUnknownReasonBitsIsMalformed) {
    rig->sendHold(1U << msg::hold::kCount, 0);
    rig->run();
    CHECK_FALSE(rig->task.held());
    LONGS_EQUAL(1, rig->task.counters().malformedInputs);
}

// ---- backing out of a seen hazard's footprint -------------------------------------

TEST(HabitualRecovery, AStartInsideASeenHazardsFootprintBacksOutThenPlansRoundIt) {
    rig->x = 10.0;
    // Seen from 0.7 m: remembered with radius 1.5 x 0.5, so the rover's centre
    // (1.2 m from its centre) lies within the disc grown by the footprint.
    rig->addHiddenDisc(3, 11.2, 0.0, 0.5);
    rig->run();
    LONGS_EQUAL(1, rig->task.mapBuilder().rememberedCount());
    rig->sendLeg(1, 16.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 10));
    CHECK_TRUE(rig->task.escaping());
    LONGS_EQUAL(1, rig->task.counters().escapes);
    LONGS_EQUAL(1, rig->seenCount(ev::kEscape));
    const msg::TrajectoryMsg out = rig->trajectory;
    LONGS_EQUAL(2, out.count);
    DOUBLES_EQUAL(10.0, out.points[0].xM, 1e-9);
    // Straight away from the disc's centre, to where it is clear with the planning margin.
    const habitual::RememberedHazard* h = &rig->task.mapBuilder().slot(0);
    const double reach = std::hypot(out.points[1].xM - h->centre.x, out.points[1].yM - h->centre.y);
    CHECK(reach >= h->radiusM + footprint + habitual::kPlanMarginM);
    CHECK(reach <= h->radiusM + footprint + habitual::kPlanMarginM + habitual::kEscapeExtraM + 1e-9);
    CHECK(out.points[1].xM < 10.0);
    // Reached: planned again from there, round the rock, to the leg end.
    CHECK_TRUE(rig->runUntil([&] { return driving() && !rig->task.escaping(); }, 80));
    CHECK(rig->trajectory.count >= 3);
    CHECK_TRUE(trajectoryFree(rig->task.checkMap(), rig->trajectory));
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 900));
    LONGS_EQUAL(0, rig->task.counters().failUps);
}

// ---- HABITUAL.replan_budget_ms --------------------------------------------------------

TEST(HabitualRecovery, TheReplanBudgetBoundsTheIterationsOfALocalReplanButNotOfANewLeg) {
    const std::uint32_t legBudget = rig->tables.habitual().rrt_iterations;
    CHECK(legBudget > habitual::kRrtIterationsPerMs);  // else 1 ms would change nothing
    setReplanBudget(1);
    // A rock the coarse map does not show, in the way of a straight leg: the
    // replan round it may take 1 ms worth of iterations.
    rig->addHiddenDisc(3, 8.0, 0.3, 0.9);
    rig->sendLeg(1, 14.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return rig->task.counters().pathBlocked > 0; }, 400));
    CHECK_TRUE(rig->runUntil([&] { return driving() || inState(HabitualState::kFailedUp); }, 60));
    CHECK(rig->task.lastQuery().iterations > 0);
    CHECK(rig->task.lastQuery().iterations <= habitual::kRrtIterationsPerMs);
    const std::uint32_t bounded = rig->task.lastQuery().iterations;

    // The same with the default 50 ms: the leg's own budget is the bound.
    delete rig;
    setup();
    setReplanBudget(50);
    rig->addHiddenDisc(3, 8.0, 0.3, 0.9);
    rig->sendLeg(1, 14.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return rig->task.counters().pathBlocked > 0; }, 400));
    CHECK_TRUE(rig->runUntil([&] { return driving() || inState(HabitualState::kFailedUp); }, 60));
    CHECK(rig->task.lastQuery().iterations > bounded);
    CHECK(rig->task.lastQuery().iterations <= legBudget);

    // A new leg that needs sampling is not a replan: the whole leg budget.
    delete rig;
    setup();
    setReplanBudget(1);
    rig->x = 3.0;
    rig->y = 2.5;
    rig->sendLeg(1, 9.0, 2.5, 30.0, 5000.0);  // round coarse-map rock 0
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 40));
    CHECK_FALSE(rig->task.lastQuery().straightLine);
    CHECK(rig->task.lastQuery().iterations > habitual::kRrtIterationsPerMs);
}

// ---- off the map: back onto the site ----------------------------------------------

TEST(HabitualRecovery, AStartOffTheSiteDrivesStraightBackOnToTheNearestPointThenOnToTheLegEnd) {
    const double yMin = static_cast<double>(rig->tables.coarseMap().y_min_m);
    rig->x = 3.0;
    rig->y = yMin - 1.2;  // slid off the south edge
    rig->sendLeg(1, 6.0, yMin + 2.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 10));
    CHECK_TRUE(rig->task.escaping());
    LONGS_EQUAL(1, rig->seenCount(ev::kEscape));
    STRCMP_CONTAINS("off the site", rig->seenText(ev::kEscape));
    const msg::TrajectoryMsg in = rig->trajectory;
    LONGS_EQUAL(2, in.count);
    DOUBLES_EQUAL(3.0, in.points[0].xM, 1e-9);
    // Straight north to the nearest point that keeps the planning margin from the edge.
    const double keep = rse::geometry::clearanceRadiusM(rig->tables.roverGeometry()) + habitual::kPlanMarginM +
                        habitual::kEscapeExtraM;
    DOUBLES_EQUAL(3.0, in.points[1].xM, 1e-9);
    DOUBLES_EQUAL(yMin + keep, in.points[1].yM, 1e-9);
    CHECK_TRUE(rig->runUntil([&] { return driving() && !rig->task.escaping(); }, 400));
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 900));
    LONGS_EQUAL(0, rig->task.counters().failUps);
}

TEST(HabitualRecovery, AStartFartherOffTheSiteThanAReentryReachesFailsUp) {
    const double yMin = static_cast<double>(rig->tables.coarseMap().y_min_m);
    rig->x = 3.0;
    rig->y = yMin - habitual::kMaxReentryM;  // the way back on is longer than kMaxReentryM
    rig->sendLeg(1, 6.0, yMin + 2.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kFailedUp); }, 40));
    LONGS_EQUAL(0, rig->task.counters().escapes);
    CHECK(LegConstraint::kNoPath == rig->lastReport.violated);
}

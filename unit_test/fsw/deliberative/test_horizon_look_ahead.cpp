// Site mode's receding horizon (horizon_look_ahead.hpp): the next horizon is
// planned while the rover drives the end of the current one, from that end
// with the covariance of arriving there, and its first leg goes out in the
// run the horizon's last leg is reached; a hazard seen since it started
// makes it stale (planned again), a replan drops it and puts the route
// progress back; the part's decisions and its start covariance on their own.
#include <cmath>
#include <cstdint>
#include <vector>

#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/horizon_look_ahead.hpp"
#include "fsw/geometry/rover_footprint.hpp"
#include "unit_test/fsw/deliberative/deliberative_rig.hpp"
#include "unit_test/fsw/deliberative/site_field.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::Handover;
using deliberative::HorizonLookAhead;
using geometry::Point2;
using test::DeliberativeRig;

namespace {

site_map::SiteMap* siteMap = nullptr;   // ~2 MB: static storage

constexpr double kStepPerRunM = 0.2;    // the rover's drive in the rig: 2 m/s at 10 Hz

// What the flight saw at the horizons' ends.
struct Flight {
    unsigned runs = 0;
    unsigned idleRuns = 0;        // runs after the first leg with no leg to drive (planning or waiting)
    unsigned plans = 0;
    unsigned lookAheadPlans = 0;  // plans whose start is the last leg's end while the rover was short of it
    bool startsAtEnds = true;     // every look-ahead plan starts at the end of the leg then in force
    bool covarianceGrown = true;  // ... with more than the pose's covariance
};

// One run's drive of the habitual layer and the rover: kStepPerRunM towards
// the leg in force, reported achieved (once, *reported its id) at its end.
void driveOneRun(DeliberativeRig* rig, std::uint32_t* reported) {
    const msg::LegCommandMsg& leg = rig->lastLeg;
    if (rig->legs == 0 || leg.legId == *reported || rig->task.state() != msg::DeliberativeState::kExecuting) {
        return;
    }
    const double dx = leg.goalXM - rig->x;
    const double dy = leg.goalYM - rig->y;
    const double d = std::hypot(dx, dy);
    if (d <= kStepPerRunM) {
        *reported = leg.legId;
        rig->achieveLeg();
    } else {
        rig->x += kStepPerRunM * dx / d;
        rig->y += kStepPerRunM * dy / d;
    }
}

// Drives the rover along each leg at kStepPerRunM a run, reporting it
// achieved at its end, until the task completes, calls home or maxRuns pass.
// Every plan is checked against the whole map.
Flight drive(DeliberativeRig* rig, unsigned maxRuns) {
    Flight f;
    std::uint32_t reported = 0;
    std::uint32_t pathsSeen = 0;
    for (; f.runs < maxRuns; ++f.runs) {
        rig->run();
        if (rig->planPaths != pathsSeen) {
            pathsSeen = rig->planPaths;
            ++f.plans;
            test::checkEveryNearRockIsACandidate(rig->task, *siteMap);
        }
        const msg::DeliberativeState s = rig->task.state();
        if (s == msg::DeliberativeState::kComplete || rig->safeRequests > 0) {
            break;
        }
        if (rig->legs > 0 && s != msg::DeliberativeState::kExecuting) {
            ++f.idleRuns;
        }
        // A look-ahead just started: from the end of the leg in force, with
        // the pose's variance grown.
        if (rig->task.lookAhead().planning() && rig->task.counters().lookAheadsStarted > f.lookAheadPlans) {
            ++f.lookAheadPlans;
            const deliberative::CcProblem& p = rig->task.problem();
            const deliberative::LegPlan& legs = rig->task.legs();
            const msg::PlanLeg& end = legs.legs[legs.count - 1];
            f.startsAtEnds = f.startsAtEnds && std::fabs(p.startX - end.xM) < 1e-9 && std::fabs(p.startY - end.yM) < 1e-9;
            f.covarianceGrown = f.covarianceGrown && p.startCov[0] > rig->positionVariance + 1e-6 &&
                                p.startCov[3] > rig->positionVariance + 1e-6;
        }
        driveOneRun(rig, &reported);
    }
    return f;
}

}  // namespace

TEST_GROUP(HorizonLookAhead) {
    void setup() override {
        static site_map::SiteMap storage;
        siteMap = &storage;
        siteMap->clear();
    }
};

TEST(HorizonLookAhead, EveryHorizonEndOfA180MetreTraverseIsDrivenThroughWithoutAStop) {
    test::loadSiteField(siteMap, 0.15, 200.0, 60.0, 7, {{10.0, 30.0}, {190.0, 30.0}});
    DeliberativeRig* rig = new DeliberativeRig(siteMap);
    CHECK(rig->init());
    rig->x = 10.0;
    rig->y = 30.0;
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(190.0, 30.0, 1e-3);
    const Flight f = drive(rig, 20000);
    CHECK(rig->task.state() == msg::DeliberativeState::kComplete);
    LONGS_EQUAL(0, rig->safeRequests);
    const deliberative::DeliberativeCounters& c = rig->task.counters();
    CHECK(c.horizonsReached >= 4);
    // Each horizon's end was a leg end like any other: the next horizon's
    // first leg went out in the run its last leg was reached.
    LONGS_EQUAL(c.horizonsReached, c.horizonsDrivenThrough);
    LONGS_EQUAL(0, c.horizonStops);
    LONGS_EQUAL(c.horizonsReached, rig->seenCount(deliberative::events::kHorizonEnd));
    CHECK(f.lookAheadPlans >= c.horizonsReached);
    CHECK(f.startsAtEnds);
    CHECK(f.covarianceGrown);
    // Once driving, the rover never waited for a plan.
    LONGS_EQUAL(0, f.idleRuns);
    DOUBLES_EQUAL(190.0, rig->x, 0.5);
    DOUBLES_EQUAL(30.0, rig->y, 0.5);
    delete rig;
}

TEST(HorizonLookAhead, AHazardSeenMakesItStaleAndAReplanDropsIt) {
    test::loadSiteField(siteMap, 0.10, 120.0, 60.0, 3, {{10.0, 30.0}, {110.0, 30.0}});
    DeliberativeRig* rig = new DeliberativeRig(siteMap);
    CHECK(rig->init());
    rig->x = 10.0;
    rig->y = 30.0;
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(110.0, 30.0, 1e-3);
    // Drive until the first look-ahead has planned.
    std::uint32_t reported = 0;
    for (int i = 0; i < 4000 && !(rig->task.lookAhead().active() && !rig->task.lookAhead().planning()); ++i) {
        rig->run();
        driveOneRun(rig, &reported);
    }
    CHECK(rig->task.lookAhead().active());
    LONGS_EQUAL(1, rig->task.counters().lookAheadsStarted);
    const std::size_t progress = rig->task.route().progress();
    CHECK(progress >= rig->task.lookAhead().progressBefore());
    // A rock seen: the look-ahead was planned with less than the rover knows
    // now, so it is dropped and started again in the same run, from the
    // route progress put back.
    const Point2 ahead = rig->task.lookAhead().horizon().goal;
    const double seen[1][3] = {{ahead.x - 10.0, ahead.y + 3.0, 0.5}};
    const std::size_t firstBefore = rig->task.lookAhead().progressBefore();
    rig->sendHazards(seen, 1);
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().lookAheadsDropped);
    LONGS_EQUAL(2, rig->task.counters().lookAheadsStarted);
    // Told once: a restart after a sighting is counted, and told at the handover.
    LONGS_EQUAL(0, rig->seenCount(deliberative::events::kLookAheadDropped));
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kLookAheadStarted));
    CHECK(rig->task.lookAhead().planning());
    LONGS_EQUAL(firstBefore, rig->task.lookAhead().progressBefore());
    LONGS_EQUAL(progress, rig->task.route().progress());
    // Planned again with it in its problem; the same list repeated (the
    // habitual layer's 1 Hz message, its revision unchanged) changes nothing.
    CHECK(rig->runUntil([&] { return !rig->task.lookAhead().planning(); }, 400));
    CHECK(rig->task.lookAhead().active());
    rig->hazardRevision -= 1;
    rig->sendHazards(seen, 1);
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().lookAheadsDropped);
    CHECK(rig->task.lookAhead().active());
    // A fail-up on the leg in force: the replan drops the look-ahead and puts
    // the route progress back where the horizon in hand left it, so the
    // replan's horizon starts from the rover's place found from there (the
    // segment nearest the rover from that progress on), not from the
    // look-ahead's start.
    const std::size_t before = rig->task.lookAhead().progressBefore();
    LONGS_EQUAL(firstBefore, before);
    const deliberative::GlobalRoute& route = rig->task.route().route();
    std::size_t nearest = before;
    double best = INFINITY;
    for (std::size_t k = before; k + 1 < route.pointCount(); ++k) {
        const Point2 q = geometry::closestOnSegment(Point2{rig->x, rig->y}, route.point(k), route.point(k + 1));
        const double d = geometry::distanceSquared(Point2{rig->x, rig->y}, q);
        if (d < best) {
            best = d;
            nearest = k;
        }
    }
    rig->report(msg::HabitualState::kFailedUp, msg::LegConstraint::kNoPath);
    rig->run();
    LONGS_EQUAL(2, rig->task.counters().lookAheadsDropped);
    CHECK(!rig->task.lookAhead().active());
    LONGS_EQUAL(1, rig->task.counters().replans);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kLookAheadDropped));
    LONGS_EQUAL(nearest, rig->task.route().progress());
    CHECK(rig->task.route().progress() <= progress);
    delete rig;
}

TEST(HorizonLookAhead, TheStartCovarianceIsThePosesGrownByTheStepsStillToDrive) {
    deliberative::CcPlan plan{};
    plan.steps = 10;
    for (std::size_t t = 0; t <= 10; ++t) {
        plan.meanX[t] = 1.5 * static_cast<double>(t);
        plan.meanY[t] = 0.0;
    }
    // Nearest mean 7 of 10: three steps to go, and the one the rover is in.
    LONGS_EQUAL(4, HorizonLookAhead::stepsToGo(plan, Point2{10.4, 0.3}));
    // At the start: every step (no more than N).
    LONGS_EQUAL(10, HorizonLookAhead::stepsToGo(plan, Point2{-1.0, 0.0}));
    // At the end: the step it is in.
    LONGS_EQUAL(1, HorizonLookAhead::stepsToGo(plan, Point2{15.0, 0.0}));
    const double pose[4] = {0.01, 0.002, 0.002, 0.02};
    double cov[4];
    HorizonLookAhead::startCovariance(pose, 4, 0.05, cov);
    DOUBLES_EQUAL(0.01 + 4 * 0.0025, cov[0], 1e-15);
    DOUBLES_EQUAL(0.002, cov[1], 0.0);
    DOUBLES_EQUAL(0.002, cov[2], 0.0);
    DOUBLES_EQUAL(0.02 + 4 * 0.0025, cov[3], 1e-15);
}

TEST(HorizonLookAhead, AHandoverTakesOnlyAFinishedCurrentPlanAndCountsEveryHorizonEnd) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    HorizonLookAhead ahead(events);
    const Point2 at{0.0, 0.0};
    // None started: planned from the pose.
    CHECK(ahead.due(20.0, true, 10.0));
    CHECK(!ahead.due(12.0, false, 10.0));
    CHECK(ahead.due(9.0, false, 10.0));
    CHECK(ahead.due(12.0, false, 15.0));
    CHECK(!ahead.due(1.0, true, 0.0));   // site_look_ahead_m 0: never
    CHECK(ahead.handover(at, 7, 1, false) == Handover::kPlanFromPose);
    // Started and still planning: finished with the rover stopped.
    ahead.begin(at, 0.15, 4, 3, 7, 1, 1e-3);
    CHECK(!ahead.due(1.0, true, 10.0));   // one at a time
    CHECK(ahead.handover(at, 7, 1, false) == Handover::kFinish);
    // Finished with a plan: taken.
    ahead.begin(at, 0.15, 4, 3, 7, 1, 1e-3);
    ahead.planned();
    CHECK(ahead.handover(at, 7, 1, true) == Handover::kTake);
    // Finished without one: planned from the pose.
    ahead.begin(at, 0.15, 4, 3, 7, 1, 1e-3);
    ahead.planned();
    CHECK(ahead.handover(at, 7, 1, false) == Handover::kPlanFromPose);
    // Finished, but the site map was replaced, or a hazard seen since: stale.
    ahead.begin(at, 0.15, 4, 3, 7, 1, 1e-3);
    ahead.planned();
    CHECK(ahead.handover(at, 7, 2, true) == Handover::kPlanFromPose);
    ahead.begin(at, 0.15, 4, 3, 7, 1, 1e-3);
    ahead.planned();
    CHECK(ahead.handover(at, 8, 1, true) == Handover::kPlanFromPose);
    // Still planning when a hazard was seen: planned from the pose too.
    ahead.begin(at, 0.15, 4, 3, 7, 1, 1e-3);
    CHECK(ahead.handover(at, 8, 1, false) == Handover::kPlanFromPose);
    // Refused (the plan maker would not start it): none this horizon.
    ahead.refused();
    CHECK(!ahead.due(1.0, true, 10.0));
    CHECK(!ahead.active());
    CHECK(ahead.handover(at, 7, 1, true) == Handover::kPlanFromPose);
    const deliberative::LookAheadCounters& c = ahead.counters();
    LONGS_EQUAL(6, c.started);
    LONGS_EQUAL(1, c.handedOver);
    LONGS_EQUAL(1, c.finishedStopped);
    LONGS_EQUAL(6, c.fromPose);
    LONGS_EQUAL(3, c.stale);
    LONGS_EQUAL(3, c.dropped);
    // A drop hands back the route progress to put back; none when idle.
    std::size_t progress = 99;
    CHECK(!ahead.drop("test", false, &progress));
    LONGS_EQUAL(99, progress);
    ahead.begin(at, 0.15, 4, 7, 7, 1, 1e-3);
    CHECK(ahead.drop("test", false, &progress));
    LONGS_EQUAL(7, progress);
    CHECK(!ahead.active());
}

TEST(HorizonLookAhead, ItIsStaleOnceTheSeenHazardsOrTheSiteMapChanged) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    HorizonLookAhead ahead(events);
    ahead.begin(Point2{0.0, 0.0}, 0.15, 4, 0, 41, 5, 1e-3);
    CHECK(!ahead.stale(41, 5));
    CHECK(ahead.stale(42, 5));   // a disc new, refined or forgotten
    CHECK(ahead.stale(41, 6));   // another site map
    LONGS_EQUAL(41, ahead.hazardRevision());
}

// PLANNER's site fields are what the layer uses: with site_look_ahead_m 0 no
// horizon is planned ahead and every horizon's end is a stop; with
// site_horizon_m 20 the horizons reach 20 m along the route; a route margin of
// 1 m keeps the route that much farther off every rock.
TEST(HorizonLookAhead, ThePlannerTablesSiteFieldsAreTheOnesUsed) {
    test::loadSiteField(siteMap, 0.15, 200.0, 60.0, 7, {{10.0, 30.0}, {190.0, 30.0}});
    DeliberativeRig* rig = new DeliberativeRig(siteMap);
    CHECK(rig->init());
    tables::PlannerTable t = rig->tables.planner();
    t.site_look_ahead_m = 0.0F;
    t.site_horizon_m = 20.0F;
    t.site_route_margin_m = 1.0F;
    CHECK_TRUE(rig->loadTable(tables::TableId::kPlanner, t, 60));
    rig->x = 10.0;
    rig->y = 30.0;
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(190.0, 30.0, 1e-3);
    // The first horizon: 20 m along the route from the rover's place.
    CHECK(rig->runUntil([&] { return rig->legs > 0; }, 2000));
    const deliberative::GlobalRoute& route = rig->task.route().route();
    const Point2 goal = rig->task.horizon().goal;
    double along = 0.0;
    bool found = false;
    for (std::size_t k = 0; k + 1 < route.pointCount() && !found; ++k) {
        const Point2 a = route.point(k);
        const Point2 b = route.point(k + 1);
        const Point2 q = geometry::closestOnSegment(goal, a, b);
        if (geometry::distance(q, goal) < 1e-6) {
            along += geometry::distance(a, goal);
            found = true;
        } else {
            along += geometry::distance(a, b);
        }
    }
    CHECK(found);
    DOUBLES_EQUAL(20.0, along, 0.6);   // the rover starts on the route's first point
    // The route keeps the footprint and 1 m off every rock of the map.
    const double kept = geometry::clearanceRadiusM(rig->tables.roverGeometry()) + 1.0;
    for (std::size_t k = 1; k < route.pointCount(); ++k) {
        for (std::size_t r = 0; r < siteMap->rockCount(); ++r) {
            CHECK(test::rockDistance(route.point(k - 1), route.point(k), siteMap->rock(r)) >= kept - 1e-6);
        }
    }
    // No look-ahead: every horizon's end is a stop.
    const Flight f = drive(rig, 20000);
    CHECK(rig->task.state() == msg::DeliberativeState::kComplete);
    const deliberative::DeliberativeCounters& c = rig->task.counters();
    CHECK(c.horizonsReached >= 7);   // 180 m in horizons of 20 m
    LONGS_EQUAL(0, c.lookAheadsStarted);
    LONGS_EQUAL(0, c.horizonsDrivenThrough);
    LONGS_EQUAL(c.horizonsReached, c.horizonStops);
    CHECK(f.idleRuns > 0);
    delete rig;
}

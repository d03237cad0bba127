// The habitual task on the bus, one 10 Hz run at a time, with a synthetic pose
// that follows whatever trajectory the task sends (habitual_rig.hpp): plans,
// replans around a hazard, energy and length violations, repair and fail-up,
// refusals, cancel, mode changes, the follower giving up, and the heap.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "fsw/habitual/habitual_events.hpp"
#include "fsw/habitual/path_shortcut.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/rover_model/power_model.hpp"
#include "unit_test/fsw/habitual/habitual_rig.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using msg::HabitualState;
using msg::LegConstraint;
using test::HabitualRig;
namespace ev = habitual::events;

namespace {

constexpr std::uint8_t kAutonomous = 2;
constexpr std::uint8_t kStandby = 1;

std::size_t trajectoryPoints(const msg::TrajectoryMsg& t, Point2* out) {
    for (std::size_t i = 0; i < t.count; ++i) {
        out[i] = Point2{t.points[i].xM, t.points[i].yM};
    }
    return t.count;
}

// Every segment of t free on map.
bool trajectoryFree(const habitual::LocalMap& map, const msg::TrajectoryMsg& t) {
    for (std::size_t i = 0; i + 1 < t.count; ++i) {
        if (!map.segmentFree(Point2{t.points[i].xM, t.points[i].yM}, Point2{t.points[i + 1].xM, t.points[i + 1].yM})) {
            return false;
        }
    }
    return t.count >= 2;
}

// The newest report about legId, or nullptr.
const msg::LegReportMsg* findReport(const HabitualRig& rig, std::uint32_t legId) {
    const std::size_t n = rig.reportCount < HabitualRig::kMaxReports ? rig.reportCount : HabitualRig::kMaxReports;
    for (std::size_t k = 0; k < n; ++k) {
        const msg::LegReportMsg& r = rig.reports[(rig.reportCount - 1 - k) % HabitualRig::kMaxReports];
        if (r.legId == legId) {
            return &r;
        }
    }
    return nullptr;
}

bool contains(const char* text, const char* part) { return std::strstr(text, part) != nullptr; }

}  // namespace

TEST_GROUP(HabitualTask) {
    HabitualRig* rig = nullptr;
    void setup() override {
        rig = new HabitualRig();
        CHECK_TRUE(rig->init());
        // The figures below are worked out with these model constants and margins;
        // the table's own constants are checked against the simulator by
        // test_power_model_calibration.cpp.
        tables::HabitualTable pinned = rig->tables.habitual();
        pinned.drive_energy_j_per_m = 60.0F;
        pinned.turn_energy_j_per_rad = 40.0F;
        pinned.power_margin_frac = 0.2F;
        pinned.distance_margin_frac = 0.1F;
        CHECK_TRUE(rig->loadTable(tables::TableId::kHabitual, pinned, 100));
        rig->setMode(kAutonomous);
        rig->run();
        rig->clearSeen();
    }
    void teardown() override { delete rig; }

    bool driving() { return rig->task.state() == HabitualState::kDriving; }
    bool inState(HabitualState s) { return rig->task.state() == s; }
};

TEST(HabitualTask, PlansAroundAKnownRockSendsAFreeTrajectoryAndReportsArrival) {
    // Rock 0 of the default coarse map (x 5..6.5, y 1.8..3.2) lies across the line.
    rig->x = 3.0;
    rig->y = 2.5;
    rig->sendLeg(1, 9.0, 2.5, 30.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 40));
    LONGS_EQUAL(1, rig->stops);  // held stopped while planning
    LONGS_EQUAL(1, rig->plans);

    const msg::TrajectoryMsg t = rig->trajectory;
    CHECK(t.count >= 3);
    CHECK(t.count <= msg::kMaxTrajectoryPoints);
    LONGS_EQUAL(1, t.legId);
    CHECK(t.trajectoryId != 0);
    DOUBLES_EQUAL(static_cast<double>(rig->tables.habitual().cruise_speed_m_s), t.speedMS, 1e-9);
    DOUBLES_EQUAL(3.0, t.points[0].xM, 1e-9);
    DOUBLES_EQUAL(2.5, t.points[0].yM, 1e-9);
    DOUBLES_EQUAL(9.0, t.points[t.count - 1].xM, 1e-9);
    DOUBLES_EQUAL(2.5, t.points[t.count - 1].yM, 1e-9);
    // Free on the task's map and on one built independently from the tables.
    CHECK_TRUE(trajectoryFree(rig->task.checkMap(), t));
    habitual::MapBuilder builder;
    habitual::LocalMap map;
    CHECK(core::Status::kOk ==
          builder.build(rig->tables.coarseMap(), static_cast<double>(rig->tables.roverGeometry().footprint_radius_m), &map));
    CHECK_TRUE(trajectoryFree(map, t));
    // It was RRT*, not the straight line, within the table's budget.
    CHECK_FALSE(rig->task.lastQuery().straightLine);
    CHECK(rig->task.lastQuery().iterations > 0);
    CHECK(rig->task.lastQuery().iterations <= rig->tables.habitual().rrt_iterations);
    CHECK(rig->task.lastQuery().taskRuns >= 1);

    // The report carries the prediction against the allowed figures.
    Point2 pts[msg::kMaxTrajectoryPoints];
    const std::size_t n = trajectoryPoints(t, pts);
    const double length = habitual::pathLength(pts, n);
    const rover_model::PowerModel model = rover_model::powerModelFrom(rig->tables.habitual());
    const double energy = rover_model::pathEnergyJ(model, pts, n, 0.0, 1.0);
    const msg::LegReportMsg& r = rig->lastReport;
    CHECK(HabitualState::kDriving == r.state);
    LONGS_EQUAL(1, r.legId);
    DOUBLES_EQUAL(length, r.predictedLengthM, 1e-9);
    DOUBLES_EQUAL(30.0 * (1.0 - static_cast<double>(rig->tables.habitual().distance_margin_frac)), r.allowedLengthM, 1e-6);
    DOUBLES_EQUAL(energy, r.predictedEnergyJ, 1e-6);
    DOUBLES_EQUAL(5000.0 * (1.0 - static_cast<double>(rig->tables.habitual().power_margin_frac)), r.allowedEnergyJ, 1e-3);
    CHECK(LegConstraint::kNone == r.violated);
    CHECK(length < 8.0);  // a short way round, not a wander
    LONGS_EQUAL(1, rig->seenCount(ev::kPlanSent));

    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 600));
    LONGS_EQUAL(1, rig->task.counters().legsAchieved);
    LONGS_EQUAL(1, rig->lastReport.legsAchieved);
    CHECK(HabitualState::kAchieved == rig->lastReport.state);
    LONGS_EQUAL(1, rig->seenCount(ev::kLegAchieved));
    LONGS_EQUAL(0, rig->task.counters().minorAnomalies);
    DOUBLES_EQUAL(length, rig->task.drivenLengthM(), 0.06);  // odometry steps of 5 cm
}

TEST(HabitualTask, OpenStraightLineIsTakenWithoutSampling) {
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    LONGS_EQUAL(2, rig->trajectory.count);
    CHECK_TRUE(rig->task.lastQuery().straightLine);
    LONGS_EQUAL(0, rig->task.lastQuery().iterations);
    DOUBLES_EQUAL(20.0, rig->lastReport.predictedLengthM, 1e-9);
    DOUBLES_EQUAL(20.0 * static_cast<double>(rig->tables.habitual().drive_energy_j_per_m),
                  rig->lastReport.predictedEnergyJ, 1e-6);
}

TEST(HabitualTask, HiddenHazardOnThePathStopsReplansAndIsAMinorAnomalyNotAFailUp) {
    rig->addHiddenDisc(3, 12.6, 0.05, 0.65);  // the demo's hidden rock, as a disc
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    const std::uint32_t firstPlan = rig->trajectory.trajectoryId;
    LONGS_EQUAL(2, rig->trajectory.count);  // straight: the coarse map does not show it

    CHECK_TRUE(rig->runUntil([&] { return rig->task.counters().pathBlocked > 0; }, 400));
    // Stopped at once, where the detector first saw it (3 m from its edge).
    LONGS_EQUAL(0, rig->trajectory.count);
    CHECK(rig->x < 12.6 - 0.65 - 0.6 - 1.0);
    CHECK(rig->x > 12.6 - 0.65 - 3.0 - 0.1);
    CHECK(inState(HabitualState::kRepairing));
    LONGS_EQUAL(1, rig->seenCount(ev::kPathBlocked));
    LONGS_EQUAL(1, rig->task.mapBuilder().rememberedCount());

    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 40));
    const msg::TrajectoryMsg detour = rig->trajectory;
    CHECK(detour.trajectoryId != firstPlan);
    CHECK(detour.count >= 3);
    CHECK_TRUE(trajectoryFree(rig->task.checkMap(), detour));
    DOUBLES_EQUAL(20.0, detour.points[detour.count - 1].xM, 1e-9);
    LONGS_EQUAL(1, rig->task.counters().minorAnomalies);
    LONGS_EQUAL(1, rig->lastReport.minorAnomalies);
    CHECK(rig->lastReport.replans >= 1);
    LONGS_EQUAL(1, rig->seenCount(ev::kMinorAnomaly));
    LONGS_EQUAL(0, rig->task.counters().failUps);

    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 800));
    LONGS_EQUAL(0, rig->seenCount(ev::kFailUp));
    LONGS_EQUAL(0, rig->lastReport.failUps);
    LONGS_EQUAL(1, rig->task.counters().pathBlocked);  // the detour is not blocked again
}

TEST(HabitualTask, RaisedPowerFactorsViolateTheEnergyBoundRepairThenFailUpWithTheExcess) {
    const tables::HabitualTable& hab = rig->tables.habitual();
    rig->sendLeg(1, 20.0, 0.0, 40.0, 2000.0);  // nominal 20 m x 60 J/m = 1200 J <= 1600 J allowed
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    rig->runFor(50);
    CHECK(driving());
    // One degraded drive still fits: no violation.
    rig->sendPowerFactors({1.0, 1.0, 1.8, 1.0, 1.0, 1.0});
    rig->run();
    const double repredictedAt = rig->x;
    rig->runFor(10);  // the next 1 Hz report carries the new prediction
    CHECK(driving());
    DOUBLES_EQUAL((5.0 + 1.8) / 6.0 * static_cast<double>(hab.drive_energy_j_per_m) * (20.0 - repredictedAt),
                  rig->lastReport.predictedEnergyJ, 1e-3);

    rig->sendPowerFactors({2.0, 2.0, 2.0, 2.0, 2.0, 2.0});
    rig->run();
    LONGS_EQUAL(0, rig->trajectory.count);  // stopped at once
    LONGS_EQUAL(1, rig->seenCount(ev::kEnergyViolated));
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kFailedUp); }, 40));
    LONGS_EQUAL(hab.repair_attempts, rig->seenCount(ev::kRepairAttempt));  // the whole repair budget used

    const double predicted = 2.0 * static_cast<double>(hab.drive_energy_j_per_m) * (20.0 - rig->x);
    const double allowed = (2000.0 - rig->task.drivenEnergyJ()) * (1.0 - static_cast<double>(hab.power_margin_frac));
    const msg::LegReportMsg& r = rig->lastReport;
    CHECK(HabitualState::kFailedUp == r.state);
    CHECK(LegConstraint::kEnergy == r.violated);
    DOUBLES_EQUAL(predicted, r.predictedEnergyJ, 1e-6);
    DOUBLES_EQUAL(allowed, r.allowedEnergyJ, 1e-6);
    DOUBLES_EQUAL(predicted - allowed, r.excess, 1e-6);
    CHECK(r.excess > 0.0);
    LONGS_EQUAL(1, r.failUps);
    LONGS_EQUAL(0, rig->trajectory.count);
    char expected[96];
    std::snprintf(expected, sizeof expected, "fail-up: energy %.0f J > allowed %.0f J by %.0f J", predicted, allowed,
                  predicted - allowed);
    CHECK_TRUE(contains(rig->seenText(ev::kFailUp), expected));
    const double stoppedAt = rig->x;
    rig->runFor(20);  // waits: no driving, no new plan
    DOUBLES_EQUAL(stoppedAt, rig->x, 0.0);
    CHECK(inState(HabitualState::kFailedUp));

    // The deliberative layer relaxes the bound: a new leg drives again.
    rig->sendLeg(2, 20.0, 0.0, 40.0, 6000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    CHECK(rig->lastReport.predictedEnergyJ <= rig->lastReport.allowedEnergyJ);
}

// The power bound (LegCommandMsg::maxPowerW): the drives' power at the cruise
// speed, P = fbar e_m v, against the bound less the power margin. It depends on
// the drives alone, so a violated bound fails up at once: no planning run, no
// repair (a path cannot lower it).
TEST(HabitualTask, APowerBoundTheDrivesAlreadyExceedFailsUpAtOnceWithoutPlanning) {
    const tables::HabitualTable& hab = rig->tables.habitual();
    const double v = static_cast<double>(hab.cruise_speed_m_s);
    const double em = static_cast<double>(hab.drive_energy_j_per_m);
    rig->sendPowerFactors({1.0, 1.6, 1.0, 1.0, 1.0, 1.0}, msg::DriveMode::kDegraded, 1);  // fbar 1.1
    rig->run();
    const double bound = 1.04 * em * v / 0.8;  // planned at fbar 1 with 4 % slack: allows 1.04 P(1)
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0, bound);
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kFailedUp); }, 5));
    LONGS_EQUAL(0, rig->plans);                                // no trajectory sent
    LONGS_EQUAL(0, rig->seenCount(ev::kRepairAttempt));        // nothing repaired
    LONGS_EQUAL(0, rig->task.lastQuery().iterations);          // nothing sampled
    const msg::LegReportMsg& r = rig->lastReport;
    CHECK(LegConstraint::kPower == r.violated);
    DOUBLES_EQUAL(1.1 * em * v, r.predictedPowerW, 1e-5);  // factors travel as floats
    DOUBLES_EQUAL(1.04 * em * v, r.allowedPowerW, 1e-5);   // the margin is a float
    DOUBLES_EQUAL(0.06 * em * v, r.excess, 1e-5);
    char expected[96];
    std::snprintf(expected, sizeof expected, "fail-up: power %.1f W > allowed %.1f W by %.1f W", 1.1 * em * v,
                  1.04 * em * v, 0.06 * em * v);
    CHECK_TRUE(contains(rig->seenText(ev::kFailUp), expected));

    // The same leg with the bound relaxed past the need is planned and driven.
    rig->sendLeg(2, 20.0, 0.0, 40.0, 5000.0, bound * 1.1);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    CHECK(rig->lastReport.predictedPowerW <= rig->lastReport.allowedPowerW);
}

TEST(HabitualTask, PowerFactorsRisingWhileDrivingFailUpOnPowerAtOnceAndStop) {
    const tables::HabitualTable& hab = rig->tables.habitual();
    const double p1 = static_cast<double>(hab.drive_energy_j_per_m) * static_cast<double>(hab.cruise_speed_m_s);
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0, 1.05 * p1 / 0.8);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    rig->runFor(30);
    CHECK(driving());
    // A worn motor: 1.2x, fbar 1.033, still within 1.05 P(1).
    rig->sendPowerFactors({1.0, 1.2, 1.0, 1.0, 1.0, 1.0}, msg::DriveMode::kDegraded, 1);
    rig->runFor(3);
    CHECK(driving());
    // Worse: 1.6x, fbar 1.1.
    rig->sendPowerFactors({1.0, 1.6, 1.0, 1.0, 1.0, 1.0}, msg::DriveMode::kDegraded, 1);
    rig->run();
    CHECK(inState(HabitualState::kFailedUp));
    LONGS_EQUAL(0, rig->trajectory.count);  // stopped at once
    CHECK(LegConstraint::kPower == rig->lastReport.violated);
    LONGS_EQUAL(0, rig->seenCount(ev::kRepairAttempt));
    LONGS_EQUAL(0, rig->seenCount(ev::kEnergyViolated));
    LONGS_EQUAL(1, rig->lastReport.failUps);
}

TEST(HabitualTask, ALegWithoutAPowerBoundIsNotCheckedForPower) {
    rig->sendPowerFactors({2.0, 2.0, 2.0, 2.0, 2.0, 2.0});
    rig->run();
    rig->sendLeg(1, 20.0, 0.0, 40.0, 1.0e6);  // maxPowerW 0: energy and length only
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    DOUBLES_EQUAL(0.0, rig->lastReport.allowedPowerW, 0.0);
    CHECK(LegConstraint::kNone == rig->lastReport.violated);
}

TEST(HabitualTask, TooShortALengthBoundFailsUpWithPathLength) {
    rig->sendLeg(1, 20.0, 0.0, 20.0, 1.0e6);  // 20 m needed, 18 m allowed after the 10 % margin
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kFailedUp); }, 40));
    const msg::LegReportMsg& r = rig->lastReport;
    CHECK(LegConstraint::kPathLength == r.violated);
    DOUBLES_EQUAL(20.0, r.predictedLengthM, 1e-9);
    DOUBLES_EQUAL(18.0, r.allowedLengthM, 1e-5);
    DOUBLES_EQUAL(2.0, r.excess, 1e-5);
    LONGS_EQUAL(0, rig->plans);  // never moved
    LONGS_EQUAL(rig->tables.habitual().repair_attempts + 1U, rig->task.counters().planningRuns);
    CHECK_TRUE(contains(rig->seenText(ev::kFailUp), "fail-up: path length 20.0 m > allowed 18.0 m by 2.0 m"));
}

TEST(HabitualTask, WalledOffGoalFailsUpWithNoPath) {
    tables::CoarseMapTable walled = rig->tables.coarseMap();
    // Four walls round (20, 0), replacing the default rocks.
    const double boxes[4][4] = {{17.5, 2.0, 22.5, 2.5}, {17.5, -2.5, 22.5, -2.0}, {17.5, -2.0, 18.0, 2.0},
                                {22.0, -2.0, 22.5, 2.0}};
    std::memset(walled.vertex_count, 0, sizeof walled.vertex_count);
    std::memset(walled.vertex_x_m, 0, sizeof walled.vertex_x_m);
    std::memset(walled.vertex_y_m, 0, sizeof walled.vertex_y_m);
    walled.obstacle_count = 4;
    for (std::size_t i = 0; i < 4; ++i) {
        const double* b = boxes[i];
        const double xs[4] = {b[0], b[2], b[2], b[0]};
        const double ys[4] = {b[1], b[1], b[3], b[3]};
        walled.vertex_count[i] = 4;
        for (std::size_t v = 0; v < 4; ++v) {
            walled.vertex_x_m[8 * i + v] = static_cast<float>(xs[v]);
            walled.vertex_y_m[8 * i + v] = static_cast<float>(ys[v]);
        }
    }
    CHECK_TRUE(rig->loadTable(tables::TableId::kCoarseMap, walled, 2));
    rig->sendLeg(1, 20.0, 0.0, 100.0, 1.0e6);
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kFailedUp); }, 60));
    CHECK(LegConstraint::kNoPath == rig->lastReport.violated);
    DOUBLES_EQUAL(0.0, rig->lastReport.excess, 0.0);
    LONGS_EQUAL(0, rig->plans);
    const std::uint32_t runs = rig->tables.habitual().repair_attempts + 1U;
    LONGS_EQUAL(runs, rig->task.counters().noPathRuns);
    // Each planning run spent the whole sampling budget before giving up.
    LONGS_EQUAL(rig->tables.habitual().rrt_iterations, rig->task.lastQuery().iterations);
    CHECK_TRUE(contains(rig->seenText(ev::kFailUp), "fail-up: no path to (20.00, 0.00)"));
}

TEST(HabitualTask, BadLegsAreRefusedAndTheLegInForceGoesOn) {
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    const std::uint32_t inForce = rig->trajectory.trajectoryId;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    struct Bad {
        std::uint32_t id;
        double gx, gy, len, energy, power;
    } const bad[] = {
        {2, nan, 0.0, 40.0, 5000.0, 0.0},   {3, 100.0, 0.0, 40.0, 5000.0, 0.0}, {4, 10.0, -11.0, 40.0, 5000.0, 0.0},
        {5, 10.0, 0.0, 0.0, 5000.0, 0.0},   {6, 10.0, 0.0, 40.0, -1.0, 0.0},    {7, 10.0, 0.0, 40.0, inf, 0.0},
        {8, 10.0, 0.0, nan, 5000.0, 0.0},   {9, 10.0, 0.0, 40.0, 5000.0, -1.0}, {10, 10.0, 0.0, 40.0, 5000.0, nan},
        {11, 10.0, 0.0, 40.0, 5000.0, inf}, {1, 10.0, 0.0, 40.0, 5000.0, 0.0},  // 1: not a new id
    };
    std::uint32_t refused = 0;
    for (const Bad& b : bad) {
        rig->sendLeg(b.id, b.gx, b.gy, b.len, b.energy, b.power);
        rig->run();
        ++refused;
        LONGS_EQUAL(refused, rig->task.counters().legsRefused);
        const msg::LegReportMsg* r = nullptr;
        for (std::size_t k = 0; k < 3 && r == nullptr; ++k) {
            const msg::LegReportMsg& c = rig->reports[(rig->reportCount - 1 - k) % HabitualRig::kMaxReports];
            if (c.legId == b.id && c.violated == LegConstraint::kBadLeg) {
                r = &c;
            }
        }
        CHECK(r != nullptr);
        CHECK(HabitualState::kIdle == r->state);
        CHECK(driving());
        LONGS_EQUAL(inForce, rig->trajectory.trajectoryId);
    }
    // Evented on the 1st, 2nd, 4th and 8th refusal; all counted.
    LONGS_EQUAL(4, rig->seenCount(ev::kLegRefused));
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 800));
    LONGS_EQUAL(1, findReport(*rig, 1)->legsAchieved);
}

// ---- Goal regions (LegCommandMsg.arriveWithinM, a plan's `within R`) ----------------

// The open straight line to (20, 0) within 3 m: the trajectory ends where the
// line is the goal tolerance deep inside the region (3 - 0.5 = 2.5 m short of
// the point), and the leg is achieved there; the same leg as a point ends at
// the point.
TEST(HabitualTask, ARegionLegStopsOnTheWayInInsteadOfDrivingToThePoint) {
    const double tolerance = static_cast<double>(rig->tables.habitual().goal_tolerance_m);
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0, 0.0, 3.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    LONGS_EQUAL(2, rig->trajectory.count);
    DOUBLES_EQUAL(20.0 - (3.0 - tolerance), rig->trajectory.points[1].xM, 1e-9);
    DOUBLES_EQUAL(0.0, rig->trajectory.points[1].yM, 1e-9);
    DOUBLES_EQUAL(20.0 - (3.0 - tolerance), rig->lastReport.predictedLengthM, 1e-9);  // judged on what is driven
    CHECK_TRUE(contains(rig->seenText(ev::kLegAccepted), "to (20.00, 0.00) within 3.00 m"));
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 800));
    const double off = std::hypot(rig->x - 20.0, rig->y);
    CHECK(off > tolerance);  // not at the point
    CHECK(off <= 3.0);       // inside the region
    LONGS_EQUAL(1, rig->task.counters().legsAchieved);

    // The same leg as a point, from where the rover stopped: to the point itself.
    rig->sendLeg(2, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    DOUBLES_EQUAL(20.0, rig->trajectory.points[rig->trajectory.count - 1].xM, 1e-9);
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 200));
    DOUBLES_EQUAL(20.0, rig->x, 1e-6);
}

// Round rock 0 of the default map (RRT*): the path runs towards the point
// and is cut where it comes within 2 - 0.5 = 1.5 m of it; still free.
TEST(HabitualTask, ARegionLegPlannedRoundARockIsCutWhereItEntersTheRegion) {
    const double tolerance = static_cast<double>(rig->tables.habitual().goal_tolerance_m);
    rig->x = 3.0;
    rig->y = 2.5;
    rig->sendLeg(1, 9.0, 2.5, 30.0, 5000.0, 0.0, 2.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 40));
    CHECK_FALSE(rig->task.lastQuery().straightLine);
    const msg::TrajectoryMsg t = rig->trajectory;
    const Point2 goal{9.0, 2.5};
    const Point2 last{t.points[t.count - 1].xM, t.points[t.count - 1].yM};
    DOUBLES_EQUAL(2.0 - tolerance, geometry::distance(last, goal), 1e-6);
    for (std::size_t i = 0; i + 1 < t.count; ++i) {  // it enters the region at its end, not before
        CHECK(geometry::distance(Point2{t.points[i].xM, t.points[i].yM}, goal) > 2.0 - tolerance);
    }
    CHECK_TRUE(trajectoryFree(rig->task.checkMap(), t));
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 600));
    const double off = std::hypot(rig->x - 9.0, rig->y - 2.5);
    CHECK(off > tolerance && off <= 2.0);
}

// A region leg that starts inside its region (the leg before ended there) is
// achieved at once: nothing planned or driven, and no power bound to keep (1 W
// here: a leg that drove would fail up on it). A point leg from as near still
// drives to the point, and a region no wider than the tolerance is the point.
TEST(HabitualTask, ARegionLegStartingInsideItsRegionIsAchievedWithoutDriving) {
    rig->x = 18.0;
    rig->y = 0.5;
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0, 1.0, 3.0);
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 10));
    LONGS_EQUAL(0, rig->task.counters().failUps);
    LONGS_EQUAL(0, rig->plans);
    LONGS_EQUAL(1, rig->task.counters().legsAchieved);
    CHECK(HabitualState::kAchieved == rig->lastReport.state);
    LONGS_EQUAL(1, rig->lastReport.legId);
    CHECK_TRUE(contains(rig->seenText(ev::kLegAchieved), "already within 3.00 m of (20.00, 0.00)"));

    rig->sendLeg(2, 20.0, 0.0, 40.0, 5000.0, 0.0, 0.4);  // below the 0.5 m tolerance: the point
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    LONGS_EQUAL(1, rig->plans);
    DOUBLES_EQUAL(20.0, rig->trajectory.points[rig->trajectory.count - 1].xM, 1e-9);
    DOUBLES_EQUAL(0.0, rig->trajectory.points[rig->trajectory.count - 1].yM, 1e-9);
}

TEST(HabitualTask, ALegWithAnArrivalRadiusNotFiniteNegativeOrBeyondTheLimitIsRefused) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const double bad[] = {nan, inf, -0.1, static_cast<double>(msg::kMaxGoalRadiusM) + 0.001};
    std::uint32_t id = 1;
    for (const double r : bad) {
        rig->sendLeg(id++, 10.0, 0.0, 40.0, 5000.0, 0.0, r);
        rig->run();
    }
    LONGS_EQUAL(4, rig->task.counters().legsRefused);
    CHECK(inState(HabitualState::kIdle));
    LONGS_EQUAL(0, rig->plans);
    CHECK_TRUE(contains(rig->seenText(ev::kLegRefused), "arrival radius"));
    // The largest radius is a leg like any other (here the rover stands inside it).
    rig->sendLeg(id, 10.0, 0.0, 40.0, 5000.0, 0.0, static_cast<double>(msg::kMaxGoalRadiusM));
    CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 10));
    LONGS_EQUAL(4, rig->task.counters().legsRefused);
}

TEST(HabitualTask, LegOutsideAutonomousIsRefused) {
    rig->setMode(kStandby);
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    rig->runFor(5);
    CHECK(inState(HabitualState::kIdle));
    LONGS_EQUAL(1, rig->task.counters().legsRefused);
    CHECK_TRUE(contains(rig->seenText(ev::kLegRefused), "not in AUTONOMOUS"));
    LONGS_EQUAL(0, rig->plans);
}

TEST(HabitualTask, CancelStopsTheRoverAndGoesIdle) {
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    rig->runFor(20);
    CHECK(rig->x > 0.4);
    rig->sendLeg(0, 0.0, 0.0, 0.0, 0.0);
    rig->run();
    CHECK(inState(HabitualState::kIdle));
    LONGS_EQUAL(0, rig->trajectory.count);
    LONGS_EQUAL(1, rig->task.counters().legsCancelled);
    CHECK(HabitualState::kIdle == rig->lastReport.state);
    LONGS_EQUAL(1, rig->seenCount(ev::kLegCancelled));
    const double stoppedAt = rig->x;
    rig->runFor(20);
    DOUBLES_EQUAL(stoppedAt, rig->x, 0.0);
}

TEST(HabitualTask, LeavingAutonomousStopsAndDropsTheLeg) {
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    rig->runFor(10);
    rig->setMode(kStandby);
    rig->run();
    CHECK(inState(HabitualState::kIdle));
    LONGS_EQUAL(0, rig->trajectory.count);
    LONGS_EQUAL(1, rig->task.counters().leftAutonomous);
    LONGS_EQUAL(1, rig->seenCount(ev::kLeftAutonomous));
    // Back in AUTONOMOUS nothing resumes by itself.
    rig->setMode(kAutonomous);
    rig->runFor(10);
    CHECK(inState(HabitualState::kIdle));
    LONGS_EQUAL(1, rig->plans);
}

TEST(HabitualTask, FollowerGivingUpIsReplannedOnceThenFailedUp) {
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    rig->runFor(10);
    rig->sendFollower(msg::FollowerState::kCannotFollow, msg::FollowReason::kCrossTrackError);
    rig->run();
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 10));
    LONGS_EQUAL(2, rig->plans);
    LONGS_EQUAL(1, rig->task.counters().minorAnomalies);
    rig->runFor(5);
    rig->sendFollower(msg::FollowerState::kCannotFollow, msg::FollowReason::kCrossTrackError);
    rig->run();
    CHECK(inState(HabitualState::kFailedUp));
    CHECK(LegConstraint::kCannotFollow == rig->lastReport.violated);
    LONGS_EQUAL(0, rig->trajectory.count);
    LONGS_EQUAL(2, rig->seenCount(ev::kCannotFollow));
}

TEST(HabitualTask, DrivesHeldByTheFollowerFailUpAtOnce) {
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    rig->sendFollower(msg::FollowerState::kCannotFollow, msg::FollowReason::kDrivesHeld);
    rig->run();
    CHECK(inState(HabitualState::kFailedUp));
    CHECK(LegConstraint::kCannotFollow == rig->lastReport.violated);
    LONGS_EQUAL(1, rig->plans);
}

TEST(HabitualTask, StatusOfAnOldTrajectoryIsIgnored) {
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
    msg::FollowerStatusMsg s{};
    s.trajectoryId = rig->trajectory.trajectoryId - 1;  // the stop sent before the plan
    s.state = msg::FollowerState::kReached;
    (void)rig->bus.publish(s);
    rig->run();
    CHECK(driving());
}

TEST(HabitualTask, PlanningWaitsForAnInitialisedPose) {
    rig->poseInitialised = false;
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    rig->runFor(20);
    CHECK(inState(HabitualState::kPlanning));
    CHECK(rig->task.counters().poseWaits >= 19);
    LONGS_EQUAL(0, rig->plans);
    CHECK(rig->seenCount(ev::kPoseNotReady) >= 1);
    rig->poseInitialised = true;
    CHECK_TRUE(rig->runUntil([&] { return driving(); }, 5));
}

TEST(HabitualTask, MalformedInputsAreCountedEventedAndIgnored) {
    const std::uint8_t junk[8] = {};
    CHECK(core::Status::kOk == rig->bus.publish(msg::ids::kLegCommand, junk, sizeof junk));
    msg::DriveModesMsg modes{};
    modes.drives[0].powerFactor = std::numeric_limits<float>::quiet_NaN();
    (void)rig->bus.publish(modes);
    msg::HazardMsg hazards{};
    hazards.count = msg::kMaxHazardsInMsg + 1;
    (void)rig->bus.publish(hazards);
    msg::FollowerStatusMsg status{};
    status.state = static_cast<msg::FollowerState>(9);
    (void)rig->bus.publish(status);
    msg::ModeMsg mode{};
    mode.mode = 7;
    (void)rig->bus.publish(mode);
    rig->run();
    LONGS_EQUAL(5, rig->task.counters().malformedInputs);
    LONGS_EQUAL(3, rig->seenCount(ev::kMalformedInput));  // 1st, 2nd, 4th
    CHECK_TRUE(rig->task.autonomous());                     // the bad mode changed nothing
    CHECK(inState(HabitualState::kIdle));
}

TEST(HabitualTask, ReportsAtOneHertzAndOnEveryStateChange) {
    const std::size_t before = rig->reportCount;
    rig->runFor(100);
    LONGS_EQUAL(10, rig->reportCount - before);
    rig->sendLeg(1, 20.0, 0.0, 40.0, 5000.0);
    const std::size_t atLeg = rig->reportCount;
    rig->run();  // idle -> planning -> driving in one run: two state changes
    CHECK(rig->reportCount - atLeg >= 2);
    CHECK(HabitualState::kDriving == rig->lastReport.state);
}

TEST(HabitualTask, NoHeapAllocationPerPlanningQueryOrOverManyRuns) {
    rig->x = 3.0;
    rig->y = 2.5;
    rig->addHiddenDisc(3, 12.6, 0.05, 0.65);
    {
        test::AllocationWatch watch;
        // RRT* legs round rock 0 and back, then the long leg past the hidden rock.
        rig->sendLeg(1, 9.0, 2.5, 30.0, 5000.0);
        rig->run();
        CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 600));
        rig->sendLeg(2, 3.0, 2.5, 30.0, 5000.0);
        rig->run();
        CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 600));
        rig->sendLeg(3, 20.0, 0.0, 60.0, 8000.0);
        rig->run();
        CHECK_TRUE(rig->runUntil([&] { return inState(HabitualState::kAchieved); }, 1200));
        rig->runFor(200);
        LONGS_EQUAL(0, watch.count());
    }
    CHECK(rig->task.counters().planningRuns >= 3);
    LONGS_EQUAL(3, rig->task.counters().legsAchieved);
}

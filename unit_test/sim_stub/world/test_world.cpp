#include <cmath>
#include <vector>

#include "sim_stub/world/kinematics.hpp"
#include "sim_stub/world/power.hpp"
#include "sim_stub/world/world.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;
using rse::test::sides;

namespace {

constexpr core::TimeNs kStep = 10 * core::kNsPerMs;

WorldConfig openGround() {
    WorldConfig c;
    c.map = MapBounds{-50, 50, -50, 50};
    return c;
}

Obstacle box(std::uint8_t id, double x0, double y0, double x1, double y1) {
    Obstacle o;
    o.id = id;
    o.shape.v[0] = {x0, y0};
    o.shape.v[1] = {x1, y0};
    o.shape.v[2] = {x1, y1};
    o.shape.v[3] = {x0, y1};
    o.shape.n = 4;
    return o;
}

// Advances in 10 ms steps from the world's time to until, wheels held.
void advanceWorld(World& w, core::TimeNs until, const WheelArray& speeds, const WheelArray& currents = WheelArray{}) {
    core::TimeNs t = w.time();
    while (t < until) {
        t = (until - t) < kStep ? until : t + kStep;
        w.advance(t, speeds, currents);
    }
}

}  // namespace

TEST_GROUP(SimWorld){};

TEST(SimWorld, ASlideCarriesTheStandingRoverItsOffsetOverItsDurationAndThenStops) {
    World w(openGround());
    advanceWorld(w, core::kNsPerSec, WheelArray{});
    w.startSlide(2.0, -0.5 * kPi, 2.0);
    CHECK_TRUE(w.sliding());
    advanceWorld(w, 2 * core::kNsPerSec, WheelArray{});
    DOUBLES_EQUAL(-1.0, w.truth().pose.y, 1e-6);  // half way after half the time
    advanceWorld(w, 5 * core::kNsPerSec, WheelArray{});
    CHECK_FALSE(w.sliding());
    DOUBLES_EQUAL(0.0, w.truth().pose.x, 1e-9);
    DOUBLES_EQUAL(-2.0, w.truth().pose.y, 1e-6);
    DOUBLES_EQUAL(0.0, w.truth().pose.theta, 1e-12);  // the IMU feels no turn
}

TEST(SimWorld, ASlideIntoARockStopsAtContact) {
    WorldConfig c = openGround();
    c.obstacles.push_back(box(1, -1.0, -3.0, 1.0, -2.0));
    World w(c);
    w.startSlide(5.0, -0.5 * kPi, 2.0);
    advanceWorld(w, 3 * core::kNsPerSec, WheelArray{});
    CHECK(w.truth().pose.y > -2.0 + 0.0);  // stopped at the rock, disc outside it
    CHECK(w.truth().pose.y < -1.0);
    LONGS_EQUAL(1, w.truth().collisions);
}

TEST(SimWorld, EqualWheelSpeedsDriveStraightTenMetresInTheExpectedTime) {
    World w(openGround());
    const RoverParams& r = w.rover();
    const double wheel = 5.0;                      // rad/s
    const double v = r.wheelRadiusM * wheel;       // 0.5 m/s
    const auto t10 = static_cast<core::TimeNs>(std::llround(10.0 / v * 1e9));  // 20 s
    advanceWorld(w, t10, sides(wheel, wheel));
    DOUBLES_EQUAL(10.0, w.truth().pose.x, 1e-6);
    DOUBLES_EQUAL(0.0, w.truth().pose.y, 1e-9);
    DOUBLES_EQUAL(0.0, w.truth().pose.theta, 1e-9);
    DOUBLES_EQUAL(v, w.truth().speedMS, 1e-12);
    DOUBLES_EQUAL(0.0, w.truth().yawRateRadS, 1e-12);
    DOUBLES_EQUAL(10.0, w.truth().distanceM, 1e-6);
    LONGS_EQUAL(0, w.truth().collisions);
}

TEST(SimWorld, StraightDrivingKeepsAnyStartHeading) {
    WorldConfig c = openGround();
    c.start = Pose2{1.0, -2.0, 2.5};
    World w(c);
    advanceWorld(w, 4 * core::kNsPerSec, sides(3.0, 3.0));
    DOUBLES_EQUAL(2.5, w.truth().pose.theta, 1e-9);
    DOUBLES_EQUAL(1.0 + 1.2 * std::cos(2.5), w.truth().pose.x, 1e-9);
    DOUBLES_EQUAL(-2.0 + 1.2 * std::sin(2.5), w.truth().pose.y, 1e-9);
}

TEST(SimWorld, OppositeWheelSpeedsTurnInPlaceAtTheSkidSteerRate) {
    World w(openGround());
    const RoverParams& r = w.rover();
    const double expected = r.wheelRadiusM * (2.0 - (-2.0)) / (r.skidFactor * r.trackWidthM);  // 0.444 rad/s
    advanceWorld(w, core::kNsPerSec, sides(-2.0, 2.0));
    DOUBLES_EQUAL(expected, w.truth().yawRateRadS, 1e-12);
    DOUBLES_EQUAL(expected, w.truth().pose.theta, 1e-9);
    DOUBLES_EQUAL(0.0, w.truth().pose.x, 1e-12);
    DOUBLES_EQUAL(0.0, w.truth().pose.y, 1e-12);
    DOUBLES_EQUAL(0.0, w.truth().speedMS, 1e-12);
    // Right side backwards turns clockwise.
    World cw(openGround());
    advanceWorld(cw, core::kNsPerSec, sides(2.0, -2.0));
    DOUBLES_EQUAL(-expected, cw.truth().pose.theta, 1e-9);
}

TEST(SimWorld, UnequalSpeedsFollowAnArcOfTheKnownRadius) {
    World w(openGround());
    const RoverParams& r = w.rover();
    const double v = r.wheelRadiusM * (4.0 + 6.0) / 2.0;                           // 0.5 m/s
    const double omega = r.wheelRadiusM * (6.0 - 4.0) / (r.skidFactor * r.trackWidthM);  // 0.222 rad/s
    const double radius = v / omega;                                               // 2.25 m
    const auto quarter = static_cast<core::TimeNs>(std::llround(kPi / 2.0 / omega * 1e9));
    advanceWorld(w, quarter, sides(4.0, 6.0));
    const double theta = omega * static_cast<double>(quarter) * 1e-9;
    const Pose2& p = w.truth().pose;
    DOUBLES_EQUAL(radius * std::sin(theta), p.x, 1e-9);
    DOUBLES_EQUAL(radius * (1.0 - std::cos(theta)), p.y, 1e-9);
    DOUBLES_EQUAL(theta, p.theta, 1e-9);
    // Every point of the path is on the circle about (0, R): check the end.
    DOUBLES_EQUAL(radius, std::hypot(p.x, p.y - radius), 1e-9);
}

TEST(SimWorld, ExactUnicycleStepMatchesTheClosedForm) {
    const Pose2 start{1.0, 2.0, 0.3};
    const Pose2 end = integrateUnicycle(start, 0.4, -0.2, 3.0);
    DOUBLES_EQUAL(1.0 + 0.4 / -0.2 * (std::sin(0.3 - 0.6) - std::sin(0.3)), end.x, 1e-12);
    DOUBLES_EQUAL(2.0 - 0.4 / -0.2 * (std::cos(0.3 - 0.6) - std::cos(0.3)), end.y, 1e-12);
    DOUBLES_EQUAL(-0.3, end.theta, 1e-12);
}

TEST(SimWorld, AFailedWheelSlowsTheRoverAndYawsItTowardItsSide) {
    World w(openGround());
    WheelArray speeds = sides(5.0, 5.0);
    speeds[4] = 0.0;  // middle-right locked
    advanceWorld(w, core::kNsPerSec, speeds);
    const BodyRates rates = skidSteerRates(speeds, w.rover());
    DOUBLES_EQUAL(0.1 * (5.0 + 10.0 / 3.0) / 2.0, rates.speedMS, 1e-12);
    CHECK(rates.yawRateRadS < 0.0);  // clockwise: toward the right, failed side
    CHECK(w.truth().pose.theta < -0.1);
    // The locked wheel carries no load; the turning ones share its drag.
    DOUBLES_EQUAL(0.0, w.loadTorqueNm(4), 0.0);
    WheelArray healthy{};
    wheelLoadTorques(w.rover(), sides(5.0, 5.0), w.truth().yawRateRadS, false, &healthy);
    const RoverParams& r = w.rover();
    const double dragShare = r.slideFriction * r.wheelNormalLoadN() * r.wheelRadiusM / 5.0;
    DOUBLES_EQUAL(healthy[0] + dragShare, w.loadTorqueNm(0), 1e-12);
}

TEST(SimWorld, LoadTorqueIsRollingResistancePlusATurningTerm) {
    const RoverParams r;
    const double rolling = r.rollingCoefficient * r.massKg * r.gravityMS2 / 6.0 * r.wheelRadiusM;
    WheelArray t{};
    wheelLoadTorques(r, sides(5.0, 5.0), 0.0, false, &t);
    for (double torque : t) {
        DOUBLES_EQUAL(rolling, torque, 1e-12);
    }
    wheelLoadTorques(r, sides(-5.0, 5.0), 0.8, false, &t);
    DOUBLES_EQUAL(-(rolling + r.turnTorquePerRadS * 0.8), t[0], 1e-12);  // opposes backward rotation
    DOUBLES_EQUAL(rolling + r.turnTorquePerRadS * 0.8, t[5], 1e-12);
    wheelLoadTorques(r, sides(0.0, 0.0), 0.0, false, &t);
    DOUBLES_EQUAL(0.0, t[2], 0.0);
    wheelLoadTorques(r, sides(5.0, 5.0), 0.0, true, &t);  // pushing against a rock
    DOUBLES_EQUAL(rolling + r.slideFriction * r.wheelNormalLoadN() * r.wheelRadiusM, t[3], 1e-12);
}

TEST(SimWorld, APivotAboutAStoppedSideDragsNothingButALockedWheelBesideTurningOnesIsDragged) {
    const RoverParams r;
    const double rolling = r.rollingCoefficient * r.wheelNormalLoadN() * r.wheelRadiusM;
    const double slide = r.slideFriction * r.wheelNormalLoadN() * r.wheelRadiusM;
    WheelArray t{};
    // Left side stopped, right side driving: the ground under the left wheels
    // does not move along them, so the right wheels carry no drag.
    wheelLoadTorques(r, sides(0.0, 2.0), 0.4, false, &t);
    DOUBLES_EQUAL(rolling + r.turnTorquePerRadS * 0.4, t[4], 1e-12);
    DOUBLES_EQUAL(0.0, t[0], 0.0);
    // One left wheel stopped between two turning ones is dragged by its side;
    // the five turning wheels share it.
    WheelArray w = sides(2.0, 2.0);
    w[1] = 0.0;
    wheelLoadTorques(r, w, 0.0, false, &t);
    DOUBLES_EQUAL(rolling + slide / 5.0, t[0], 1e-12);
    DOUBLES_EQUAL(rolling + slide / 5.0, t[5], 1e-12);
    DOUBLES_EQUAL(0.0, t[1], 0.0);
}

TEST(SimWorld, DrivingIntoABoxCountsOneCollisionAndStopsTheRoverAtContact) {
    WorldConfig c = openGround();
    c.obstacles.push_back(box(4, 3.0, -1.0, 4.0, 1.0));
    World w(c);
    const double stopX = 3.0 - w.rover().radiusM;  // 2.4 m
    advanceWorld(w, 10 * core::kNsPerSec, sides(5.0, 5.0));
    LONGS_EQUAL(1, w.truth().collisions);
    LONGS_EQUAL(4, w.truth().lastCollisionObstacle);
    CHECK_TRUE(w.truth().inContact);
    CHECK_TRUE(w.truth().blocked);
    DOUBLES_EQUAL(stopX, w.truth().pose.x, 0.5e-3 + 1e-9);  // within one 1 ms sub-step
    CHECK(w.truth().pose.x < stopX);
    DOUBLES_EQUAL(0.0, w.truth().speedMS, 0.0);
    // Pausing and pushing again is the same collision.
    advanceWorld(w, 11 * core::kNsPerSec, sides(0.0, 0.0));
    advanceWorld(w, 12 * core::kNsPerSec, sides(5.0, 5.0));
    LONGS_EQUAL(1, w.truth().collisions);
    // Backing away clears the contact; driving in again is a new one.
    advanceWorld(w, 13 * core::kNsPerSec, sides(-5.0, -5.0));
    CHECK_FALSE(w.truth().inContact);
    advanceWorld(w, 16 * core::kNsPerSec, sides(5.0, 5.0));
    LONGS_EQUAL(2, w.truth().collisions);
}

TEST(SimWorld, TheRoverMayTurnOnTheSpotWhileTouchingARock) {
    WorldConfig c = openGround();
    c.obstacles.push_back(box(1, 3.0, -1.0, 4.0, 1.0));
    World w(c);
    advanceWorld(w, 6 * core::kNsPerSec, sides(5.0, 5.0));
    const double x = w.truth().pose.x;
    advanceWorld(w, 7 * core::kNsPerSec, sides(-2.0, 2.0));
    DOUBLES_EQUAL(x, w.truth().pose.x, 1e-12);
    CHECK(w.truth().pose.theta > 0.4);
}

TEST(SimWorld, TheMapEdgeIsAWall) {
    WorldConfig c = openGround();
    c.map = MapBounds{-5, 5, -5, 5};
    World w(c);
    advanceWorld(w, 20 * core::kNsPerSec, sides(5.0, 5.0));
    DOUBLES_EQUAL(5.0 - w.rover().radiusM, w.truth().pose.x, 1e-3);
    LONGS_EQUAL(1, w.truth().mapEdgeHits);
    CHECK_TRUE(w.truth().atMapEdge);
    LONGS_EQUAL(1, w.truth().collisions);  // the edge is a collision, as a rock is
    LONGS_EQUAL(0, w.truth().lastCollisionObstacle);  // no rock
    // Staying against it is the same contact, not a new one.
    advanceWorld(w, 5 * core::kNsPerSec, sides(5.0, 5.0));
    LONGS_EQUAL(1, w.truth().collisions);
}

TEST(SimWorld, SlipNoiseIsDeterministicForASeedAndDiffersAcrossSeeds) {
    WorldConfig c = openGround();
    c.rover.slipSigma = 0.05;
    c.seed = 7;
    World a(c);
    World b(c);
    c.seed = 8;
    World other(c);
    World clean(openGround());
    for (World* w : {&a, &b, &other, &clean}) {
        advanceWorld(*w, 5 * core::kNsPerSec, sides(4.0, 6.0));
    }
    DOUBLES_EQUAL(a.truth().pose.x, b.truth().pose.x, 0.0);
    DOUBLES_EQUAL(a.truth().pose.y, b.truth().pose.y, 0.0);
    DOUBLES_EQUAL(a.truth().pose.theta, b.truth().pose.theta, 0.0);
    CHECK(a.truth().pose.x != other.truth().pose.x);
    CHECK(std::fabs(a.truth().pose.x - clean.truth().pose.x) > 1e-6);
    DOUBLES_EQUAL(clean.truth().pose.x, a.truth().pose.x, 0.1);  // small: a few per cent
}

TEST(SimWorld, DrivingDrawsTheBatteryDownMoreThanStandingStill) {
    WorldConfig c = openGround();
    c.solar.peakCurrentA = 0.0;
    World idle(c);
    World driving(c);
    const double start = driving.truth().stateOfCharge;
    const WheelArray motorCurrents{2.0, 2.0, 2.0, 2.0, 2.0, 2.0};
    advanceWorld(idle, 60 * core::kNsPerSec, sides(0.0, 0.0));
    advanceWorld(driving, 60 * core::kNsPerSec, sides(5.0, 5.0), motorCurrents);
    CHECK(idle.truth().stateOfCharge < start);  // the avionics alone
    CHECK(driving.truth().stateOfCharge < idle.truth().stateOfCharge);
    DOUBLES_EQUAL(12.0, driving.truth().motorCurrentA, 1e-12);
    // 12 A of motors plus about 25 W / 28 V of avionics for a minute out of 20 Ah.
    const double expectedDrop = (12.0 + 25.0 / 28.2) * 60.0 / (20.0 * 3600.0);
    DOUBLES_EQUAL(expectedDrop, start - driving.truth().stateOfCharge, 0.05 * expectedDrop);
    CHECK(driving.truth().busVoltageV < idle.truth().busVoltageV);  // sag under load
    CHECK(driving.truth().energyDrawnWh > 0.0);
}

TEST(SimWorld, SolarChargesAndFollowsTheDayProfile) {
    WorldConfig c = openGround();
    c.solar.peakCurrentA = 3.0;
    World w(c);
    const double start = w.truth().stateOfCharge;
    advanceWorld(w, 60 * core::kNsPerSec, sides(0.0, 0.0));
    CHECK(w.truth().stateOfCharge > start);
    CHECK(w.truth().busCurrentA < 0.0);  // charging
    SolarParams day;
    day.profile = SolarProfile::kDay;
    day.peakCurrentA = 2.0;
    day.dayLengthS = 1000.0;
    day.phase = 0.25;
    DOUBLES_EQUAL(2.0, solarArrayCurrentA(day, 0.0), 1e-12);     // noon
    DOUBLES_EQUAL(0.0, solarArrayCurrentA(day, 500.0), 1e-12);   // midnight
    DOUBLES_EQUAL(0.0, solarArrayCurrentA(day, 250.0), 1e-9);    // sunset
    DOUBLES_EQUAL(std::sqrt(0.5) * 2.0, solarArrayCurrentA(day, 875.0), 1e-9);  // mid-morning
}

TEST(SimWorld, OpenCircuitVoltageCurveIsMonotonic) {
    DOUBLES_EQUAL(22.0, openCircuitVoltage(0.0), 1e-12);
    DOUBLES_EQUAL(27.0, openCircuitVoltage(0.5), 1e-12);
    DOUBLES_EQUAL(29.4, openCircuitVoltage(1.0), 1e-12);
    double previous = 0.0;
    for (int i = 0; i <= 100; ++i) {
        const double v = openCircuitVoltage(i / 100.0);
        CHECK(v > previous);
        previous = v;
    }
}

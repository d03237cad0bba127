// Calibration of the habitual power model (fsw/rover_model/power_model.hpp)
// against the simulated rover, in lockstep: the flight software drives the
// simulated drives over CAN and the energy is measured as the flight software
// sees it.
//
// Measured energy: sum over the six wheels of |current actual| (DriveStatusMsg,
// as the drives report it) x bus voltage (the latest PowerMsg) x 10 ms, over
// the frames in which any wheel turns (|velocity actual| > 0.01 rad/s): what the
// drives draw to move the rover, start and stop included, and not the no-load
// current they draw while standing (the model leaves standing out). The
// simulator's own motor-current truth is integrated beside it as a cross-check.
//
// The manoeuvres are the ones the reflexive follower makes: straight at the
// habitual table's cruise speed, and turning in place at the rover geometry
// table's max_body_rate_rad_s through reflexive::skidSteerWheelSpeeds (as the
// follower commands it; the simulated chassis then turns at 1 / skid_factor of
// that). Energy per radian is per radian of true heading change.
//
// The model is asserted with the HABITUAL table's constants within kTolerance:
// if these tests fail, the table's drive_energy_j_per_m / turn_energy_j_per_rad
// are off; the calibrated values are printed (run with -v).
#include <cmath>
#include <cstdio>

#include "fsw/rover_model/power_model.hpp"
#include "fsw/reflexive/manual_drive.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;

namespace {

constexpr double kTolerance = 0.15;        // model vs measured, relative
constexpr double kRatioTolerance = 0.05;   // degraded / nominal energy vs the mean power factor
constexpr double kMovingRadS = 0.01;
constexpr double kFrameS = 0.010;
constexpr double kPi = 3.14159265358979323846;

struct Meter {
    core::PipeId pipe = 0;
    core::Message inbox{};
    double voltageV = 0.0;
    msg::DriveModesMsg modes{};
    bool haveModes = false;
    bool metering = false;
    double flightJ = 0.0;
    double truthJ = 0.0;
    double lastTheta = 0.0;
    double turnedRad = 0.0;  // sum of |heading change| since reset()

    void reset(sim::LockstepRig& rig) {
        flightJ = 0.0;
        truthJ = 0.0;
        turnedRad = 0.0;
        lastTheta = rig.rover().truth().pose.theta;
    }
};
Meter g_meter;

void meterFrame(sim::LockstepRig& rig) {
    Meter& m = g_meter;
    while (core::isOk(rig.fsw().bus().receive(m.pipe, &m.inbox))) {
        msg::PowerMsg power{};
        msg::DriveModesMsg modes{};
        msg::DriveStatusMsg status{};
        if (core::isOk(m.inbox.decode(&power))) {
            m.voltageV = power.busVoltageV;
        } else if (core::isOk(m.inbox.decode(&modes))) {
            m.modes = modes;
            m.haveModes = true;
        } else if (core::isOk(m.inbox.decode(&status)) && m.metering) {
            bool moving = false;
            double currents = 0.0;
            for (const msg::WheelStatus& w : status.wheels) {
                moving = moving || std::fabs(w.velocityRadS) > kMovingRadS;
                currents += std::fabs(w.currentA);
            }
            if (moving) {
                m.flightJ += currents * m.voltageV * kFrameS;
                m.truthJ += rig.rover().truth().motorCurrentA * rig.rover().truth().busVoltageV * kFrameS;
            }
        }
    }
    const double theta = rig.rover().truth().pose.theta;
    m.turnedRad += std::fabs(geometry::wrapAngleRad(theta - m.lastTheta));
    m.lastTheta = theta;
}

struct Measured {
    double flightJ;
    double truthJ;
    double amount;  // metres driven or radians turned
};

}  // namespace

TEST_GROUP(PowerModelCalibration) {
    sim::LockstepRig* rig = nullptr;

    void setup() override {
        sim::Scenario scenario = sim::loadScenarioFile("sim_stub/scenarios/straight_10m.toml");
        // Room to drive twice and turn: the site edge stops the simulated rover.
        scenario.map.xMin = -50.0;
        scenario.map.xMax = 100.0;
        scenario.map.yMin = -50.0;
        scenario.map.yMax = 50.0;
        rig = new sim::LockstepRig(scenario);
        CHECK(core::Status::kOk == rig->init());
        g_meter = Meter{};
        CHECK(core::isOk(rig->fsw().bus().createPipe("calibration", 8, &g_meter.pipe)));
        CHECK(core::isOk(rig->fsw().bus().subscribe(g_meter.pipe, msg::ids::kDriveStatus)));
        CHECK(core::isOk(rig->fsw().bus().subscribe(g_meter.pipe, msg::ids::kPower)));
        CHECK(core::isOk(rig->fsw().bus().subscribe(g_meter.pipe, msg::ids::kDriveModes)));
        rig->setOnFrame(meterFrame);
        CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * kNsPerSec));
        rig->runFor(500 * kNsPerMs);
        CHECK(g_meter.voltageV > 20.0);
    }
    void teardown() override {
        delete rig;
        rig = nullptr;
    }

    const tables::HabitualTable& habitualTable() { return rig->fsw().tables().habitual(); }
    double cruise() { return static_cast<double>(habitualTable().cruise_speed_m_s); }

    // Straight at the cruise speed for `metres`, then stop and settle.
    Measured driveStraight(double metres) {
        g_meter.reset(*rig);
        g_meter.metering = true;
        const double start = rig->rover().truth().distanceM;
        rig->commandBody(cruise(), 0.0);
        CHECK_TRUE(rig->runUntil([&] { return rig->rover().truth().distanceM - start >= metres; },
                                 static_cast<core::TimeNs>((metres / cruise() + 10.0) * kNsPerSec)));
        rig->commandBody(0.0, 0.0);
        rig->runFor(2 * kNsPerSec);
        g_meter.metering = false;
        return Measured{g_meter.flightJ, g_meter.truthJ, rig->rover().truth().distanceM - start};
    }

    // Turning in place as the follower commands it, for `radians` of true heading.
    Measured turnInPlace(double radians) {
        const tables::RoverGeometryTable& geometry = rig->fsw().tables().roverGeometry();
        const reflexive::WheelSpeeds speeds =
            reflexive::skidSteerWheelSpeeds(0.0, static_cast<double>(geometry.max_body_rate_rad_s), geometry);
        g_meter.reset(*rig);
        g_meter.metering = true;
        rig->commandWheels(speeds.radS);
        CHECK_TRUE(rig->runUntil([&] { return g_meter.turnedRad >= radians; }, 60 * kNsPerSec));
        rig->commandAllWheels(0.0);
        rig->runFor(2 * kNsPerSec);
        g_meter.metering = false;
        return Measured{g_meter.flightJ, g_meter.truthJ, g_meter.turnedRad};
    }

    static void print(const char* what, const Measured& m, double predicted, const char* unit) {
        char line[200];
        std::snprintf(line, sizeof line,
                      "\n%s: %.3f %s, measured %.0f J (truth %.0f J) = %.1f J/%s; model with the table %.0f J (%+.1f %%)",
                      what, m.amount, unit, m.flightJ, m.truthJ, m.flightJ / m.amount, unit, predicted,
                      100.0 * (predicted - m.flightJ) / m.flightJ);
        UT_PRINT(line);
    }
};

TEST(PowerModelCalibration, StraightDriveAtCruiseSpeedMatchesTheModel) {
    const Measured m = driveStraight(10.0);
    CHECK(m.amount > 10.0);
    DOUBLES_EQUAL(m.truthJ, m.flightJ, 0.02 * m.truthJ);  // the reported currents are the physical ones
    const rover_model::PowerModel model = rover_model::powerModelFrom(habitualTable());
    const double predicted = rover_model::motionEnergyJ(model, m.amount, 0.0, 1.0);
    print("straight", m, predicted, "m");
    DOUBLES_EQUAL(m.flightJ, predicted, kTolerance * m.flightJ);
}

TEST(PowerModelCalibration, TurnInPlaceMatchesTheModel) {
    const Measured m = turnInPlace(kPi);
    CHECK(m.amount > kPi);
    CHECK(rig->rover().truth().distanceM < 0.05);  // in place
    DOUBLES_EQUAL(m.truthJ, m.flightJ, 0.02 * m.truthJ);
    const rover_model::PowerModel model = rover_model::powerModelFrom(habitualTable());
    const double predicted = rover_model::motionEnergyJ(model, 0.0, m.amount, 1.0);
    print("turn in place", m, predicted, "rad");
    DOUBLES_EQUAL(m.flightJ, predicted, kTolerance * m.flightJ);
}

TEST(PowerModelCalibration, DegradedMotorRaisesTheEnergyByTheEstimatedMeanPowerFactor) {
    const Measured nominal = driveStraight(6.0);
    rig->rover().degradeMotor(2, 1.8);  // rear-left draws 1.8x the current for the same torque
    // Let the drive mode estimator see it (its power factor is low-pass filtered).
    rig->commandBody(cruise(), 0.0);
    rig->runFor(10 * kNsPerSec);
    const Measured degraded = driveStraight(6.0);
    CHECK_TRUE(g_meter.haveModes);
    const double factorEstimate = static_cast<double>(g_meter.modes.drives[2].powerFactor);
    const double fbar =
        rover_model::meanPowerFactor(g_meter.modes, static_cast<double>(habitualTable().failed_drive_power_factor));
    const double measuredRatio = (degraded.flightJ / degraded.amount) / (nominal.flightJ / nominal.amount);
    char line[200];
    std::snprintf(line, sizeof line,
                  "\ndegraded wheel 2 x1.8: estimated factor %.3f, mean factor %.4f; measured J/m ratio %.4f "
                  "(nominal %.1f J/m, degraded %.1f J/m)",
                  factorEstimate, fbar, measuredRatio, nominal.flightJ / nominal.amount,
                  degraded.flightJ / degraded.amount);
    UT_PRINT(line);
    DOUBLES_EQUAL(1.8, factorEstimate, 0.1);
    DOUBLES_EQUAL(fbar, measuredRatio, kRatioTolerance * measuredRatio);
    // And the model, scaled by the estimate, predicts the degraded drive from the nominal one.
    const rover_model::PowerModel calibrated{nominal.flightJ / nominal.amount, 0.0, 2.0};
    DOUBLES_EQUAL(degraded.flightJ, rover_model::motionEnergyJ(calibrated, degraded.amount, 0.0, fbar),
                  kRatioTolerance * degraded.flightJ);
}

// The power model alone: straight paths, corners, the initial turn, power
// factors and failed drives (fsw/rover_model/power_model.hpp).
#include <cmath>
#include <limits>

#include "fsw/rover_model/power_model.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using rover_model::PowerModel;

namespace {

constexpr double kPi = 3.14159265358979323846;
const PowerModel kModel{100.0, 50.0, 2.0};  // J/m, J/rad, failed factor

msg::DriveModesMsg nominalModes() {
    msg::DriveModesMsg m{};
    for (msg::DriveModeBelief& d : m.drives) {
        d.powerFactor = 1.0F;
        d.declared = msg::DriveMode::kNominal;
    }
    return m;
}

}  // namespace

TEST_GROUP(PowerModel){};

TEST(PowerModel, StraightPathAheadCostsItsLengthOnly) {
    const Point2 path[] = {{0.0, 0.0}, {4.0, 0.0}, {10.0, 0.0}};
    DOUBLES_EQUAL(0.0, rover_model::totalHeadingChangeRad(path, 3, 0.0), 1e-12);
    DOUBLES_EQUAL(1000.0, rover_model::pathEnergyJ(kModel, path, 3, 0.0, 1.0), 1e-9);
}

TEST(PowerModel, InitialTurnFromTheCurrentHeadingIsCounted) {
    const Point2 path[] = {{0.0, 0.0}, {0.0, 10.0}};  // north, rover facing east
    DOUBLES_EQUAL(kPi / 2.0, rover_model::totalHeadingChangeRad(path, 2, 0.0), 1e-12);
    DOUBLES_EQUAL(1000.0 + 50.0 * kPi / 2.0, rover_model::pathEnergyJ(kModel, path, 2, 0.0, 1.0), 1e-9);
    // Facing west: the turn is the short way round, pi/2 again, not 3 pi / 2.
    DOUBLES_EQUAL(kPi / 2.0, rover_model::totalHeadingChangeRad(path, 2, kPi), 1e-12);
}

TEST(PowerModel, EveryCornerCountsItsAbsoluteHeadingChange) {
    // East 3 m, north 4 m, then straight back to the start.
    const Point2 path[] = {{0.0, 0.0}, {3.0, 0.0}, {3.0, 4.0}, {0.0, 0.0}};
    const double back = std::atan2(-4.0, -3.0);  // heading of the last leg
    const double expectedTurn = kPi / 2.0 + std::fabs(geometry::wrapAngleRad(back - kPi / 2.0));
    DOUBLES_EQUAL(expectedTurn, rover_model::totalHeadingChangeRad(path, 4, 0.0), 1e-12);
    // A left and a right turn both cost: zig-zag 45 deg each way.
    const Point2 zig[] = {{0.0, 0.0}, {1.0, 1.0}, {2.0, 0.0}, {3.0, 1.0}};
    DOUBLES_EQUAL(kPi / 4.0 + kPi / 2.0 + kPi / 2.0, rover_model::totalHeadingChangeRad(zig, 4, 0.0), 1e-12);
    DOUBLES_EQUAL(100.0 * 3.0 * std::sqrt(2.0) + 50.0 * 1.25 * kPi, rover_model::pathEnergyJ(kModel, zig, 4, 0.0, 1.0),
                  1e-9);
}

TEST(PowerModel, RepeatedPointsHaveNoDirectionAndAreSkipped) {
    const Point2 path[] = {{0.0, 0.0}, {0.0, 0.0}, {5.0, 0.0}, {5.0, 0.0}, {5.0, 5.0}};
    DOUBLES_EQUAL(kPi / 2.0, rover_model::totalHeadingChangeRad(path, 5, 0.0), 1e-12);
    DOUBLES_EQUAL(0.0, rover_model::pathEnergyJ(kModel, path, 1, 0.0, 1.0), 0.0);
    DOUBLES_EQUAL(0.0, rover_model::pathEnergyJ(kModel, nullptr, 4, 0.0, 1.0), 0.0);
}

TEST(PowerModel, EnergyScalesWithTheMeanPowerFactor) {
    msg::DriveModesMsg m = nominalModes();
    DOUBLES_EQUAL(1.0, rover_model::meanPowerFactor(m, 2.0), 1e-12);
    m.drives[2].powerFactor = 1.8F;  // one degraded drive
    const double fbar = (5.0 + 1.8) / 6.0;
    DOUBLES_EQUAL(fbar, rover_model::meanPowerFactor(m, 2.0), 1e-6);
    const Point2 path[] = {{0.0, 0.0}, {10.0, 0.0}};
    DOUBLES_EQUAL(1000.0 * fbar, rover_model::pathEnergyJ(kModel, path, 2, 0.0, rover_model::meanPowerFactor(m, 2.0)),
                  1e-3);
    DOUBLES_EQUAL(3.0 * (100.0 * 2.0 + 50.0 * 0.5), rover_model::motionEnergyJ(kModel, 2.0, 0.5, 3.0), 1e-12);
}

TEST(PowerModel, FactorsBelowNominalAreTakenAsNominal) {
    msg::DriveModesMsg m = nominalModes();
    m.drives[0].powerFactor = 0.4F;  // idle or slipping: its share falls on the others
    DOUBLES_EQUAL(1.0, rover_model::meanPowerFactor(m, 2.0), 1e-12);
}

TEST(PowerModel, FailedDriveCountsAtLeastTheTablesFailedFactor) {
    msg::DriveModesMsg m = nominalModes();
    m.drives[5].declared = msg::DriveMode::kFailed;
    m.drives[5].powerFactor = 0.0F;  // a locked wheel draws nothing itself
    DOUBLES_EQUAL((5.0 + 2.0) / 6.0, rover_model::meanPowerFactor(m, 2.0), 1e-12);
    m.drives[5].powerFactor = 3.0F;  // its own estimate wins when higher
    DOUBLES_EQUAL((5.0 + 3.0) / 6.0, rover_model::meanPowerFactor(m, 2.0), 1e-6);
    // Unknown stands for failures the mode model does not describe: as failed.
    m.drives[5].declared = msg::DriveMode::kUnknown;
    m.drives[5].powerFactor = 1.0F;
    DOUBLES_EQUAL((5.0 + 2.0) / 6.0, rover_model::meanPowerFactor(m, 2.0), 1e-12);
    // A degraded drive is not failed: its estimate stands.
    m.drives[5].declared = msg::DriveMode::kDegraded;
    m.drives[5].powerFactor = 1.5F;
    DOUBLES_EQUAL((5.0 + 1.5) / 6.0, rover_model::meanPowerFactor(m, 2.0), 1e-12);
}

TEST(PowerModel, NonFiniteFactorCountsAsFailed) {
    msg::DriveModesMsg m = nominalModes();
    m.drives[1].powerFactor = std::numeric_limits<float>::quiet_NaN();
    DOUBLES_EQUAL((5.0 + 2.0) / 6.0, rover_model::meanPowerFactor(m, 2.0), 1e-12);
}

TEST(PowerModel, ParametersComeFromTheHabitualTable) {
    tables::HabitualTable t{};
    t.drive_energy_j_per_m = 123.0F;
    t.turn_energy_j_per_rad = 45.0F;
    t.failed_drive_power_factor = 2.5F;
    const PowerModel m = rover_model::powerModelFrom(t);
    DOUBLES_EQUAL(123.0, m.driveEnergyJPerM, 1e-9);
    DOUBLES_EQUAL(45.0, m.turnEnergyJPerRad, 1e-9);
    DOUBLES_EQUAL(2.5, m.failedDrivePowerFactor, 1e-9);
}

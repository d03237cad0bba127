// The rover's power model: the energy the six wheel drives will draw to drive
// a path, and the power they draw at the cruise speed. The deliberative layer
// sets each leg's not-to-exceed energy and power with it;
// the habitual layer checks a plan against that bound before the rover commits
// to it. Both layers use it, so it sits below both (fsw/rover_model/).
//
//   E = fbar * (e_m * L + e_r * Theta)
//
//   L      path length (m)
//   Theta  sum of |heading change| (rad): the turn from the rover's current
//          heading onto the first segment, plus the turn at every corner
//   e_m    HABITUAL.drive_energy_j_per_m: what six nominal drives draw per metre
//          driven straight at the cruise speed
//   e_r    HABITUAL.turn_energy_j_per_rad: what they draw per radian turned in
//          place at the follower's turn rate
//   fbar   mean over the six drives of each drive's power factor (DriveModesMsg:
//          its current relative to a nominal drive's), where a drive declared
//          failed or unknown counts at least HABITUAL.failed_drive_power_factor,
//          and any other drive at least 1
//
// Assumptions, and why they hold well enough for a go / no-go check:
// - A drive's current at steady speed is constant (no-load current plus the
//   rolling-resistance torque), so its energy per metre is power / speed: e_m is
//   only valid at the speed it was calibrated at, which is the cruise speed the
//   habitual layer asks for. Acceleration and deceleration (0.3 s at 0.2 m/s^2)
//   are a few percent of a leg and are left out.
// - A corner costs its heading change at the turn-in-place rate whether the
//   follower turns in place or rounds it on an arc: the scrubbing torque is paid
//   per radian either way, and rounding shortens the path a little, so the
//   model leans to the high side.
// - Each drive carries one sixth of the nominal load and its current scales by
//   its factor, so the total scales by the mean factor. A drive drawing less than
//   its peers is idle or slipping and its share falls on the others, so no
//   factor is taken below 1: the model never predicts less than nominal. A
//   locked (failed) wheel draws nothing itself but the other five drag it; the
//   table's failed factor stands for that extra load.
// - Flat ground: slope, soil changes and the avionics base load are not here
//   (the base load does not depend on the path).
// - Energy the drives draw while the rover stands still (no-load current while
//   planning) is not path energy and is not counted.
// Calibration against the simulator: unit_test/fsw/rover_model/test_power_model_calibration.cpp
// and docs/habitual.md ("Power model").
//
// Pure math: no bus, no events, no state.
#pragma once

#include <cstddef>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::rover_model {

struct PowerModel {
    double driveEnergyJPerM;        // e_m
    double turnEnergyJPerRad;       // e_r
    double failedDrivePowerFactor;  // floor for a drive declared failed or unknown
};

PowerModel powerModelFrom(const tables::HabitualTable& table);

// fbar (>= 1). A factor that is not finite counts as a failed drive's.
double meanPowerFactor(const msg::DriveModesMsg& modes, double failedDrivePowerFactor);

// Theta of path[0..count) for a rover at path[0] facing headingRad. Zero-length
// segments have no direction and are skipped; 0 for fewer than two points.
double totalHeadingChangeRad(const geometry::Point2* path, std::size_t count, double headingRad);

// E for a length and a heading change already known (e.g. the part of a leg
// already driven).
double motionEnergyJ(const PowerModel& model, double lengthM, double headingChangeRad, double meanFactor);

// E of path[0..count) for a rover at path[0] facing headingRad.
double pathEnergyJ(const PowerModel& model, const geometry::Point2* path, std::size_t count, double headingRad,
                   double meanFactor);

// P = fbar * e_m * v: the power the six drives draw driving straight at the
// cruise speed v (m/s), e_m being energy per metre at that speed. What a leg's
// power bound limits: it depends on the drives' health, not on the path, so
// no local replan can lower it (docs/habitual.md, "Power bound").
double cruisePowerW(const PowerModel& model, double cruiseSpeedMS, double meanFactor);

}  // namespace rse::rover_model

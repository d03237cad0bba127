// What really happened in the simulated world. Readable by the test harness
// only: the flight software sees nothing but CAN frames.
#pragma once

#include <array>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "sim_stub/world/geometry.hpp"
#include "sim_stub/world/kinematics.hpp"

namespace rse::sim {

struct WheelTruth {
    double speedRadS = 0.0;     // from the wheel model
    double currentA = 0.0;      // from the wheel model
    double loadTorqueNm = 0.0;  // from the load model, applied on the next step
};

struct TruthRecord {
    core::TimeNs time = 0;
    Pose2 pose;
    double speedMS = 0.0;            // achieved forward speed (0 while blocked)
    double yawRateRadS = 0.0;        // achieved yaw rate (with slip noise)
    double commandedSpeedMS = 0.0;   // what the wheels alone would give (no slip, not blocked)
    double commandedYawRateRadS = 0.0;
    double distanceM = 0.0;          // path length driven
    std::array<WheelTruth, kWheelCount> wheels{};

    double stateOfCharge = 0.0;      // 0..1
    double busVoltageV = 0.0;
    double busCurrentA = 0.0;        // net battery current, + = discharge
    double motorCurrentA = 0.0;      // sum of |motor current|
    double baseLoadCurrentA = 0.0;
    double solarCurrentA = 0.0;
    double energyDrawnWh = 0.0;

    std::uint32_t collisions = 0;          // new contacts of the footprint with an obstacle or the map's edge
    double leastClearanceM = 1e9;          // least gap between the footprint disc and an obstacle so far (<= 0: touched)
    bool inContact = false;                // touching (blocked by) an obstacle now
    std::uint16_t lastCollisionObstacle = 0;  // obstacle id of the latest contact with an obstacle
    std::uint32_t mapEdgeHits = 0;         // new contacts with the map boundary (counted in collisions too)
    bool atMapEdge = false;
    bool blocked = false;                  // the last sub-step's translation was refused
};

}  // namespace rse::sim

// Six-wheel skid-steer rover (Rocky 8 style): kinematics and wheel load model.
//
// Wheels are indexed 0..5 in the ICD's node order (docs/icd.md §1.1):
//   0 front-left, 1 middle-left, 2 rear-left, 3 front-right, 4 middle-right, 5 rear-right.
// A positive wheel speed drives the rover forward on both sides (the drive
// reports wheel angular velocity, not motor-shaft rotation).
//
// Kinematics (skid-steer with an empirical skid factor chi >= 1):
//   v     = r * (mean_left + mean_right) / 2
//   omega = r * (mean_right - mean_left) / (chi * B)
// r wheel radius, B track width; chi > 1 because the wheels must scrub sideways
// to turn a rigid six-wheel chassis, so the body turns slower than a two-wheel
// differential drive would.
//
// Failed (locked) wheel: its zero speed enters its side's mean, so that side is
// slower and the rover both loses speed and yaws toward the failed side; the
// locked wheel is dragged, sliding, at a friction force mu_slide * N that the
// turning wheels share as extra load torque (see wheelLoadTorques).
//
// Pose integration: exact unicycle solution over each fixed sub-step (the body
// rates are constant within it), so straight driving keeps the heading exactly.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "sim_stub/world/geometry.hpp"

namespace rse::sim {

constexpr std::size_t kWheelCount = 6;
using WheelArray = std::array<double, kWheelCount>;

// A wheel slower than this (rad/s) is "not turning": locked or stopped.
constexpr double kStoppedWheelRadS = 0.01;

struct RoverParams {
    double wheelRadiusM = 0.10;
    double trackWidthM = 0.60;
    double massKg = 100.0;
    double radiusM = 0.60;            // footprint circle for collisions
    double skidFactor = 1.5;          // chi >= 1
    double gravityMS2 = 3.711;        // Mars
    double rollingCoefficient = 0.10; // rolling resistance, soft soil
    // Skid-steer scrubbing: extra load torque per wheel, N*m per rad/s of body yaw rate.
    double turnTorquePerRadS = 2.0;
    double slideFriction = 0.5;       // sliding friction of a dragged (locked) wheel or a blocked rover
    double slipSigma = 0.0;           // relative wheel-slip noise on v and omega (0 = off)
    std::array<std::uint8_t, kWheelCount> driveNodes{{1, 2, 3, 4, 5, 6}};

    double wheelNormalLoadN() const { return massKg * gravityMS2 / static_cast<double>(kWheelCount); }
};

struct BodyRates {
    double speedMS = 0.0;      // forward speed v
    double yawRateRadS = 0.0;  // omega, + = counter-clockwise (left)
};

BodyRates skidSteerRates(const WheelArray& wheelSpeedsRadS, const RoverParams& rover);

// Exact solution of x' = v cos(theta), y' = v sin(theta), theta' = omega over dt
// seconds with constant v and omega. Heading wrapped to (-pi, pi].
Pose2 integrateUnicycle(const Pose2& pose, double speedMS, double yawRateRadS, double dtS);

// Per-wheel load torque (N*m) the ground exerts against each wheel, signed like
// the wheel's speed (a positive value resists positive rotation; the motor must
// produce it to hold speed). For a turning wheel:
//   tau = sign(w) * ( C_rr * N * r                       rolling resistance
//                   + k_turn * |omega|                   skid-steer scrubbing
//                   + n_dragged * mu_slide * N * r / n_turning  dragging stopped wheels
//                   + (blocked ? mu_slide * N * r : 0) )        pushing against an obstacle
// with N = m g / 6. A wheel that is not turning gets 0. A stopped wheel is
// dragged only when the ground under its side moves (the side's mean wheel
// speed is not stopped): a locked wheel beside two turning ones is, but in a
// pivot turn about a stopped side nothing slides along the wheels' direction.
void wheelLoadTorques(const RoverParams& rover, const WheelArray& wheelSpeedsRadS, double yawRateRadS,
                      bool blocked, WheelArray* torquesNm);

}  // namespace rse::sim

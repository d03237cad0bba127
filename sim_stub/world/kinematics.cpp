#include "sim_stub/world/kinematics.hpp"

#include <cmath>

namespace rse::sim {

BodyRates skidSteerRates(const WheelArray& w, const RoverParams& rover) {
    const double left = (w[0] + w[1] + w[2]) / 3.0;
    const double right = (w[3] + w[4] + w[5]) / 3.0;
    BodyRates rates;
    rates.speedMS = rover.wheelRadiusM * (left + right) / 2.0;
    rates.yawRateRadS = rover.wheelRadiusM * (right - left) / (rover.skidFactor * rover.trackWidthM);
    return rates;
}

Pose2 integrateUnicycle(const Pose2& pose, double v, double omega, double dtS) {
    Pose2 next = pose;
    const double dTheta = omega * dtS;
    if (std::fabs(dTheta) < 1e-12) {
        // Straight (or nearly): the arc formula would divide by ~0. Midpoint heading
        // keeps the error O(dTheta^2) and exactly straight when omega is 0.
        const double mid = pose.theta + 0.5 * dTheta;
        next.x += v * dtS * std::cos(mid);
        next.y += v * dtS * std::sin(mid);
    } else {
        const double radius = v / omega;
        next.x += radius * (std::sin(pose.theta + dTheta) - std::sin(pose.theta));
        next.y -= radius * (std::cos(pose.theta + dTheta) - std::cos(pose.theta));
    }
    next.theta = wrapAngle(pose.theta + dTheta);
    return next;
}

void wheelLoadTorques(const RoverParams& rover, const WheelArray& w, double yawRateRadS, bool blocked,
                      WheelArray* torquesNm) {
    const double normal = rover.wheelNormalLoadN();
    const double r = rover.wheelRadiusM;
    // The ground under each side moves at the side's mean wheel speed (the
    // kinematics above); a stopped wheel slides only if its side moves.
    const double left = (w[0] + w[1] + w[2]) / 3.0;
    const double right = (w[3] + w[4] + w[5]) / 3.0;
    std::size_t turning = 0;
    std::size_t dragged = 0;
    for (std::size_t i = 0; i < kWheelCount; ++i) {
        const double side = i < kWheelCount / 2 ? left : right;
        if (std::fabs(w[i]) > kStoppedWheelRadS) {
            ++turning;
        } else if (std::fabs(side) > kStoppedWheelRadS) {
            ++dragged;
        }
    }
    double perWheel = rover.rollingCoefficient * normal * r + rover.turnTorquePerRadS * std::fabs(yawRateRadS);
    if (turning > 0) {
        perWheel += static_cast<double>(dragged) * rover.slideFriction * normal * r / static_cast<double>(turning);
    }
    if (blocked) {
        perWheel += rover.slideFriction * normal * r;
    }
    for (std::size_t i = 0; i < kWheelCount; ++i) {
        if (std::fabs(w[i]) > kStoppedWheelRadS) {
            (*torquesNm)[i] = w[i] > 0.0 ? perWheel : -perWheel;
        } else {
            (*torquesNm)[i] = 0.0;
        }
    }
}

}  // namespace rse::sim

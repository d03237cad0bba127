// Test-only: six wheel drives as the simulator's CiA 402 emulator behaves
// (sim_stub/drives/cia402_drive_emulator.hpp), reduced to what the drive mode
// estimator sees in DriveStatusMsg:
//   velocity  first-order lag to the target, tau 50 ms, integrated in 1 ms steps;
//             reported one frame late (the TPDO answers the previous SYNC)
//   current   degradation x (150 mA + 2000 mA/N m x |load| + 20 mA/(rad/s^2) x |dv/dt|)
//             while the torque is on, 0 when the motor has failed; plus seeded
//             Gaussian noise on every report
//   load      the same for all wheels (rolling resistance and a term in the
//             left/right speed difference, i.e. the yaw rate), times a per-wheel
//             factor within +-2 % ("almost the same")
//   failure   torque off at once (the wheel coasts to 0 with the lag, current 0),
//             health kFaulted one frame later, kFailed 300 ms after that
//   interlock two frames after any drive first reports a fault every target is 0
//             (latched), as fsw/io/drive_interlock does
//   jam       (a failure the model does not describe) the wheel is held at 0 while
//             the motor pushes: extra load torque, no fault report
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "fsw/core/clock.hpp"
#include "fsw/msg/drive_msgs.hpp"

namespace rse::test {

class DriveModel {
public:
    static constexpr core::TimeNs kFrame = 10 * core::kNsPerMs;

    explicit DriveModel(std::uint64_t seed, double currentSigmaA = 0.03, double velocitySigmaRadS = 0.01)
        : rng_(seed), currentNoise_(0.0, currentSigmaA), velocityNoise_(0.0, velocitySigmaRadS) {
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            health_[w] = msg::DriveHealth::kOperational;
        }
    }

    // Skid-steer: wheels 0-2 left, 3-5 right (docs/icd.md §1.1).
    void command(double leftRadS, double rightRadS) {
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            commanded_[w] = w < msg::kWheelCount / 2 ? leftRadS : rightRadS;
        }
    }
    void degrade(std::size_t wheel, double factor) { degradation_[wheel] = factor; }
    void failMotor(std::size_t wheel) {
        if (!failed_[wheel]) {
            failed_[wheel] = true;
            failedAt_[wheel] = now_;
        }
    }
    void jam(std::size_t wheel, double extraLoadNm) { jamLoadNm_[wheel] = extraLoadNm; }
    void setHealth(std::size_t wheel, msg::DriveHealth health) { forcedHealth_[wheel] = health; forced_[wheel] = true; }
    void setEmcy(std::size_t wheel, std::uint16_t code) { emcy_[wheel] = code; }
    bool interlockTripped() const { return tripped_; }
    core::TimeNs now() const { return now_; }

    // One 10 ms frame: the physics up to the next frame time, then the status
    // the flight software would publish at that time.
    msg::DriveStatusMsg step() {
        const core::TimeNs frameStart = now_;
        // The interlock acts on what the previous frames reported.
        if (!tripped_ && faultSeenAt_ >= 0 && frameStart >= faultSeenAt_ + 2 * kFrame) {
            tripped_ = true;
        }
        double target[msg::kWheelCount];
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            target[w] = tripped_ ? 0.0 : commanded_[w];
        }
        const double loadNm = 0.3 + 0.5 * std::fabs(target[msg::kWheelCount - 1] - target[0]);
        double currentMa[msg::kWheelCount] = {};
        const double h = 1e-3;
        const double decay = std::exp(-h / 0.05);
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            reportedVelocity_[w] = velocity_[w];  // what the TPDO of the previous SYNC said
            double accelSum = 0.0;
            for (int k = 0; k < 10; ++k) {
                const double goal = failed_[w] || jamLoadNm_[w] > 0.0 ? 0.0 : target[w];
                const double next = goal + (velocity_[w] - goal) * decay;
                accelSum += std::fabs(next - velocity_[w]) / h;
                velocity_[w] = next;
            }
            if (!failed_[w]) {
                const double load = loadNm * kLoadFactor[w] + jamLoadNm_[w];
                currentMa[w] = degradation_[w] * (150.0 + 2000.0 * load + 20.0 * accelSum / 10.0);
            }
        }
        now_ += kFrame;
        msg::DriveStatusMsg s{};
        s.timeNs = now_;
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            msg::WheelStatus& ws = s.wheels[w];
            ws.targetRadS = target[w];
            ws.velocityRadS = reportedVelocity_[w] + velocityNoise_(rng_);
            const double noise = currentNoise_(rng_);
            ws.currentA = failed_[w] ? 0.0 : currentMa[w] * 1e-3 + noise;
            ws.feedbackTimeNs = now_ - kFrame;
            ws.feedbackCount = ++feedbackCount_;
            ws.health = healthOf(w);
            ws.lastEmcyCode = failed_[w] ? 0x5000 : emcy_[w];
            if (ws.health == msg::DriveHealth::kFaulted || ws.health == msg::DriveHealth::kFailed) {
                if (faultSeenAt_ < 0) {
                    faultSeenAt_ = now_;
                }
            }
        }
        s.interlockTripped = tripped_ ? 1 : 0;
        return s;
    }

private:
    static constexpr double kLoadFactor[msg::kWheelCount] = {1.0, 1.02, 0.98, 1.01, 0.99, 1.0};

    msg::DriveHealth healthOf(std::size_t w) const {
        if (forced_[w]) {
            return forcedHealth_[w];
        }
        if (failed_[w] && now_ > failedAt_[w] + kFrame) {
            return now_ >= failedAt_[w] + kFrame + 300 * core::kNsPerMs ? msg::DriveHealth::kFailed
                                                                     : msg::DriveHealth::kFaulted;
        }
        return health_[w];
    }

    std::mt19937_64 rng_;
    std::normal_distribution<double> currentNoise_;
    std::normal_distribution<double> velocityNoise_;
    core::TimeNs now_ = 0;
    double commanded_[msg::kWheelCount] = {};
    double velocity_[msg::kWheelCount] = {};
    double reportedVelocity_[msg::kWheelCount] = {};
    double degradation_[msg::kWheelCount] = {1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
    double jamLoadNm_[msg::kWheelCount] = {};
    bool failed_[msg::kWheelCount] = {};
    core::TimeNs failedAt_[msg::kWheelCount] = {};
    msg::DriveHealth health_[msg::kWheelCount];
    msg::DriveHealth forcedHealth_[msg::kWheelCount] = {};
    bool forced_[msg::kWheelCount] = {};
    std::uint16_t emcy_[msg::kWheelCount] = {};
    core::TimeNs faultSeenAt_ = -1;
    bool tripped_ = false;
    std::uint32_t feedbackCount_ = 0;
};

}  // namespace rse::test

#include "sim_stub/drives/cia402_drive_emulator.hpp"

#include <cmath>

#include "sim_stub/drives/cia402_drive_codes.hpp"

// The wheel drive emulator's motor and thermal models and its noisy reports
// (cia402_drive_emulator.hpp, "Motor model", "Thermal model", "Measurement noise").

namespace rse::sim {

namespace {

using namespace drive_codes;

constexpr std::size_t kMaxModelSubsteps = 100000;  // bounds one step's integration loop

double seconds(core::TimeNs t) { return static_cast<double>(t) / static_cast<double>(core::kNsPerSec); }

}  // namespace

bool Cia402DriveEmulator::torqueOn() const {
    return life_ == NodeLife::kRunning && !motorFailed_ &&
           (power_ == PowerState::kOperationEnabled || power_ == PowerState::kQuickStopActive);
}

double Cia402DriveEmulator::effectiveTargetRadS() const {
    if (power_ != PowerState::kOperationEnabled || mode_ != kProfileVelocityMode) {
        return 0.0;
    }
    std::int32_t t = targetVelocity_;
    const std::int32_t limit = config_.speedLimitMradS > 0 ? config_.speedLimitMradS : 0;
    if (t > limit) {
        t = limit;
    } else if (t < -limit) {
        t = -limit;
    }
    return static_cast<double>(t) / 1000.0;
}

void Cia402DriveEmulator::advanceTemperature(double dts) {
    const double amps = current_ * 1e-3;
    const double tau = seconds(config_.thermalTimeConstant);
    const double cooling = tau > 0.0 ? (temperatureC_ - config_.ambientC) / tau : 0.0;
    temperatureC_ += dts * (config_.heatGainCPerA2S * overheat_ * amps * amps - cooling);
}

void Cia402DriveEmulator::advanceModel(core::TimeNs now) {
    if (!haveTime_) {
        haveTime_ = true;
        time_ = now;
        return;
    }
    const core::TimeNs h = config_.modelStep > 0 ? config_.modelStep : core::kNsPerMs;
    const double tau = seconds(config_.velocityTimeConstant);
    for (std::size_t n = 0; time_ < now && n < kMaxModelSubsteps; ++n) {
        const core::TimeNs remaining = now - time_;
        const core::TimeNs dt = (remaining > h && n + 1 < kMaxModelSubsteps) ? h : remaining;
        const double dts = seconds(dt);
        const double decay = tau > 0.0 ? std::exp(-dts / tau) : 0.0;
        const bool on = torqueOn();
        const double target = on ? effectiveTargetRadS() : 0.0;
        const double before = velocity_;
        velocity_ = target + (before - target) * decay;
        if (std::fabs(velocity_) < 1e-9 && target == 0.0) {
            velocity_ = 0.0;  // no denormal tail
        }
        time_ += dt;
        if (!on) {
            current_ = 0.0;
            overCurrentTiming_ = false;
            advanceTemperature(dts);
            continue;
        }
        const double acceleration = (velocity_ - before) / dts;
        // Braking a wheel that slips under a blocked rover: the slip's friction
        // stops it, the drive does not push against it (the block share off).
        const bool braking = std::fabs(velocity_) > std::fabs(target) + kBrakingMarginRadS || velocity_ * target < 0.0;
        const double load = braking ? loadTorqueNm_ - blockTorqueNm_ : loadTorqueNm_;
        current_ = degradation_ * (config_.noLoadCurrentMa + config_.currentPerTorqueMaPerNm * std::fabs(load) +
                                   config_.currentPerAccelMaPerRadS2 * std::fabs(acceleration));
        advanceTemperature(dts);
        if (current_ <= static_cast<double>(config_.overCurrentLimitMa)) {
            overCurrentTiming_ = false;
            continue;
        }
        if (!overCurrentTiming_) {
            overCurrentTiming_ = true;
            overCurrentSince_ = time_;
        } else if (time_ - overCurrentSince_ > config_.overCurrentTime) {
            overCurrentTiming_ = false;
            raiseError(kErrOverCurrent, emcy::kOverCurrent, time_);  // power stage off from here on
        }
    }
}

std::int32_t Cia402DriveEmulator::velocityActualMradS() const {
    return clampTo<std::int32_t>(std::llround(velocity_ * 1000.0), INT32_MIN, INT32_MAX);
}

std::int16_t Cia402DriveEmulator::currentActualMa() const {
    return clampTo<std::int16_t>(std::llround(current_), INT16_MIN, INT16_MAX);
}

// One report: the model value plus one noise draw, then quantised and saturated
// like the noise-free value. With sigma 0 nothing is drawn.
std::int32_t Cia402DriveEmulator::reportVelocityMradS() {
    if (config_.velocitySigmaMradS > 0.0) {
        const double v = velocity_ * 1000.0 + config_.velocitySigmaMradS * velocityRng_.gaussian();
        reportedVelocity_ = clampTo<std::int32_t>(std::llround(v), INT32_MIN, INT32_MAX);
    } else {
        reportedVelocity_ = velocityActualMradS();
    }
    return reportedVelocity_;
}

std::int16_t Cia402DriveEmulator::reportCurrentMa() {
    if (config_.currentSigmaMa > 0.0) {
        const double c = current_ + config_.currentSigmaMa * currentRng_.gaussian();
        reportedCurrent_ = clampTo<std::int16_t>(std::llround(c), INT16_MIN, INT16_MAX);
    } else {
        reportedCurrent_ = currentActualMa();
    }
    return reportedCurrent_;
}

}  // namespace rse::sim

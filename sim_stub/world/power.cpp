#include "sim_stub/world/power.hpp"

#include <cmath>

#include "sim_stub/world/geometry.hpp"

namespace rse::sim {

namespace {
struct OcvPoint {
    double soc;
    double volts;
};
constexpr OcvPoint kOcv[] = {{0.0, 22.0}, {0.1, 25.2}, {0.5, 27.0}, {0.9, 28.4}, {1.0, 29.4}};
constexpr std::size_t kOcvPoints = sizeof(kOcv) / sizeof(kOcv[0]);

double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }
}  // namespace

double openCircuitVoltage(double soc) {
    const double s = clamp01(soc);
    for (std::size_t i = 1; i < kOcvPoints; ++i) {
        if (s <= kOcv[i].soc) {
            const double t = (s - kOcv[i - 1].soc) / (kOcv[i].soc - kOcv[i - 1].soc);
            return kOcv[i - 1].volts + t * (kOcv[i].volts - kOcv[i - 1].volts);
        }
    }
    return kOcv[kOcvPoints - 1].volts;
}

double solarArrayCurrentA(const SolarParams& solar, double timeS) {
    if (solar.profile == SolarProfile::kConstant) {
        return solar.peakCurrentA;
    }
    const double s = std::sin(2.0 * kPi * (timeS / solar.dayLengthS + solar.phase));
    return s > 0.0 ? solar.peakCurrentA * s : 0.0;
}

Battery::Battery(const BatteryParams& battery, const SolarParams& solar)
    : params_(battery), solar_(solar), soc_(clamp01(battery.initialSoc)), voltage_(openCircuitVoltage(soc_)) {
    baseCurrent_ = params_.baseLoadW / voltage_;
    solarCurrent_ = solarArrayCurrentA(solar_, 0.0);
    busCurrent_ = baseCurrent_ - solarCurrent_;
}

void Battery::step(double dtS, double timeS, double motorCurrentSumA) {
    motorCurrent_ = std::fabs(motorCurrentSumA);
    solarCurrent_ = solarArrayCurrentA(solar_, timeS);
    // Base load at the previous voltage: an explicit step, no implicit solve.
    baseCurrent_ = voltage_ > 1.0 ? params_.baseLoadW / voltage_ : 0.0;
    busCurrent_ = motorCurrent_ + baseCurrent_ - solarCurrent_;
    if (busCurrent_ < 0.0 && soc_ >= 1.0) {
        // Full: the shunt regulator sheds what the loads do not take, so a
        // strong array cannot push the pack above its full voltage.
        solarCurrent_ = motorCurrent_ + baseCurrent_;
        busCurrent_ = 0.0;
    }
    if (dtS > 0.0) {
        const double capacityAs = params_.capacityAh * 3600.0;
        soc_ = clamp01(soc_ - busCurrent_ * dtS / capacityAs);
        energyDrawnWh_ += busCurrent_ * voltage_ * dtS / 3600.0;
    }
    voltage_ = openCircuitVoltage(soc_) - params_.internalResistanceOhm * busCurrent_;
}

}  // namespace rse::sim

// Battery and solar array.
//
// Bus current (+ = discharge) = sum |motor current| + base load / V - solar current.
// Motor currents are taken as drawn from the bus at bus voltage (the drives'
// converters are lossless; no regeneration: a negative motor current counts as
// its magnitude). The avionics base load is a constant power.
// State of charge: dQ/dt = -I_bus, SoC = Q / capacity, clamped to [0, 1].
// Recharge: whenever the array gives more than the loads draw, I_bus < 0 and
// the pack charges, at rest or driving (a scenario sets the array's current:
// the default 1 A array against the 25 W base load nets about zero, so a
// recharge test needs a stronger one, e.g. scenarios/low_battery.toml). A full
// pack (SoC 1) takes no charge: a shunt regulator sheds the surplus, so
// solarCurrentA() is then what the loads use and I_bus = 0.
// Voltage: V = OCV(SoC) - R_int * I_bus, with OCV piecewise linear through
//   SoC 0 -> 22.0 V, 0.1 -> 25.2 V, 0.5 -> 27.0 V, 0.9 -> 28.4 V, 1.0 -> 29.4 V
// (a 7-cell Li-ion pack on a nominal 28 V bus).
// Solar: constant (peak current always) or a day profile
//   I = peak * max(0, sin(2 pi (t / day_length + phase)))
// where phase is the fraction of the day at t = 0 (0 sunrise, 0.25 noon,
// 0.5 sunset, 0.5..1 night).
#pragma once

#include <cstdint>

namespace rse::sim {

struct BatteryParams {
    double capacityAh = 20.0;
    double initialSoc = 0.90;
    double baseLoadW = 25.0;            // avionics, always on
    double internalResistanceOhm = 0.05;
};

enum class SolarProfile : std::uint8_t { kConstant, kDay };

struct SolarParams {
    SolarProfile profile = SolarProfile::kConstant;
    double peakCurrentA = 1.0;
    double dayLengthS = 88775.0;  // one Mars sol
    double phase = 0.25;          // noon at t = 0
};

double openCircuitVoltage(double soc);
double solarArrayCurrentA(const SolarParams& solar, double timeS);

class Battery {
public:
    Battery(const BatteryParams& battery, const SolarParams& solar);

    // Integrates dtS seconds ending at timeS with the sum of the motor current
    // magnitudes held over the interval.
    void step(double dtS, double timeS, double motorCurrentSumA);

    double stateOfCharge() const { return soc_; }
    double voltageV() const { return voltage_; }
    double busCurrentA() const { return busCurrent_; }  // net, + = discharge
    double baseCurrentA() const { return baseCurrent_; }
    double solarCurrentA() const { return solarCurrent_; }
    double motorCurrentA() const { return motorCurrent_; }
    double energyDrawnWh() const { return energyDrawnWh_; }  // from the battery, net of solar

private:
    BatteryParams params_;
    SolarParams solar_;
    double soc_;
    double voltage_;
    double busCurrent_ = 0.0;
    double baseCurrent_ = 0.0;
    double solarCurrent_ = 0.0;
    double motorCurrent_ = 0.0;
    double energyDrawnWh_ = 0.0;
};

}  // namespace rse::sim

// Recharging at rest (issue 13, "low battery ignored"): the fault response
// stops the rover and waits for the array to recharge the pack past
// FAULT_RESPONSE.battery_clear_v, so the simulator must be able to do that, in
// a time a lockstep test can wait for.
#include <cstdint>

#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "sim_stub/world/power.hpp"
#include "sim_stub/world/world.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;

namespace {

constexpr core::TimeNs kStep = 10 * core::kNsPerMs;

tables::FaultResponseTable defaultFaultResponse() {
    tables::FaultResponseTable t{};
    for (std::size_t i = 0; i < tables::kDefaultTableImageCount; ++i) {
        const tables::TableImageRef& ref = tables::kDefaultTableImages[i];
        if (tables::decodeTable(ref.data, ref.length, &t).ok()) {
            return t;
        }
    }
    FAIL("no default FAULT_RESPONSE image");
    return t;
}

// Parked (wheels still, no motor current) until the bus voltage exceeds
// volts or limitS passes; returns the time in seconds, or -1.
double parkedUntilAbove(World& w, double volts, double limitS) {
    const WheelArray still{};
    const auto limit = static_cast<core::TimeNs>(limitS * 1e9);
    while (w.time() < limit) {
        w.advance(w.time() + kStep, still, still);
        if (w.truth().busVoltageV > volts) {
            return static_cast<double>(w.time()) * 1e-9;
        }
    }
    return -1.0;
}

}  // namespace

TEST_GROUP(SimRecharge){};

// low_battery.toml: 2 % charge, an 8 A array. Below battery_low_v at start,
// above battery_clear_v parked after about 11 minutes (650 s) with no motor
// current; in lockstep the six enabled drives' no-load current slows it to
// 762 s (unit_test/system/lockstep/test_lockstep_fault_detection.cpp).
TEST(SimRecharge, TheLowBatteryScenarioRechargesPastTheClearVoltageParkedInAboutElevenMinutes) {
    const tables::FaultResponseTable limits = defaultFaultResponse();
    const double lowV = static_cast<double>(limits.battery_low_v);
    const double clearV = static_cast<double>(limits.battery_clear_v);
    const Scenario s = loadScenarioFile("sim_stub/scenarios/low_battery.toml");
    World w(s.worldConfig());
    CHECK(w.truth().busVoltageV < lowV);
    const double startSoc = w.truth().stateOfCharge;
    const double atS = parkedUntilAbove(w, clearV, 30.0 * 60.0);
    CHECK(atS > 0.0);
    CHECK(atS > 9.0 * 60.0);
    CHECK(atS < 13.0 * 60.0);
    CHECK(w.truth().busCurrentA < 0.0);  // charging
    CHECK(w.truth().stateOfCharge > startSoc + 0.05);
}

// The demo's 1 A array against the 25 W avionics on a 2 % pack: a net drain,
// never a recharge. Why the low-battery scenario needs a stronger array.
TEST(SimRecharge, TheDemosArrayCannotRechargeALowPack) {
    Scenario s = loadScenarioFile("sim_stub/scenarios/demo_mission.toml");
    DOUBLES_EQUAL(1.0, s.solar.peakCurrentA, 1e-12);
    s.battery.initialSoc = 0.02;
    World w(s.worldConfig());
    const double startSoc = w.truth().stateOfCharge;
    CHECK(parkedUntilAbove(w, static_cast<double>(defaultFaultResponse().battery_clear_v), 20.0 * 60.0) < 0.0);
    CHECK(w.truth().stateOfCharge < startSoc);
    CHECK(w.truth().busCurrentA > 0.0);
}

// A full pack takes no more charge: the regulator sheds the array's surplus.
TEST(SimRecharge, AFullPackStaysFullAtItsOpenCircuitVoltageWhateverTheArrayGives) {
    BatteryParams battery;
    battery.initialSoc = 0.999;
    SolarParams solar;
    solar.peakCurrentA = 20.0;
    Battery b(battery, solar);
    for (int i = 0; i < 6000; ++i) {
        b.step(0.01, 0.01 * (i + 1), 0.0);
    }
    DOUBLES_EQUAL(1.0, b.stateOfCharge(), 1e-12);
    DOUBLES_EQUAL(0.0, b.busCurrentA(), 1e-12);
    DOUBLES_EQUAL(openCircuitVoltage(1.0), b.voltageV(), 1e-12);
    DOUBLES_EQUAL(b.baseCurrentA(), b.solarCurrentA(), 1e-12);  // the array feeds the loads only
}

#include "sim_stub/devices/power_monitor_emulator.hpp"

#include "hal/canopen/le_codec.hpp"

namespace rse::sim {

PowerMonitorEmulator::PowerMonitorEmulator(hal::CanBus& bus, const World& world, const PowerMonitorParams& params,
                                           std::uint64_t seed, bool pollsBus)
    : DeviceEmulator(bus, kPowerNodeId, pollsBus), world_(world), params_(params), rng_(seed, RngStream::kPower) {}

void PowerMonitorEmulator::onBoot(core::TimeNs now, bool /*resetApplication*/) {
    schedule_.start(now + kPowerPeriodNs, kPowerPeriodNs);
}

void PowerMonitorEmulator::produce(core::TimeNs now) {
    const std::size_t due = schedule_.take(now, kDeviceMaxCatchUp, &mutableStats().samplesSkipped);
    for (std::size_t i = 0; i < due; ++i) {
        const TruthRecord& t = world_.truth();
        const double volts = t.busVoltageV + params_.voltageSigmaV * rng_.gaussian();
        const double amps = t.busCurrentA + params_.currentSigmaA * rng_.gaussian();
        hal::CanFrame f;
        f.id = kPowerCobId;
        f.dlc = 8;
        hal::le::putU16(&f.data[0], saturateU16(volts * 1e3));
        hal::le::putI16(&f.data[2], saturateI16(amps * 1e3));
        hal::le::putU16(&f.data[4], saturateU16(t.stateOfCharge * 1e4));
        hal::le::putU16(&f.data[6], saturateU16(t.solarCurrentA * 1e3));
        sendData(f);
    }
}

}  // namespace rse::sim

// Power monitor (node 0x21): 10 Hz on 0x6A1 (docs/icd.md §1.2).
//   bytes 0-1 bus voltage u16 [mV], 2-3 bus current i16 [mA, + = discharge],
//   4-5 state of charge u16 [0.01 %], 6-7 solar current u16 [mA].
// Values from the world's battery truth; voltage and current carry Gaussian
// noise (defaults sigma 5 mV and 10 mA), state of charge and solar current none.
// Each field saturates at its type's range (the bus current at +-32.767 A).
#pragma once

#include <cstdint>

#include "sim_stub/devices/device_emulator.hpp"
#include "sim_stub/world/random.hpp"
#include "sim_stub/world/world.hpp"

namespace rse::sim {

constexpr std::uint8_t kPowerNodeId = 0x21;
constexpr std::uint32_t kPowerCobId = 0x6A1;
constexpr core::TimeNs kPowerPeriodNs = 100 * core::kNsPerMs;

struct PowerMonitorParams {
    double voltageSigmaV = 0.005;
    double currentSigmaA = 0.010;
};

class PowerMonitorEmulator final : public DeviceEmulator {
public:
    PowerMonitorEmulator(hal::CanBus& bus, const World& world, const PowerMonitorParams& params,
                         std::uint64_t seed, bool pollsBus = true);

private:
    void onBoot(core::TimeNs now, bool resetApplication) override;
    void produce(core::TimeNs now) override;

    const World& world_;
    PowerMonitorParams params_;
    SimRng rng_;
    PeriodicSchedule schedule_;
};

}  // namespace rse::sim

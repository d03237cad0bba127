// Position-fix source (node 0x23, sun tracker / visual odometry): 1 Hz, two frames
// back to back with the same fix counter (docs/icd.md §1.2):
//   0x6A3: x i32 [mm], sigma u16 [mm], fix counter u16
//   0x6A4: y i32 [mm], heading i16 [1e-4 rad, +-pi], fix counter u16
// Fix = true pose + independent Gaussian noise: x and y with sigmaM (default
// 0.05 m), heading with headingSigmaRad (default 0.005 rad). The sigma field
// carries sigmaM (at least 1 mm: the flight side rejects 0).
#pragma once

#include <cstdint>

#include "sim_stub/devices/device_emulator.hpp"
#include "sim_stub/world/random.hpp"
#include "sim_stub/world/world.hpp"

namespace rse::sim {

constexpr std::uint8_t kPositionFixNodeId = 0x23;
constexpr std::uint32_t kFixXCobId = 0x6A3;
constexpr std::uint32_t kFixYCobId = 0x6A4;
constexpr core::TimeNs kFixPeriodNs = core::kNsPerSec;

struct PositionFixParams {
    double sigmaM = 0.05;
    double headingSigmaRad = 0.005;
};

class PositionFixEmulator final : public DeviceEmulator {
public:
    PositionFixEmulator(hal::CanBus& bus, const World& world, const PositionFixParams& params, std::uint64_t seed,
                        bool pollsBus = true);

    std::uint16_t fixCounter() const { return counter_; }  // of the next fix

private:
    void onBoot(core::TimeNs now, bool resetApplication) override;
    void produce(core::TimeNs now) override;

    const World& world_;
    PositionFixParams params_;
    SimRng rng_;
    PeriodicSchedule schedule_;
    std::uint16_t counter_ = 0;
};

}  // namespace rse::sim

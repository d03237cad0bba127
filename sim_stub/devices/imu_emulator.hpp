// IMU (node 0x20): yaw rate at 100 Hz on 0x6A0 (docs/icd.md §1.2).
//   bytes 0-3 yaw rate i32 [µrad/s], 4-5 sample counter u16, 6 status (bit 0 valid), 7 reserved 0.
// Measured rate = true yaw rate + bias + N(0, noiseSigma), one draw per sample
// from the scenario seed. Defaults: noise sigma 0.002 rad/s (about 0.11 deg/s per
// sample), bias 0. The fault hook stepBias adds a bias step (stays until
// another step; survives NMT resets and restarts, it is a physical fault).
#pragma once

#include <cstdint>

#include "sim_stub/devices/device_emulator.hpp"
#include "sim_stub/world/random.hpp"
#include "sim_stub/world/world.hpp"

namespace rse::sim {

constexpr std::uint8_t kImuNodeId = 0x20;
constexpr std::uint32_t kImuCobId = 0x6A0;
constexpr core::TimeNs kImuPeriodNs = 10 * core::kNsPerMs;

struct ImuParams {
    double noiseSigmaRadS = 0.002;
    double biasRadS = 0.0;
};

class ImuEmulator final : public DeviceEmulator {
public:
    ImuEmulator(hal::CanBus& bus, const World& world, const ImuParams& params, std::uint64_t seed,
                bool pollsBus = true);

    void stepBias(double deltaRadS) { bias_ += deltaRadS; }
    double biasRadS() const { return bias_; }
    std::uint16_t sampleCounter() const { return counter_; }  // of the next sample

private:
    void onBoot(core::TimeNs now, bool resetApplication) override;
    void produce(core::TimeNs now) override;

    const World& world_;
    ImuParams params_;
    SimRng rng_;
    double bias_;
    std::uint16_t counter_ = 0;
    PeriodicSchedule schedule_;
};

}  // namespace rse::sim

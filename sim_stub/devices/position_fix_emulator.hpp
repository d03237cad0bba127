// Position-fix source (node 0x23, sun tracker / visual odometry): 1 Hz, two frames
// back to back with the same fix counter (docs/icd.md §1.2):
//   0x6A3: x i32 [mm], sigma u16 [mm], fix counter u16
//   0x6A4: y i32 [mm], heading i16 [1e-4 rad, +-pi], fix counter u16
// Fix = true pose + independent Gaussian noise: x and y with sigmaM (default
// 0.05 m), heading with headingSigmaRad (default 0.005 rad). The sigma field
// carries sigmaM (at least 1 mm: the flight side rejects 0).
//
// Outliers (fault position_fix_outlier): injectOutlier(offset, bearing, count)
// displaces the next `count` fixes produced by offset metres towards bearing (map
// frame, counter-clockwise from +x) on top of the normal noise; the heading and
// the sigma field are unchanged. "Produced" means given a fix counter: a fix
// withheld by a dropout or NMT stopped still uses one up, a crashed device
// produces none (the outliers wait for its restart). A new injection replaces
// whatever is still pending.
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

    // False (and nothing changes) unless offsetM is finite and > 0, bearingRad is
    // finite and count >= 1.
    bool injectOutlier(double offsetM, double bearingRad, std::uint32_t count);
    std::uint32_t outliersPending() const { return outliersPending_; }
    std::uint32_t outliersProduced() const { return outliersProduced_; }  // since construction

private:
    void onBoot(core::TimeNs now, bool resetApplication) override;
    void produce(core::TimeNs now) override;

    const World& world_;
    PositionFixParams params_;
    SimRng rng_;
    PeriodicSchedule schedule_;
    std::uint16_t counter_ = 0;
    std::uint32_t outliersPending_ = 0;
    std::uint32_t outliersProduced_ = 0;
    double outlierDx_ = 0.0;
    double outlierDy_ = 0.0;
};

}  // namespace rse::sim

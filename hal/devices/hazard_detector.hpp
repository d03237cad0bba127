// Hazard-detector client (0x6A2): obstacles seen near the rover, in the rover
// frame, kept in a fixed table by obstacle id and forgotten when not reported
// for kHazardExpiry. A report with id 0 says "nothing in view" and clears the table.
#pragma once

#include "fsw/core/static_vector.hpp"
#include "hal/devices/device_frame_sink.hpp"

namespace rse::hal {

struct HazardSighting {
    std::uint8_t obstacleId = 0;
    double rangeM = 0.0;       // to the nearest point
    double bearingRad = 0.0;   // 0 ahead, + left
    double halfWidthM = 0.0;
    core::TimeNs time = 0;
};

constexpr std::size_t kMaxHazards = 16;
constexpr core::TimeNs kHazardExpiry = 1 * core::kNsPerSec;

class HazardDetector final : public DeviceFrameSink {
public:
    explicit HazardDetector(core::EventLog& events) : DeviceFrameSink(events, "hazard") {}
    // Drops sightings older than kHazardExpiry. Call once per cycle.
    void expire(core::TimeNs now);
    const core::StaticVector<HazardSighting, kMaxHazards>& sightings() const { return sightings_; }
    std::uint32_t tableFull() const { return tableFull_; }

private:
    bool decode(const CanFrame& frame, core::TimeNs now, const char** reason) override;
    core::StaticVector<HazardSighting, kMaxHazards> sightings_;
    std::uint32_t tableFull_ = 0;
};

}  // namespace rse::hal

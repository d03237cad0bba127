#include "hal/devices/hazard_detector.hpp"

#include "hal/canopen/le_codec.hpp"

namespace rse::hal {

bool HazardDetector::decode(const CanFrame& frame, core::TimeNs now, const char** reason) {
    const std::int16_t rangeCm = le::getI16(&frame.data[0]);
    const std::int16_t bearing = le::getI16(&frame.data[2]);
    const std::int16_t halfWidthCm = le::getI16(&frame.data[4]);
    const std::uint8_t id = frame.data[6];
    noteCounter(frame.data[7], 256);
    if (id == 0) {
        sightings_.clear();
        return true;
    }
    if (rangeCm < 0 || halfWidthCm < 0 || bearing > 3142 || bearing < -3142) {
        *reason = "negative range or width, or bearing beyond +-pi";
        return false;
    }
    HazardSighting s;
    s.obstacleId = id;
    s.rangeM = static_cast<double>(rangeCm) * 0.01;
    s.bearingRad = static_cast<double>(bearing) * 1e-3;
    s.halfWidthM = static_cast<double>(halfWidthCm) * 0.01;
    s.time = now;
    for (HazardSighting& existing : sightings_) {
        if (existing.obstacleId == id) {
            existing = s;
            return true;
        }
    }
    if (!core::isOk(sightings_.push_back(s))) {
        ++tableFull_;  // more obstacles in view than the table holds: the newest is dropped
    }
    return true;
}

void HazardDetector::expire(core::TimeNs now) {
    std::size_t i = 0;
    while (i < sightings_.size()) {  // bounded by kMaxHazards
        if (now - sightings_.at(i)->time > kHazardExpiry) {
            (void)sightings_.erase(i);
        } else {
            ++i;
        }
    }
}

}  // namespace rse::hal

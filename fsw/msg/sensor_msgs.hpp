// Sensors across the hal I/O boundary (docs/icd.md §1.2 for their sources).
#pragma once

#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

struct ImuMsg {
    static constexpr core::MsgId kMsgId = ids::kImu;
    std::int64_t timeNs;
    double yawRateRadS;
    std::uint8_t valid;
    std::uint8_t pad[7];
};

struct PowerMsg {
    static constexpr core::MsgId kMsgId = ids::kPower;
    std::int64_t timeNs;
    double busVoltageV;
    double busCurrentA;    // + = discharge
    double stateOfCharge;  // 0..1
    double solarCurrentA;
};

struct PositionFixMsg {
    static constexpr core::MsgId kMsgId = ids::kPositionFix;
    std::int64_t timeNs;
    double xM;
    double yM;
    double headingRad;
    double sigmaM;
};

constexpr std::size_t kMaxHazardsInMsg = 16;

struct HazardSightingTlm {
    double rangeM;
    double bearingRad;  // 0 ahead, + left, rover frame
    double halfWidthM;
    std::uint8_t obstacleId;
    std::uint8_t pad[7];
};

// Published every 100 ms whether the detector spoke or not (sightings expire
// after 1 s), so the sightings alone cannot show a silent detector:
// detectorFrames can (health judges staleness on it).
struct HazardMsg {
    static constexpr core::MsgId kMsgId = ids::kHazards;
    std::int64_t timeNs;
    std::uint8_t count;
    std::uint8_t pad[3];
    std::uint32_t detectorFrames;  // frames accepted from the detector since start (sightings and "clear" reports)
    HazardSightingTlm sightings[kMaxHazardsInMsg];
};

}  // namespace rse::msg

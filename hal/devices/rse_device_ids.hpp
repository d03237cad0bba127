// COB-IDs of the RSE (non-CANopen) devices' data frames, docs/icd.md §1.2.
// Their node ids (heartbeats) are not here: they come from the CAN_NODE_MAP table.
#pragma once

#include <cstdint>

namespace rse::hal::device_ids {

constexpr std::uint32_t kImuRates = 0x6A0;
constexpr std::uint32_t kPower = 0x6A1;
constexpr std::uint32_t kHazard = 0x6A2;
constexpr std::uint32_t kFixX = 0x6A3;
constexpr std::uint32_t kFixY = 0x6A4;

}  // namespace rse::hal::device_ids

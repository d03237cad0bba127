// COB-IDs of the RSE (non-CANopen) devices' data frames, docs/icd.md §1.2.
// The sensors' node ids (heartbeats) are not here: they come from the
// CAN_NODE_MAP table. The science instruments' node ids are fixed
// (hal/devices/instrument_protocol.hpp), like every COB-ID here.
#pragma once

#include <cstdint>

namespace rse::hal::device_ids {

constexpr std::uint32_t kImuRates = 0x6A0;
constexpr std::uint32_t kPower = 0x6A1;
constexpr std::uint32_t kHazard = 0x6A2;
constexpr std::uint32_t kFixX = 0x6A3;
constexpr std::uint32_t kFixY = 0x6A4;
// Science instruments (docs/icd.md §1.7): status from, commands to.
constexpr std::uint32_t kGrinderStatus = 0x6A5;
constexpr std::uint32_t kCameraStatus = 0x6A6;
constexpr std::uint32_t kGrinderCommand = 0x6B5;
constexpr std::uint32_t kCameraCommand = 0x6B6;

}  // namespace rse::hal::device_ids

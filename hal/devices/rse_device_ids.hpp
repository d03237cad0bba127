// Node ids and COB-IDs of the RSE (non-CANopen) devices, docs/icd.md §1.1-1.2.
#pragma once

#include <cstdint>

namespace rse::hal::device_ids {

constexpr std::uint8_t kImuNode = 0x20;
constexpr std::uint8_t kPowerNode = 0x21;
constexpr std::uint8_t kHazardNode = 0x22;
constexpr std::uint8_t kFixNode = 0x23;

constexpr std::uint32_t kImuRates = 0x6A0;
constexpr std::uint32_t kPower = 0x6A1;
constexpr std::uint32_t kHazard = 0x6A2;
constexpr std::uint32_t kFixX = 0x6A3;
constexpr std::uint32_t kFixY = 0x6A4;

}  // namespace rse::hal::device_ids

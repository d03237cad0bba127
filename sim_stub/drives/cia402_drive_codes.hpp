// The CANopen and CiA 402 codes the wheel drive emulator's parts share
// (cia402_drive_emulator.hpp; docs/icd.md §1.2-1.4). Internal to sim_stub/drives/.
#pragma once

#include <cstdint>

namespace rse::sim::drive_codes {

// COB-ID function codes (docs/icd.md §1.2).
constexpr std::uint32_t kCobNmt = 0x000;
constexpr std::uint32_t kCobSync = 0x080;
constexpr std::uint32_t kCobEmcy = 0x080;
constexpr std::uint32_t kCobTpdo1 = 0x180;
constexpr std::uint32_t kCobTpdo2 = 0x280;
constexpr std::uint32_t kCobRpdo1 = 0x200;
constexpr std::uint32_t kCobSdoRequest = 0x600;
constexpr std::uint32_t kCobHeartbeat = 0x700;

// 0x6060 modes of operation: profile velocity, the only one.
constexpr std::uint8_t kProfileVelocityMode = 3;

// v saturated to [lo, hi] as T (a report's integer field).
template <typename T>
T clampTo(long long v, long long lo, long long hi) {
    return static_cast<T>(v < lo ? lo : (v > hi ? hi : v));
}

}  // namespace rse::sim::drive_codes

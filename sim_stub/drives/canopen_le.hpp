// Little-endian packing for the simulator's CANopen payloads.
//
// Deliberately independent of hal/canopen/le_codec.hpp: the emulators and the
// flight master meet in lockstep tests, and a byte-order mistake shared by both
// sides would pass those tests unnoticed.
#pragma once

#include <cstdint>

namespace rse::sim::le {

inline std::uint16_t u16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>(static_cast<unsigned>(p[0]) | (static_cast<unsigned>(p[1]) << 8U));
}
inline std::uint32_t u32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8U) |
           (static_cast<std::uint32_t>(p[2]) << 16U) | (static_cast<std::uint32_t>(p[3]) << 24U);
}
inline std::int16_t i16(const std::uint8_t* p) { return static_cast<std::int16_t>(u16(p)); }
inline std::int32_t i32(const std::uint8_t* p) { return static_cast<std::int32_t>(u32(p)); }

inline void put16(std::uint8_t* p, std::uint16_t v) {
    p[0] = static_cast<std::uint8_t>(v & 0xFFU);
    p[1] = static_cast<std::uint8_t>((v >> 8U) & 0xFFU);
}
inline void put32(std::uint8_t* p, std::uint32_t v) {
    p[0] = static_cast<std::uint8_t>(v & 0xFFU);
    p[1] = static_cast<std::uint8_t>((v >> 8U) & 0xFFU);
    p[2] = static_cast<std::uint8_t>((v >> 16U) & 0xFFU);
    p[3] = static_cast<std::uint8_t>((v >> 24U) & 0xFFU);
}
inline void putI16(std::uint8_t* p, std::int16_t v) { put16(p, static_cast<std::uint16_t>(v)); }
inline void putI32(std::uint8_t* p, std::int32_t v) { put32(p, static_cast<std::uint32_t>(v)); }

}  // namespace rse::sim::le

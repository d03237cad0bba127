// Builds a complete command packet (docs/icd.md, "Ground link"): primary and
// secondary headers, security header, arguments, MAC, checksum. Flight never
// sends commands; this lives here so the ground tool, the tests and the fuzz
// seeds build packets with the very code that defines the layout the flight
// validator (command_validator.hpp) takes apart.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/command_auth.hpp"

namespace rse::cmdtlm {

struct CommandFields {
    std::uint16_t apid = 0;
    std::uint8_t functionCode = 0;
    std::uint16_t sequenceCount = 0;  // CCSDS sequence count (14 bits)
    std::uint16_t keyId = kNoKey;     // kNoKey: unauthenticated (lab setting only)
    std::uint32_t authSequence = 0;   // anti-replay sequence number
};

// key: the keyId's key, or nullptr for an unauthenticated packet (no MAC).
// Returns the packet length, or 0 when it does not fit capacity/kMaxCommandPacket
// or the MAC could not be computed.
std::size_t encodeCommandPacket(const CommandFields& fields, const std::uint8_t* args, std::size_t argLength,
                                const std::uint8_t* key, HmacSha256& hmac, std::uint8_t* out,
                                std::size_t capacity);

}  // namespace rse::cmdtlm

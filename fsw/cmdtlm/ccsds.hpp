// CCSDS Space Packets (CCSDS 133.0-B) as RSE uses them on the ground link.
// Byte layouts, the checksum rule and the time epoch: docs/icd.md, "Ground link".
//
//   primary header (6 bytes, big-endian):
//     bits 0-2 version (0) | 3 type (1 command, 0 telemetry) | 4 secondary header (1)
//     | 5-15 APID; bits 16-17 sequence flags (3: unsegmented) | 18-31 sequence count;
//     bytes 4-5 packet data length = total length - 7.
//   command:   + function code (1, bit 7 reserved 0) + checksum (1)
//              + security header: key id (2, 0 = none) + anti-replay sequence (4)
//              + arguments + MAC (16, when key id != 0)
//   telemetry: + time: seconds (4) + subseconds (2, 1/65536 s) of mission elapsed time
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"

namespace rse::cmdtlm {

constexpr std::size_t kPrimaryHeaderSize = 6;
constexpr std::size_t kCommandSecondaryHeaderSize = 2;
constexpr std::size_t kSecurityHeaderSize = 6;
constexpr std::size_t kCommandHeaderSize = kPrimaryHeaderSize + kCommandSecondaryHeaderSize + kSecurityHeaderSize;
constexpr std::size_t kMacSize = 16;  // HMAC-SHA-256 truncated to its first 128 bits
constexpr std::size_t kTelemetrySecondaryHeaderSize = 6;
constexpr std::size_t kTelemetryHeaderSize = kPrimaryHeaderSize + kTelemetrySecondaryHeaderSize;
constexpr std::size_t kMaxCommandPacket = 256;    // larger command packets are refused
constexpr std::size_t kMaxTelemetryPacket = 512;  // largest packet flight sends
constexpr std::size_t kChecksumOffset = 7;
constexpr std::uint16_t kMaxApid = 0x7FF;
constexpr std::uint16_t kSequenceCountMask = 0x3FFF;
constexpr std::uint8_t kUnsegmented = 3;

enum class PacketType : std::uint8_t { kTelemetry = 0, kCommand = 1 };

struct PrimaryHeader {
    std::uint8_t version = 0;
    PacketType type = PacketType::kTelemetry;
    bool secondaryHeader = true;
    std::uint16_t apid = 0;
    std::uint8_t sequenceFlags = kUnsegmented;
    std::uint16_t sequenceCount = 0;
    std::uint16_t dataLength = 0;  // total packet length - 7
};

void encodePrimaryHeader(const PrimaryHeader& header, std::uint8_t out[kPrimaryHeaderSize]);
PrimaryHeader decodePrimaryHeader(const std::uint8_t in[kPrimaryHeaderSize]);

// The cFS command checksum: the checksum byte is chosen so that the XOR of 0xFF
// and every byte of the packet, checksum included, is zero. commandChecksum()
// computes it with the checksum byte taken as zero; checksumValid() applies the
// rule to a received packet.
std::uint8_t commandChecksum(const std::uint8_t* packet, std::size_t length);
bool checksumValid(const std::uint8_t* packet, std::size_t length);

// Mission elapsed time: the executive clock (CLOCK_MONOTONIC in real time, the
// virtual clock in lockstep). HK.utc_at_met_zero correlates it with UTC.
struct MetTime {
    std::uint32_t seconds = 0;
    std::uint16_t subseconds = 0;  // units of 1/65536 s
};
MetTime toMet(core::TimeNs time);
double metSeconds(const MetTime& time);

// Writes a telemetry packet: header, then payload bytes. Returns the packet
// length, or 0 if it does not fit in capacity or the APID is out of range.
std::size_t buildTelemetryPacket(std::uint16_t apid, std::uint16_t sequenceCount, core::TimeNs time,
                                 const std::uint8_t* payload, std::size_t payloadLength, std::uint8_t* out,
                                 std::size_t capacity);

}  // namespace rse::cmdtlm

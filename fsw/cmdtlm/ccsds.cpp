#include "fsw/cmdtlm/ccsds.hpp"

#include <cstring>

namespace rse::cmdtlm {

void encodePrimaryHeader(const PrimaryHeader& header, std::uint8_t out[kPrimaryHeaderSize]) {
    const auto word0 = static_cast<std::uint16_t>(((header.version & 0x7U) << 13) |
                                                  (static_cast<unsigned>(header.type) << 12) |
                                                  ((header.secondaryHeader ? 1U : 0U) << 11) |
                                                  (header.apid & kMaxApid));
    const auto word1 = static_cast<std::uint16_t>(((header.sequenceFlags & 0x3U) << 14) |
                                                  (header.sequenceCount & kSequenceCountMask));
    out[0] = static_cast<std::uint8_t>(word0 >> 8);
    out[1] = static_cast<std::uint8_t>(word0);
    out[2] = static_cast<std::uint8_t>(word1 >> 8);
    out[3] = static_cast<std::uint8_t>(word1);
    out[4] = static_cast<std::uint8_t>(header.dataLength >> 8);
    out[5] = static_cast<std::uint8_t>(header.dataLength);
}

PrimaryHeader decodePrimaryHeader(const std::uint8_t in[kPrimaryHeaderSize]) {
    const auto word0 = static_cast<std::uint16_t>((in[0] << 8) | in[1]);
    const auto word1 = static_cast<std::uint16_t>((in[2] << 8) | in[3]);
    PrimaryHeader h;
    h.version = static_cast<std::uint8_t>(word0 >> 13);
    h.type = ((word0 >> 12) & 1U) != 0 ? PacketType::kCommand : PacketType::kTelemetry;
    h.secondaryHeader = ((word0 >> 11) & 1U) != 0;
    h.apid = static_cast<std::uint16_t>(word0 & kMaxApid);
    h.sequenceFlags = static_cast<std::uint8_t>(word1 >> 14);
    h.sequenceCount = static_cast<std::uint16_t>(word1 & kSequenceCountMask);
    h.dataLength = static_cast<std::uint16_t>((in[4] << 8) | in[5]);
    return h;
}

std::uint8_t commandChecksum(const std::uint8_t* packet, std::size_t length) {
    std::uint8_t sum = 0xFF;
    for (std::size_t i = 0; i < length; ++i) {
        if (i != kChecksumOffset) {
            sum = static_cast<std::uint8_t>(sum ^ packet[i]);
        }
    }
    return sum;
}

bool checksumValid(const std::uint8_t* packet, std::size_t length) {
    std::uint8_t sum = 0xFF;
    for (std::size_t i = 0; i < length; ++i) {
        sum = static_cast<std::uint8_t>(sum ^ packet[i]);
    }
    return length > kChecksumOffset && sum == 0;
}

MetTime toMet(core::TimeNs time) {
    MetTime met;
    if (time <= 0) {
        return met;
    }
    met.seconds = static_cast<std::uint32_t>(time / core::kNsPerSec);
    const core::TimeNs fraction = time % core::kNsPerSec;
    met.subseconds = static_cast<std::uint16_t>((fraction * 65536) / core::kNsPerSec);
    return met;
}

double metSeconds(const MetTime& time) {
    return static_cast<double>(time.seconds) + static_cast<double>(time.subseconds) / 65536.0;
}

std::size_t buildTelemetryPacket(std::uint16_t apid, std::uint16_t sequenceCount, core::TimeNs time,
                                 const std::uint8_t* payload, std::size_t payloadLength, std::uint8_t* out,
                                 std::size_t capacity) {
    const std::size_t total = kTelemetryHeaderSize + payloadLength;
    if (apid > kMaxApid || total > capacity || total > kMaxTelemetryPacket) {
        return 0;
    }
    PrimaryHeader h;
    h.type = PacketType::kTelemetry;
    h.apid = apid;
    h.sequenceCount = static_cast<std::uint16_t>(sequenceCount & kSequenceCountMask);
    h.dataLength = static_cast<std::uint16_t>(total - 7);
    encodePrimaryHeader(h, out);
    const MetTime met = toMet(time);
    out[6] = static_cast<std::uint8_t>(met.seconds >> 24);
    out[7] = static_cast<std::uint8_t>(met.seconds >> 16);
    out[8] = static_cast<std::uint8_t>(met.seconds >> 8);
    out[9] = static_cast<std::uint8_t>(met.seconds);
    out[10] = static_cast<std::uint8_t>(met.subseconds >> 8);
    out[11] = static_cast<std::uint8_t>(met.subseconds);
    if (payloadLength > 0) {
        std::memcpy(out + kTelemetryHeaderSize, payload, payloadLength);
    }
    return total;
}

}  // namespace rse::cmdtlm

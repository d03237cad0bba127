#include "fsw/cmdtlm/command_packet.hpp"

#include "fsw/core/byte_codec.hpp"

namespace rse::cmdtlm {

std::size_t encodeCommandPacket(const CommandFields& fields, const std::uint8_t* args, std::size_t argLength,
                                const std::uint8_t* key, HmacSha256& hmac, std::uint8_t* out,
                                std::size_t capacity) {
    const std::size_t total = kCommandHeaderSize + argLength + (key != nullptr ? kMacSize : 0);
    if (total > capacity || total > kMaxCommandPacket || fields.apid > kMaxApid) {
        return 0;
    }
    PrimaryHeader h;
    h.type = PacketType::kCommand;
    h.apid = fields.apid;
    h.sequenceCount = static_cast<std::uint16_t>(fields.sequenceCount & kSequenceCountMask);
    h.dataLength = static_cast<std::uint16_t>(total - 7);
    encodePrimaryHeader(h, out);
    core::BeWriter w(out + kPrimaryHeaderSize, capacity - kPrimaryHeaderSize);
    w.u8(static_cast<std::uint8_t>(fields.functionCode & 0x7F));
    w.u8(0);  // checksum, filled last
    w.u16(key != nullptr ? fields.keyId : kNoKey);
    w.u32(fields.authSequence);
    w.bytes(args, argLength);
    if (!w.ok()) {
        return 0;
    }
    std::size_t length = kPrimaryHeaderSize + w.size();
    if (key != nullptr) {
        if (!core::isOk(hmac.packetMac(key, out, length, out + length))) {
            return 0;
        }
        length += kMacSize;
    }
    out[kChecksumOffset] = commandChecksum(out, length);
    return length;
}

}  // namespace rse::cmdtlm

#include "fsw/cmdtlm/command_validator.hpp"

#include <cmath>

#include "fsw/core/byte_codec.hpp"

namespace rse::cmdtlm {

const char* toString(CommandReject reason) {
    switch (reason) {
        case CommandReject::kAccepted: return "accepted";
        case CommandReject::kQueueOverflow: return "queue_overflow";
        case CommandReject::kBadLength: return "bad_length";
        case CommandReject::kBadHeader: return "bad_header";
        case CommandReject::kBadChecksum: return "bad_checksum";
        case CommandReject::kUnknownApid: return "unknown_apid";
        case CommandReject::kUnknownFunction: return "unknown_function_code";
        case CommandReject::kMacMissing: return "mac_missing";
        case CommandReject::kUnknownKey: return "unknown_key";
        case CommandReject::kBadMac: return "bad_mac";
        case CommandReject::kReplayedSequence: return "replayed_sequence";
        case CommandReject::kStaleSequence: return "stale_sequence";
        case CommandReject::kArgumentOutOfRange: return "argument_out_of_range";
        case CommandReject::kWrongMode: return "wrong_mode";
        case CommandReject::kExecutionFailed: return "execution_failed";
        case CommandReject::kCount: break;
    }
    return "?";
}

namespace {

CommandVerdict& fail(CommandVerdict& v, CommandReject reason, std::int16_t detail = -1) {
    v.reason = reason;
    v.detail = detail;
    return v;
}

// Checks each argument against the descriptor; returns the index of the first
// one out of range or not finite, or -1.
std::int16_t firstBadArgument(const CommandDesc& command, const std::uint8_t* args, std::size_t length) {
    core::BeReader r(args, length);
    for (std::size_t i = 0; i < command.argCount; ++i) {
        const ArgDesc& arg = command.args[i];
        if (arg.type == FieldType::blob) {
            continue;  // its length was checked with the packet length
        }
        const double value = readAsDouble(r, arg.type);
        if (!r.ok() || !std::isfinite(value) || value < arg.min || value > arg.max) {
            return static_cast<std::int16_t>(i);
        }
    }
    return -1;
}

}  // namespace

CommandVerdict CommandValidator::check(const std::uint8_t* packet, std::size_t length, Mode mode) {
    CommandVerdict v;
    // 1-2: length and header.
    if (packet == nullptr || length < kCommandHeaderSize || length > kMaxCommandPacket) {
        return fail(v, CommandReject::kBadLength);
    }
    v.header = decodePrimaryHeader(packet);
    v.functionCode = static_cast<std::uint8_t>(packet[6] & 0x7F);
    if (static_cast<std::size_t>(v.header.dataLength) + 7 != length) {
        return fail(v, CommandReject::kBadLength);
    }
    if (v.header.version != 0 || v.header.type != PacketType::kCommand || !v.header.secondaryHeader ||
        v.header.sequenceFlags != kUnsegmented || (packet[6] & 0x80) != 0) {
        return fail(v, CommandReject::kBadHeader);
    }
    // 3: checksum.
    if (!checksumValid(packet, length)) {
        return fail(v, CommandReject::kBadChecksum);
    }
    // 4: what command.
    if (!isCommandApid(v.header.apid)) {
        return fail(v, CommandReject::kUnknownApid);
    }
    v.command = findCommand(v.header.apid, v.functionCode);
    if (v.command == nullptr) {
        return fail(v, CommandReject::kUnknownFunction);
    }
    // 5-7: authentication.
    core::BeReader security(packet + kPrimaryHeaderSize + kCommandSecondaryHeaderSize, kSecurityHeaderSize);
    v.keyId = security.u16();
    v.authSequence = security.u32();
    std::size_t end = length;
    if (v.keyId == kNoKey) {
        if (authRequired_) {
            return fail(v, CommandReject::kMacMissing);
        }
    } else {
        const std::uint8_t* key = keys_.find(v.keyId);
        if (key == nullptr) {
            return fail(v, CommandReject::kUnknownKey);
        }
        if (length < kCommandHeaderSize + kMacSize) {
            return fail(v, CommandReject::kBadLength);
        }
        end = length - kMacSize;
        std::uint8_t expected[kMacSize];
        if (!core::isOk(hmac_.packetMac(key, packet, end, expected)) || !macEqual(expected, packet + end)) {
            return fail(v, CommandReject::kBadMac);
        }
        switch (keys_.check(v.keyId, v.authSequence)) {
            case KeyStore::Freshness::kReplayed: return fail(v, CommandReject::kReplayedSequence);
            case KeyStore::Freshness::kStale: return fail(v, CommandReject::kStaleSequence);
            case KeyStore::Freshness::kFresh: break;
        }
        keys_.commit(v.keyId, v.authSequence);
    }
    // 8-9: arguments.
    v.args = packet + kCommandHeaderSize;
    v.argLength = end - kCommandHeaderSize;
    const std::size_t fixed = v.command->fixedArgBytes;
    const bool lengthOk = v.command->maxBlobBytes == 0
                              ? v.argLength == fixed
                              : v.argLength > fixed && v.argLength <= fixed + v.command->maxBlobBytes;
    if (!lengthOk) {
        return fail(v, CommandReject::kBadLength, static_cast<std::int16_t>(fixed));
    }
    const std::int16_t bad = firstBadArgument(*v.command, v.args, v.argLength);
    if (bad >= 0) {
        return fail(v, CommandReject::kArgumentOutOfRange, bad);
    }
    // 10: mode.
    if (!modeAllows(v.command->modes, mode)) {
        return fail(v, CommandReject::kWrongMode, static_cast<std::int16_t>(mode));
    }
    return v;
}

CommandVerdict CommandValidator::screen(const std::uint8_t* packet, std::size_t length) const {
    CommandVerdict v;
    if (packet == nullptr || length < kCommandHeaderSize || length > kMaxCommandPacket) {
        return fail(v, CommandReject::kBadLength);
    }
    v.header = decodePrimaryHeader(packet);
    v.functionCode = static_cast<std::uint8_t>(packet[6] & 0x7F);
    if (static_cast<std::size_t>(v.header.dataLength) + 7 != length) {
        return fail(v, CommandReject::kBadLength);
    }
    if (v.header.version != 0 || v.header.type != PacketType::kCommand || !v.header.secondaryHeader ||
        v.header.sequenceFlags != kUnsegmented || (packet[6] & 0x80) != 0) {
        return fail(v, CommandReject::kBadHeader);
    }
    if (!checksumValid(packet, length)) {
        return fail(v, CommandReject::kBadChecksum);
    }
    if (!isCommandApid(v.header.apid)) {
        return fail(v, CommandReject::kUnknownApid);
    }
    v.command = findCommand(v.header.apid, v.functionCode);
    if (v.command == nullptr) {
        return fail(v, CommandReject::kUnknownFunction);
    }
    core::BeReader security(packet + kPrimaryHeaderSize + kCommandSecondaryHeaderSize, kSecurityHeaderSize);
    v.keyId = security.u16();
    v.authSequence = security.u32();
    if (v.keyId == kNoKey) {
        if (authRequired_) {
            return fail(v, CommandReject::kMacMissing);
        }
    } else {
        if (keys_.find(v.keyId) == nullptr) {
            return fail(v, CommandReject::kUnknownKey);
        }
        if (length < kCommandHeaderSize + kMacSize) {
            return fail(v, CommandReject::kBadLength);
        }
    }
    return v;
}

}  // namespace rse::cmdtlm

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
        case CommandReject::kSequenceUnsynchronised: return "sequence_unsynchronised";
        case CommandReject::kSequenceExhausted: return "sequence_exhausted";
        case CommandReject::kSequenceStoreFailed: return "sequence_store_failed";
        case CommandReject::kCount: break;
    }
    return "?";
}

CommandReject linkReason(CommandReject reason) {
    return reason == CommandReject::kUnknownKey ? CommandReject::kBadMac : reason;
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

bool CommandValidator::resyncFails(CommandVerdict& v, const std::uint8_t* packet, std::size_t end) {
    const std::size_t argLength = end - kCommandHeaderSize;
    if (argLength != v.command->fixedArgBytes) {
        fail(v, CommandReject::kBadLength, static_cast<std::int16_t>(v.command->fixedArgBytes));
        return true;
    }
    if (v.authSequence > kMaxUsableSequence) {
        fail(v, CommandReject::kSequenceExhausted);
        return true;
    }
    core::BeReader r(packet + kCommandHeaderSize, argLength);
    const std::uint64_t high = r.u32();
    const std::uint64_t nonce = (high << 32) | r.u32();
    if (!replay_.challengeReady()) {
        fail(v, CommandReject::kSequenceUnsynchronised, static_cast<std::int16_t>(Unsynced::kNoChallenge));
        return true;
    }
    if (nonce != replay_.challenge()) {
        fail(v, CommandReject::kSequenceUnsynchronised, static_cast<std::int16_t>(Unsynced::kChallengeMismatch));
        return true;
    }
    // The nonce proves freshness; the new floor is the command's own number,
    // never below the floor in force for a key that is still synchronised.
    std::uint32_t newFloor = v.authSequence;
    if (replay_.unsynced(v.keyId) == Unsynced::kSynced) {
        const std::uint32_t current = keys_.lastSequence(v.keyId);
        newFloor = current > newFloor ? current : newFloor;
    }
    const core::Status stored = replay_.resync(v.keyId, newFloor);
    if (!core::isOk(stored)) {
        fail(v, CommandReject::kSequenceStoreFailed);
        v.deferred = stored == core::Status::kBusy;
        return true;
    }
    keys_.setFloor(v.keyId, newFloor);
    replay_.nextChallenge();
    return false;
}

CommandVerdict CommandValidator::authenticate(const std::uint8_t* packet, std::size_t length) {
    // 1-5: length, header, checksum, command, key id: the screen's checks.
    CommandVerdict v = screen(packet, length);
    if (v.reason != CommandReject::kAccepted || v.keyId == kNoKey) {
        return v;
    }
    // 7: the MAC.
    const std::uint8_t* key = keys_.find(v.keyId);
    if (key == nullptr) {
        return fail(v, CommandReject::kUnknownKey);  // the screen refuses it first; kept for safety
    }
    const std::size_t end = length - kMacSize;
    std::uint8_t expected[kMacSize];
    if (!core::isOk(hmac_.packetMac(key, packet, end, expected)) || !macEqual(expected, packet + end)) {
        return fail(v, CommandReject::kBadMac);
    }
    return v;
}

CommandVerdict CommandValidator::check(const std::uint8_t* packet, std::size_t length, Mode mode) {
    // 1-7: the screen's checks and the MAC.
    CommandVerdict v = authenticate(packet, length);
    if (v.reason != CommandReject::kAccepted) {
        return v;
    }
    // 8: freshness.
    std::size_t end = length;
    if (v.keyId != kNoKey) {
        end = length - kMacSize;
        if (v.command->code == CommandCode::AUTH_RESYNC) {
            if (resyncFails(v, packet, end)) {
                return v;
            }
        } else {
            const Unsynced why = replay_.unsynced(v.keyId);
            if (why != Unsynced::kSynced) {
                return fail(v, CommandReject::kSequenceUnsynchronised, static_cast<std::int16_t>(why));
            }
            switch (keys_.check(v.keyId, v.authSequence)) {
                case KeyStore::Freshness::kReplayed: return fail(v, CommandReject::kReplayedSequence);
                case KeyStore::Freshness::kStale: return fail(v, CommandReject::kStaleSequence);
                case KeyStore::Freshness::kFresh: break;
            }
            if (v.authSequence > kMaxUsableSequence) {
                return fail(v, CommandReject::kSequenceExhausted);
            }
            // Persist before recording: the stored reservation always covers
            // every number accepted, so a restart cannot reopen one.
            const core::Status stored = replay_.reserve(v.keyId, v.authSequence);
            if (!core::isOk(stored)) {
                fail(v, CommandReject::kSequenceStoreFailed);
                v.deferred = stored == core::Status::kBusy;
                return v;
            }
            keys_.commit(v.keyId, v.authSequence);
        }
    }
    // 9-10: arguments.
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
    // 11: mode.
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
        // check()'s order: room for the MAC first, whatever the key id.
        if (length < kCommandHeaderSize + kMacSize) {
            return fail(v, CommandReject::kBadLength);
        }
        // Rejected here without a MAC; the link hears bad_mac for it as for a
        // wrong MAC (linkReason), in the same task run, from the same rate
        // limit under a flood (docs/icd.md).
        if (keys_.find(v.keyId) == nullptr) {
            return fail(v, CommandReject::kUnknownKey);
        }
    }
    return v;
}

}  // namespace rse::cmdtlm

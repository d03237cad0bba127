// A command's verdict: the reason the command service refused it, or
// kAccepted with what an application needs to carry it out (the command's
// descriptor and its argument bytes). The checks that reach it are
// command_validator.hpp's; this header is the part the applications that own
// commands see (app_commands.hpp), without the checks' crypto and storage.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::cmdtlm {

constexpr std::uint16_t kNoKey = 0;  // key id of an unauthenticated command

// Numeric values are part of the telemetry format (CMD_ACK.reason, HK counters).
enum class CommandReject : std::uint8_t {
    kAccepted = 0,
    kQueueOverflow = 1,
    kBadLength = 2,
    kBadHeader = 3,
    kBadChecksum = 4,
    kUnknownApid = 5,
    kUnknownFunction = 6,
    kMacMissing = 7,
    kUnknownKey = 8,
    kBadMac = 9,
    kReplayedSequence = 10,
    kStaleSequence = 11,
    kArgumentOutOfRange = 12,
    kWrongMode = 13,
    kExecutionFailed = 14,
    kSequenceUnsynchronised = 15,
    kSequenceExhausted = 16,
    kSequenceStoreFailed = 17,
    kCount
};
constexpr std::size_t kRejectReasonCount = static_cast<std::size_t>(CommandReject::kCount);
static_assert(kRejectReasonCount <= 20, "HK.cmd_rejected_by_reason holds 20 counters");
const char* toString(CommandReject reason);  // snake_case names, as in docs/dictionary.md

// What the link is told (CMD_ACK.reason, the rejection event): an unknown key id
// reads as bad_mac, so a sender without a key cannot learn which key ids exist.
// HK.cmd_rejected_by_reason still counts the two apart (docs/icd.md §5.4).
CommandReject linkReason(CommandReject reason);

struct CommandVerdict {
    CommandReject reason = CommandReject::kAccepted;
    std::int16_t detail = -1;               // argument index for kArgumentOutOfRange
    PrimaryHeader header{};                 // valid from check 2 on
    std::uint8_t functionCode = 0;
    std::uint16_t keyId = kNoKey;
    std::uint32_t authSequence = 0;
    const CommandDesc* command = nullptr;   // set from check 4 on
    const std::uint8_t* args = nullptr;     // argument bytes inside the packet
    std::size_t argLength = 0;
    // Not yet decided: the anti-replay reservation that covers this number is
    // being written. The packet stays queued and is checked again next frame.
    // reason is kSequenceStoreFailed meanwhile, so a caller that ignores this
    // flag refuses the command rather than act on it.
    bool deferred = false;
};

}  // namespace rse::cmdtlm

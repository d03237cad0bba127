// Every check a command packet passes before it may act, in a fixed order, and
// the first one it fails. Bounded, no events (the dispatcher reports), so the
// fuzzer can drive it directly. It does no I/O itself: the anti-replay
// reservation is posted to a writer (replay().attach()), and a command waits
// for it (CommandVerdict::deferred).
//
// Order (docs/icd.md, "Command checks"):
//   1 length: at least the command headers, at most kMaxCommandPacket, equal to
//     the primary header's length field            -> kBadLength
//   2 header: version 0, command type, secondary header present, unsegmented,
//     function-code reserved bit clear              -> kBadHeader
//   3 checksum (cFS rule)                           -> kBadChecksum
//   4 APID, then function code, in the dictionary   -> kUnknownApid, kUnknownFunction
//   5 key id: 0 is refused when authentication is required -> kMacMissing;
//     otherwise there must be room for the MAC      -> kBadLength
//   6 the key must be loaded                        -> kUnknownKey (the link is told
//     kBadMac, in the same frame as a MAC check's answer: docs/icd.md)
//   Steps 1-6 are screen(); 1-7 are authenticate(), which check() runs first.
//   7 MAC over the packet                           -> kBadMac
//   8 anti-replay sequence (fsw/cmdtlm/anti_replay_state.hpp):
//     key refused until AUTH_RESYNC (store missing or corrupt, key not in it)
//                                                   -> kSequenceUnsynchronised (detail: why)
//     repeated / too old                            -> kReplayedSequence, kStaleSequence
//     above kMaxUsableSequence                      -> kSequenceExhausted
//     above the key's persisted reservation: a new reservation is written first
//     (deferred until durable); when that write fails -> kSequenceStoreFailed
//     (only now is the sequence number recorded: a forged packet cannot move the
//     window; a command refused by a later check has used its number up)
//     AUTH_RESYNC is fresh by its challenge instead (anti_replay_state.hpp):
//     wrong nonce -> kSequenceUnsynchronised (detail 4)
//   9 argument bytes: exactly the dictionary's size (a blob within its maximum) -> kBadLength
//  10 each argument within [min, max] and finite    -> kArgumentOutOfRange (detail: argument index)
//  11 the current mode allows the command           -> kWrongMode
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/anti_replay_state.hpp"
#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_verdict.hpp"
#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::cmdtlm {

class CommandValidator {
public:
    CommandValidator(KeyStore& keys, HmacSha256& hmac) : keys_(keys), hmac_(hmac) {}

    // The lab setting: unauthenticated commands (key id 0) accepted. Default off.
    void setAuthRequired(bool required) { authRequired_ = required; }
    bool authRequired() const { return authRequired_; }

    CommandVerdict check(const std::uint8_t* packet, std::size_t length, Mode mode);

    // The persisted side of the anti-replay window (volatile until a store is attached).
    AntiReplayState& replay() { return replay_; }
    const AntiReplayState& replay() const { return replay_; }
    // The cheap checks alone, in check()'s order: 1 length, 2 header, 3 checksum,
    // 4 APID and function code, 5 key id (missing, unknown, no room for the MAC);
    // no MAC, no sequence, nothing recorded. A packet it rejects is rejected by
    // check() with the same reason; one it passes (kAccepted) still needs check().
    // Command ingest runs it on every packet as it arrives, so a flood of garbage
    // costs no MAC and takes no queue slot (docs/icd.md, "Floods").
    CommandVerdict screen(const std::uint8_t* packet, std::size_t length) const;
    // screen() and then 7, the MAC (0.8-1.2 us for a small packet on the
    // development VM): still nothing recorded. Command ingest runs it on every
    // packet, so only authentic packets take a queue slot and a flood of packets
    // with a known key id and a wrong MAC cannot crowd valid commands out of the
    // queue; check() runs it again (a packet is checked whole where it acts).
    CommandVerdict authenticate(const std::uint8_t* packet, std::size_t length);

private:
    // Check 7 for AUTH_RESYNC: fresh by its challenge; on success the key's floor moves.
    bool resyncFails(CommandVerdict& v, const std::uint8_t* packet, std::size_t end);

    KeyStore& keys_;
    HmacSha256& hmac_;
    AntiReplayState replay_;
    bool authRequired_ = true;
};

}  // namespace rse::cmdtlm

// One ground session on a link: sends commands (authenticated with the session's
// key and a fresh anti-replay number from the sequence store) and waits for the
// matching CMD_ACK; decodes every telemetry packet it receives meanwhile and
// hands each to an observer (watch printing, the script runner's waits).
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/command_encoder.hpp"
#include "ground/ground_link.hpp"
#include "ground/sequence_store.hpp"
#include "ground/telemetry_decoder.hpp"

namespace rse::ground {

constexpr double kDefaultAckTimeout = 2.0;  // seconds

enum class AckOutcome { kAccepted, kRejected, kNoAck, kNotWaited };

struct AckResult {
    AckOutcome outcome = AckOutcome::kNoAck;
    unsigned reason = 0;   // CMD_ACK.reason (0 accepted)
    int detail = -1;       // CMD_ACK.detail
    std::uint32_t authSequence = 0;
    std::vector<std::uint8_t> packet;   // what was sent
    std::optional<DecodedPacket> ack;   // the CMD_ACK, when one came
    std::string summary;                // "GOTO (0x181/0, auth seq 7) accepted" or why no ack
};

class GroundSession {
public:
    using Observer = std::function<void(const DecodedPacket&)>;

    GroundSession(GroundLink& link, SequenceStore& sequences, PacketAuth auth,
                  double ackTimeout = kDefaultAckTimeout);

    // Builds, sends and (when wait) waits up to the ack timeout for the CMD_ACK
    // of this command (same APID, function code and auth sequence). forcedSequence
    // replaces the store's next number (and is noted in the store). Throws
    // LinkError, StateError, CommandError.
    AckResult sendCommand(const cmdtlm::CommandDesc& command, const std::vector<std::uint8_t>& args,
                          std::optional<std::uint32_t> forcedSequence = std::nullopt, bool wait = true);

    // The next packet within timeout, decoded (malformed ones too); nullopt on
    // timeout. The observer sees it first.
    std::optional<DecodedPacket> receive(double timeoutSeconds);

    void setObserver(Observer observer) { observer_ = std::move(observer); }
    GroundLink& link() { return link_; }
    const PacketAuth& auth() const { return auth_; }
    double ackTimeout() const { return ackTimeout_; }

    // Packets received so far, and how many of them came before the last
    // command was sent: a packet numbered above receivedAtLastSend() (counting
    // from 1, the observer sees receivedCount() already including it) arrived
    // after that command went out.
    std::uint64_t receivedCount() const { return received_; }
    std::uint64_t receivedAtLastSend() const { return receivedAtLastSend_; }

    // "no acknowledgement within 2 s: is rse-fsw running and is the link up?"
    std::string noAckText() const;

private:
    GroundLink& link_;
    SequenceStore& sequences_;
    PacketAuth auth_;
    double ackTimeout_;
    Observer observer_;
    std::uint64_t received_ = 0;
    std::uint64_t receivedAtLastSend_ = 0;
};

// One step of a transfer (table load, plan load): sends the command, waits
// for its acknowledgement and reports "WHAT: <ack summary>" (on out when
// accepted, on err otherwise). Returns 0 accepted, 1 no acknowledgement, 3
// rejected (the CLI's exit codes).
int sendReported(GroundSession& session, cmdtlm::CommandCode code, const std::vector<std::uint8_t>& args,
                 const std::string& what, std::ostream& out, std::ostream& err);

// True when `packet` is the CMD_ACK of that command and sequence.
bool isAckFor(const DecodedPacket& packet, const cmdtlm::CommandDesc& command, std::uint32_t authSequence);

// Monotonic seconds, for deadlines.
double monotonicSeconds();

}  // namespace rse::ground

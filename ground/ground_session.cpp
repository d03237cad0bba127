#include "ground/ground_session.hpp"

#include <chrono>
#include <ostream>

#include "ground/text_format.hpp"

namespace rse::ground {

double monotonicSeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool isAckFor(const DecodedPacket& packet, const cmdtlm::CommandDesc& command, std::uint32_t authSequence) {
    return packet.ok && packet.apid == cmdtlm::CMD_ACK_Tlm::kApid &&
           packet.value("apid").value_or(-1) == command.apid &&
           packet.value("function_code").value_or(-1) == command.functionCode &&
           packet.value("auth_sequence").value_or(-1) == static_cast<double>(authSequence);
}

GroundSession::GroundSession(GroundLink& link, SequenceStore& sequences, PacketAuth auth, double ackTimeout)
    : link_(link), sequences_(sequences), auth_(std::move(auth)), ackTimeout_(ackTimeout) {}

std::string GroundSession::noAckText() const {
    return "no acknowledgement within " + formatNumber(ackTimeout_) +
           " s: is rse-fsw running and is the link up? (" + link_.describe() + ")";
}

std::optional<DecodedPacket> GroundSession::receive(double timeoutSeconds) {
    std::optional<std::vector<std::uint8_t>> bytes = link_.receive(timeoutSeconds);
    if (!bytes) {
        return std::nullopt;
    }
    DecodedPacket packet = decodeTelemetry(*bytes);
    ++received_;
    if (observer_) {
        observer_(packet);
    }
    return packet;
}

AckResult GroundSession::sendCommand(const cmdtlm::CommandDesc& command, const std::vector<std::uint8_t>& args,
                                     std::optional<std::uint32_t> forcedSequence, bool wait) {
    AckResult result;
    if (forcedSequence) {
        result.authSequence = *forcedSequence;
        sequences_.noteUsed(auth_.keyId, *forcedSequence);
    } else {
        result.authSequence = sequences_.next(auth_.keyId);  // persisted before it is sent
    }
    result.packet = buildCommandPacket(command, args, auth_, result.authSequence);
    // Whatever is waiting already came before the command and cannot be its
    // ack (a stale ack of an earlier run with the same number must not match):
    // take it in now, then mark where the command's own answers begin.
    for (int i = 0; i < 10000 && receive(0.0); ++i) {
    }
    link_.send(result.packet);
    receivedAtLastSend_ = received_;
    if (!wait) {
        result.outcome = AckOutcome::kNotWaited;
        result.summary = std::string(command.name) + " sent (auth seq " + std::to_string(result.authSequence) +
                         "), not waiting for the acknowledgement";
        return result;
    }
    const double deadline = monotonicSeconds() + ackTimeout_;
    for (;;) {
        const double left = deadline - monotonicSeconds();
        if (left <= 0.0) {
            break;
        }
        std::optional<DecodedPacket> packet = receive(left);
        if (!packet) {
            continue;
        }
        if (isAckFor(*packet, command, result.authSequence)) {
            result.reason = static_cast<unsigned>(packet->value("reason").value_or(0));
            result.detail = static_cast<int>(packet->value("detail").value_or(-1));
            result.outcome = result.reason == 0 ? AckOutcome::kAccepted : AckOutcome::kRejected;
            result.summary = describeAck(*packet);
            result.ack = std::move(packet);
            return result;
        }
    }
    result.outcome = AckOutcome::kNoAck;
    result.summary = std::string(command.name) + ": " + noAckText();
    return result;
}

int sendReported(GroundSession& session, cmdtlm::CommandCode code, const std::vector<std::uint8_t>& args,
                 const std::string& what, std::ostream& out, std::ostream& err) {
    const AckResult result = session.sendCommand(cmdtlm::describe(code), args);
    if (result.outcome == AckOutcome::kNoAck) {
        err << what << ": " << session.noAckText() << "\n";
        return 1;
    }
    if (result.outcome == AckOutcome::kRejected) {
        err << what << ": " << result.summary << "\n";
        return 3;
    }
    out << what << ": " << result.summary << "\n";
    return 0;
}

}  // namespace rse::ground

// Telemetry output: encodes a dictionary telemetry struct, wraps it in a CCSDS
// packet (per-APID sequence count, MET time) and hands it to every ground link.
// Single-threaded like everything in the executive: any task may send.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::cmdtlm {

constexpr std::size_t kMaxLinks = 3;  // UDP, CAN ISO-TP, and one spare (in-memory in tests)

class TelemetryOutput {
public:
    TelemetryOutput(const core::Clock& clock, core::EventLog& events) : clock_(clock), events_(events) {}

    core::Status addLink(hal::PacketLink* link);
    std::size_t linkCount() const { return linkCount_; }
    hal::PacketLink* link(std::size_t index) const { return index < linkCount_ ? links_[index] : nullptr; }

    template <typename T>
    void send(const T& telemetry) {
        core::BeWriter w(payload_, sizeof payload_);
        encodeTelemetry(w, telemetry);
        sendPayload(T::kApid, payload_, w.ok() ? w.size() : kMaxTelemetryPacket + 1);
    }
    void sendPayload(std::uint16_t apid, const std::uint8_t* payload, std::size_t length);

    std::uint32_t sent() const { return sent_; }        // packets accepted by a link (counted per link)
    std::uint32_t dropped() const { return dropped_; }  // packets a link refused
    void resetCounters();

private:
    const core::Clock& clock_;
    core::EventLog& events_;
    hal::PacketLink* links_[kMaxLinks] = {};
    std::size_t linkCount_ = 0;
    std::uint16_t sequence_[kMaxApid + 1] = {};
    std::uint8_t payload_[kMaxTelemetryPacket] = {};
    std::uint8_t packet_[kMaxTelemetryPacket] = {};
    std::uint32_t sent_ = 0;
    std::uint32_t dropped_ = 0;
    std::uint32_t tooLarge_ = 0;
};

}  // namespace rse::cmdtlm

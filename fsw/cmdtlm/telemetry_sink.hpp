// Where an application sends its telemetry packets: a dictionary telemetry
// struct in, encoded (big-endian, dictionary.hpp) and handed on as one
// packet's payload. TelemetryOutput implements it (CCSDS header, sequence
// count, every ground link); packers and command handlers see only this, so an
// application never reaches a link, and a unit test records what it sent.
// Single-threaded like everything in the executive.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"

namespace rse::cmdtlm {

class TelemetrySink {
public:
    TelemetrySink(const TelemetrySink&) = delete;
    TelemetrySink& operator=(const TelemetrySink&) = delete;

    template <typename T>
    void send(const T& telemetry) {
        core::BeWriter w(payload_, sizeof payload_);
        encodeTelemetry(w, telemetry);
        if (w.ok()) {
            sendPayload(T::kApid, payload_, w.size());
        } else {
            reportTooLarge(T::kApid, sizeof telemetry);
        }
    }
    // One packet of APID apid with this payload (already encoded).
    virtual void sendPayload(std::uint16_t apid, const std::uint8_t* payload, std::size_t length) = 0;

protected:
    TelemetrySink() = default;
    ~TelemetrySink() = default;
    // A payload that does not fit a packet (a dictionary error): counted, evented.
    virtual void reportTooLarge(std::uint16_t apid, std::size_t length) = 0;

private:
    std::uint8_t payload_[kMaxTelemetryPacket] = {};  // the encoding, kept off the senders' stacks
};

}  // namespace rse::cmdtlm

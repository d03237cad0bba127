#include "fsw/cmdtlm/telemetry_output.hpp"

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

core::Status TelemetryOutput::addLink(hal::PacketLink* link) {
    if (link == nullptr) {
        return core::Status::kInvalidArgument;
    }
    if (linkCount_ >= kMaxLinks) {
        return core::Status::kNoCapacity;
    }
    links_[linkCount_++] = link;
    return core::Status::kOk;
}

void TelemetryOutput::sendPayload(std::uint16_t apid, const std::uint8_t* payload, std::size_t length) {
    const std::size_t size = length <= kMaxTelemetryPacket
                                 ? buildTelemetryPacket(apid, sequence_[apid & kMaxApid], clock_.now(), payload,
                                                        length, packet_, sizeof packet_)
                                 : 0;
    if (size == 0) {
        ++tooLarge_;
        if (core::isReportableOccurrence(tooLarge_)) {
            events_.report(events::kTelemetryTooLarge, core::Severity::kError,
                           "tlm: APID 0x%03x payload of %zu bytes does not fit a packet (%u times)",
                           static_cast<unsigned>(apid), length, static_cast<unsigned>(tooLarge_));
        }
        return;
    }
    sequence_[apid & kMaxApid] = static_cast<std::uint16_t>((sequence_[apid & kMaxApid] + 1) & kSequenceCountMask);
    for (std::size_t i = 0; i < linkCount_; ++i) {
        if (!links_[i]->downlinkActive()) {
            continue;
        }
        const core::Status status = links_[i]->send(packet_, size);
        if (core::isOk(status)) {
            ++sent_;
            continue;
        }
        ++dropped_;
        if (core::isReportableOccurrence(dropped_)) {
            events_.report(events::kTelemetryDropped, core::Severity::kWarning,
                           "tlm: link %s refused APID 0x%03x (%s), %u dropped", links_[i]->name(),
                           static_cast<unsigned>(apid), core::toString(status), static_cast<unsigned>(dropped_));
        }
    }
}

void TelemetryOutput::resetCounters() {
    sent_ = 0;
    dropped_ = 0;
    tooLarge_ = 0;
}

}  // namespace rse::cmdtlm

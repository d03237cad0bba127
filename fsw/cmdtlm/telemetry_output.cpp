#include "fsw/cmdtlm/telemetry_output.hpp"

#include <algorithm>

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

void TelemetryOutput::sendPayload(std::uint16_t apid, const std::uint8_t* payload, std::size_t length) {
    const std::size_t size =
        buildTelemetryPacket(apid, sequence_[apid & kMaxApid], clock_.now(), payload, length, packet_, sizeof packet_);
    if (size == 0) {
        reportTooLarge(apid, length);
        return;
    }
    sequence_[apid & kMaxApid] = static_cast<std::uint16_t>((sequence_[apid & kMaxApid] + 1) & kSequenceCountMask);
    const hal::TxPriority priority = telemetryPriority(apid);
    std::uint32_t& droppedHere = droppedBy_[static_cast<std::size_t>(priority)];
    for (std::size_t i = 0; i < links_.size(); ++i) {
        hal::PacketLink* link = links_.at(i);
        if (!link->downlinkActive()) {
            continue;
        }
        const core::Status status = link->sendWithPriority(packet_, size, priority);
        if (core::isOk(status)) {
            ++sent_;
            continue;
        }
        ++dropped_;
        ++droppedHere;
        if (core::isReportableOccurrence(droppedHere)) {
            events_.report(events::kTelemetryDropped, core::Severity::kWarning,
                           "tlm: link %s refused APID 0x%03x (%s): %u %s packets dropped", link->name(),
                           static_cast<unsigned>(apid), core::toString(status), static_cast<unsigned>(droppedHere),
                           hal::toString(priority));
        }
    }
}

std::size_t TelemetryOutput::room(hal::TxPriority priority) const {
    std::size_t least = hal::kTxRoomUnlimited;
    for (std::size_t i = 0; i < links_.size(); ++i) {
        const hal::PacketLink* link = links_.at(i);
        if (link->downlinkActive()) {
            least = std::min(least, link->txRoom(priority));
        }
    }
    return least;
}

void TelemetryOutput::reportTooLarge(std::uint16_t apid, std::size_t length) {
    ++tooLarge_;
    if (core::isReportableOccurrence(tooLarge_)) {
        events_.report(events::kTelemetryTooLarge, core::Severity::kError,
                       "tlm: APID 0x%03x payload of %zu bytes does not fit a packet (%u times)",
                       static_cast<unsigned>(apid), length, static_cast<unsigned>(tooLarge_));
    }
}

void TelemetryOutput::fillHousekeeping(HK_Tlm& hk) const {
    hk.tlm_sent = sent_;
    hk.tlm_dropped = dropped_;
}

void TelemetryOutput::resetCounters() {
    sent_ = 0;
    dropped_ = 0;
    for (std::uint32_t& d : droppedBy_) {
        d = 0;
    }
    tooLarge_ = 0;
}

}  // namespace rse::cmdtlm

#include "ground/event_data_pairing.hpp"

#include "fsw/cmdtlm/event_data.hpp"

namespace rse::ground {

bool readEventData(const DecodedPacket& p, EventDataPacket* out) {
    if (!p.ok || p.apid != cmdtlm::EVENT_DATA_Tlm::kApid) {
        return false;
    }
    out->sequence = static_cast<std::uint32_t>(p.value("event_sequence").value_or(0.0));
    out->id = static_cast<std::uint16_t>(p.value("event_id").value_or(0.0));
    out->withheld = static_cast<std::uint32_t>(p.value("data_withheld").value_or(0.0));
    const double count = p.value("value_count").value_or(0.0);
    out->data = core::EventData{};
    out->data.count = static_cast<std::uint8_t>(count < static_cast<double>(core::kEventDataValues)
                                                    ? count
                                                    : static_cast<double>(core::kEventDataValues));
    for (std::size_t i = 0; i < out->data.count; ++i) {
        out->data.values[i] = p.value("value", i).value_or(0.0);
    }
    return true;
}

void EventDataPairing::onEvent(std::uint32_t sequence, std::uint16_t id, std::size_t handle) {
    if (cmdtlm::findEventData(id) == nullptr) {
        return;  // an event without numbers
    }
    ++expected_;
    awaiting_.push_back(Awaiting{sequence, id, handle});
    if (awaiting_.size() > kPairingWindow) {
        awaiting_.pop_front();  // its numbers are long overdue: missing
    }
}

std::optional<std::size_t> EventDataPairing::onData(const EventDataPacket& data) {
    withheld_ = data.withheld;
    // The latest first: after a restart an old sequence may still wait.
    for (auto it = awaiting_.rbegin(); it != awaiting_.rend(); ++it) {
        if (it->sequence == data.sequence && it->id == data.id) {
            const std::size_t handle = it->handle;
            awaiting_.erase(std::next(it).base());
            ++paired_;
            return handle;
        }
    }
    ++stray_;
    return std::nullopt;
}

}  // namespace rse::ground

#include "fsw/core/software_bus.hpp"

#include <cstdio>

#include "fsw/core/core_events.hpp"

namespace rse::core {

Status SoftwareBus::rejectConfig(const char* what, Status status) {
    ++stats_.configRejected;
    events_.report(events::kBusConfigRejected, Severity::kError, "bus: %s rejected (%s)", what,
                   toString(status));
    return status;
}

Status SoftwareBus::createPipe(const char* name, std::uint16_t depth, PipeId* out) {
    if (name == nullptr || out == nullptr || depth == 0) {
        return rejectConfig("createPipe", Status::kInvalidArgument);
    }
    if (pipeCount_ == kBusMaxPipes || slotsUsed_ + depth > kBusTotalQueueSlots) {
        return rejectConfig("createPipe", Status::kNoCapacity);
    }
    Pipe& pipe = pipes_[pipeCount_];
    std::snprintf(pipe.name, sizeof pipe.name, "%s", name);
    pipe.firstSlot = static_cast<std::uint16_t>(slotsUsed_);
    pipe.head = 0;
    pipe.count = 0;
    pipe.stats = PipeStats{};
    pipe.stats.depth = depth;
    slotsUsed_ += depth;
    *out = static_cast<PipeId>(pipeCount_);
    ++pipeCount_;
    return Status::kOk;
}

SoftwareBus::Route* SoftwareBus::findRoute(MsgId id) {
    for (std::size_t i = 0; i < routeCount_; ++i) {
        if (routes_[i].id == id) {
            return &routes_[i];
        }
    }
    return nullptr;
}

Status SoftwareBus::subscribe(PipeId pipe, MsgId id) {
    if (pipe >= pipeCount_) {
        return rejectConfig("subscribe", Status::kNotFound);
    }
    Route* route = findRoute(id);
    if (route == nullptr) {
        if (routeCount_ == kBusMaxRoutes) {
            return rejectConfig("subscribe", Status::kNoCapacity);
        }
        route = &routes_[routeCount_++];
        *route = Route{};
        route->id = id;
    }
    const std::uint32_t bit = 1U << pipe;
    if ((route->pipeMask & bit) != 0) {
        return rejectConfig("subscribe", Status::kAlreadyExists);
    }
    route->pipeMask |= bit;
    return Status::kOk;
}

void SoftwareBus::enqueue(PipeId pipeId, const MessageHeader& header, const void* payload) {
    Pipe& pipe = pipes_[pipeId];
    if (pipe.count == pipe.stats.depth) {
        ++pipe.stats.dropped;
        ++stats_.dropped;
        if (isReportableOccurrence(pipe.stats.dropped)) {
            events_.report(events::kBusQueueOverflow, Severity::kWarning,
                           "bus: pipe %s full (depth %u), msg 0x%04X dropped, %u drops so far",
                           pipe.name, static_cast<unsigned>(pipe.stats.depth),
                           static_cast<unsigned>(header.id),
                           static_cast<unsigned>(pipe.stats.dropped));
        }
        return;
    }
    const std::size_t slot =
        pipe.firstSlot + static_cast<std::size_t>((pipe.head + pipe.count) % pipe.stats.depth);
    slots_[slot].header = header;
    std::memcpy(slots_[slot].payload, payload, header.length);
    ++pipe.count;
    ++pipe.stats.delivered;
    ++stats_.delivered;
    if (pipe.count > pipe.stats.highWater) {
        pipe.stats.highWater = pipe.count;
    }
}

Status SoftwareBus::publish(MsgId id, const void* payload, std::size_t length) {
    if (length > kBusMaxPayload) {
        ++stats_.rejectedTooLarge;
        if (isReportableOccurrence(stats_.rejectedTooLarge)) {
            events_.report(events::kBusMessageTooLarge, Severity::kError,
                           "bus: msg 0x%04X of %zu bytes exceeds %zu, rejected",
                           static_cast<unsigned>(id), length, kBusMaxPayload);
        }
        return Status::kTooLarge;
    }
    if (payload == nullptr && length != 0) {
        ++stats_.rejectedInvalid;
        if (isReportableOccurrence(stats_.rejectedInvalid)) {
            events_.report(events::kBusPublishInvalid, Severity::kError,
                           "bus: msg 0x%04X published with no payload but length %zu, rejected",
                           static_cast<unsigned>(id), length);
        }
        return Status::kInvalidArgument;
    }
    ++stats_.published;
    Route* route = findRoute(id);
    if (route == nullptr || route->pipeMask == 0) {
        ++stats_.noSubscribers;
        return Status::kOk;
    }
    MessageHeader header;
    header.id = id;
    header.length = static_cast<std::uint16_t>(length);
    header.sequence = route->sequence++;
    header.time = clock_.now();
    for (std::size_t p = 0; p < pipeCount_; ++p) {
        if ((route->pipeMask & (1U << p)) != 0) {
            enqueue(static_cast<PipeId>(p), header, payload);
        }
    }
    return Status::kOk;
}

Status SoftwareBus::receive(PipeId pipeId, Message* out) {
    if (out == nullptr) {
        return Status::kInvalidArgument;
    }
    if (pipeId >= pipeCount_) {
        return Status::kNotFound;
    }
    Pipe& pipe = pipes_[pipeId];
    if (pipe.count == 0) {
        return Status::kEmpty;
    }
    const Message& slot = slots_[pipe.firstSlot + pipe.head];
    out->header = slot.header;
    std::memcpy(out->payload, slot.payload, slot.header.length);
    pipe.head = static_cast<std::uint16_t>((pipe.head + 1) % pipe.stats.depth);
    --pipe.count;
    ++pipe.stats.received;
    return Status::kOk;
}

const PipeStats* SoftwareBus::pipeStats(PipeId pipe) const {
    return pipe < pipeCount_ ? &pipes_[pipe].stats : nullptr;
}

const char* SoftwareBus::pipeName(PipeId pipe) const {
    return pipe < pipeCount_ ? pipes_[pipe].name : "";
}

void SoftwareBus::resetCounters() {
    stats_ = BusStats{};
    for (std::size_t p = 0; p < pipeCount_; ++p) {
        PipeStats& s = pipes_[p].stats;
        s.delivered = 0;
        s.received = 0;
        s.dropped = 0;
        s.highWater = pipes_[p].count;
    }
}

}  // namespace rse::core

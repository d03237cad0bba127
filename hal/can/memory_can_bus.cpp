#include "hal/can/memory_can_bus.hpp"

namespace rse::hal {

using core::Status;

Status MemoryCanEndpoint::send(const CanFrame& frame) {
    if (!isValidFrame(frame)) {
        ++stats_.txInvalid;
        return Status::kInvalidArgument;
    }
    if (hub_ == nullptr || state_ == CanBusState::kBusOff || state_ == CanBusState::kDown) {
        ++stats_.txUnavailable;
        return Status::kUnavailable;
    }
    ++stats_.txFrames;
    hub_->transmit(this, frame);
    return Status::kOk;
}

Status MemoryCanEndpoint::receive(CanFrame* out) {
    if (out == nullptr) {
        return Status::kInvalidArgument;
    }
    if (hub_ == nullptr) {
        return Status::kUnavailable;
    }
    hub_->releaseDueFrames();
    if (!core::isOk(rx_.pop(out))) {
        return Status::kEmpty;
    }
    ++stats_.rxFrames;
    return Status::kOk;
}

Status MemoryCanEndpoint::setFilters(const CanFilter* filters, std::size_t count) {
    if (count > kCanMaxFilters) {
        return Status::kNoCapacity;
    }
    if (filters == nullptr && count != 0) {
        return Status::kInvalidArgument;
    }
    filters_.clear();
    for (std::size_t i = 0; i < count; ++i) {
        (void)filters_.push_back(filters[i]);  // cannot fail: count checked above
    }
    return Status::kOk;
}

bool MemoryCanEndpoint::accepts(const CanFrame& frame) const {
    if (filters_.empty()) {
        return true;
    }
    for (const CanFilter& f : filters_) {
        if (passesFilter(f, frame)) {
            return true;
        }
    }
    return false;
}

void MemoryCanEndpoint::deliver(const CanFrame& frame) {
    if (state_ == CanBusState::kBusOff || state_ == CanBusState::kDown) {
        return;  // a bus-off controller takes no part in the bus
    }
    if (!accepts(frame)) {
        ++stats_.rxFiltered;
        return;
    }
    if (!core::isOk(rx_.push(frame))) {
        ++stats_.rxOverruns;
    }
}

MemoryCanEndpoint* MemoryCanBus::attach(const char* name) {
    if (endpointCount_ == kMemoryBusMaxEndpoints) {
        return nullptr;
    }
    MemoryCanEndpoint& e = endpoints_[endpointCount_++];
    e.hub_ = this;
    e.name_ = name != nullptr ? name : "";
    e.state_ = CanBusState::kErrorActive;
    return &e;
}

Status MemoryCanBus::addFault(const CanFaultRule& rule) { return faults_.push_back(rule); }

void MemoryCanBus::setBusOff(MemoryCanEndpoint* endpoint, bool busOff) {
    if (endpoint == nullptr || endpoint->hub_ != this) {
        return;
    }
    if (busOff && endpoint->state_ != CanBusState::kBusOff) {
        ++endpoint->stats_.busOffCount;
        ++endpoint->stats_.errorFrames;
    }
    endpoint->state_ = busOff ? CanBusState::kBusOff : CanBusState::kErrorActive;
}

CanFaultRule* MemoryCanBus::matchFault(const CanFrame& frame) {
    for (std::size_t i = 0; i < faults_.size(); ++i) {
        CanFaultRule* rule = faults_.at(i);
        if ((frame.id & rule->mask) == (rule->id & rule->mask)) {
            return rule;
        }
    }
    return nullptr;
}

void MemoryCanBus::transmit(const MemoryCanEndpoint* sender, const CanFrame& frame) {
    releaseDueFrames();  // frames held earlier go first
    CanFrame wire = frame;
    CanFaultRule* rule = matchFault(wire);
    if (rule != nullptr) {
        const CanFaultRule applied = *rule;  // the rule may be erased just below
        if (rule->count > 0 && --rule->count == 0) {
            // Spent: remove it (order of the remaining rules is kept).
            (void)faults_.erase(static_cast<std::size_t>(rule - faults_.begin()));
        }
        switch (applied.kind) {
            case CanFaultKind::kDrop:
                ++stats_.faultDropped;
                return;
            case CanFaultKind::kCorrupt:
                if (wire.dlc > 0) {
                    wire.data[applied.corruptByte % wire.dlc] ^= applied.corruptXor;
                }
                ++stats_.faultCorrupted;
                break;
            case CanFaultKind::kDelay: {
                HeldFrame held{wire, clock_.now() + applied.delay, sender};
                if (core::isOk(held_.push_back(held))) {
                    ++stats_.faultDelayed;
                } else {
                    ++stats_.delayOverflow;
                }
                return;
            }
        }
    }
    broadcast(sender, wire);
}

void MemoryCanBus::broadcast(const MemoryCanEndpoint* sender, const CanFrame& frame) {
    ++stats_.framesCarried;
    CanFrame stamped = frame;
    stamped.timestamp = clock_.now();
    for (std::size_t i = 0; i < endpointCount_; ++i) {
        if (&endpoints_[i] != sender) {
            endpoints_[i].deliver(stamped);
        }
    }
}

void MemoryCanBus::releaseDueFrames() {
    const core::TimeNs now = clock_.now();
    std::size_t i = 0;
    while (i < held_.size()) {  // bounded by kMemoryBusMaxDelayed
        const HeldFrame* held = held_.at(i);
        if (held->releaseAt <= now) {
            const HeldFrame due = *held;
            (void)held_.erase(i);
            broadcast(due.sender, due.frame);
        } else {
            ++i;
        }
    }
}

}  // namespace rse::hal

// The rover's ground links. Every link carries commands in and telemetry out,
// so command ingest and telemetry output read this one list, filled at start-up.
#pragma once

#include <cstddef>

#include "fsw/core/static_vector.hpp"
#include "fsw/core/status.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::cmdtlm {

constexpr std::size_t kMaxLinks = 3;  // UDP, CAN ISO-TP, and one spare (in-memory in tests)

class GroundLinks {
public:
    // kInvalidArgument for nullptr, kNoCapacity beyond kMaxLinks.
    core::Status add(hal::PacketLink* link) {
        if (link == nullptr) {
            return core::Status::kInvalidArgument;
        }
        return core::isOk(links_.push_back(link)) ? core::Status::kOk : core::Status::kNoCapacity;
    }
    std::size_t size() const { return links_.size(); }
    hal::PacketLink* at(std::size_t index) const {
        hal::PacketLink* const* slot = links_.at(index);
        return slot == nullptr ? nullptr : *slot;
    }

private:
    core::StaticVector<hal::PacketLink*, kMaxLinks> links_;
};

}  // namespace rse::cmdtlm

// The rover's ground links. Every link carries commands in and telemetry out,
// so command ingest and telemetry output read this one list, filled at start-up.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/static_vector.hpp"
#include "fsw/core/status.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::cmdtlm {

constexpr std::size_t kMaxLinks = 3;  // UDP, CAN ISO-TP, and one spare (in-memory in tests)

class GroundLinks {
public:
    // Who calls the link's service() once a minor frame: the command task, for
    // every link but those whose transport runs in another task's frame (the
    // CAN ISO-TP link, serviced by the CAN I/O task with the bus it shares). A
    // link serviced by nobody leaves work undone (the UDP link's ICMP reports
    // would wait in its receive buffer); one serviced twice would advance its
    // transport twice a frame.
    enum class Service : std::uint8_t { kByCommandTask, kByOwner };

    // kInvalidArgument for nullptr, kNoCapacity beyond kMaxLinks.
    core::Status add(hal::PacketLink* link, Service service = Service::kByCommandTask) {
        if (link == nullptr) {
            return core::Status::kInvalidArgument;
        }
        return core::isOk(links_.push_back(Entry{link, service})) ? core::Status::kOk : core::Status::kNoCapacity;
    }
    std::size_t size() const { return links_.size(); }
    hal::PacketLink* at(std::size_t index) const {
        const Entry* slot = links_.at(index);
        return slot == nullptr ? nullptr : slot->link;
    }
    // The command task's once-a-frame call.
    void serviceCommandTaskLinks() const {
        for (std::size_t i = 0; i < links_.size(); ++i) {
            const Entry* e = links_.at(i);
            if (e->service == Service::kByCommandTask) {
                e->link->service();
            }
        }
    }

private:
    struct Entry {
        hal::PacketLink* link;
        Service service;
    };
    core::StaticVector<Entry, kMaxLinks> links_;
};

}  // namespace rse::cmdtlm

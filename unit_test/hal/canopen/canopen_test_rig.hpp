// A flight endpoint and a "peer" endpoint on one in-memory bus, with helpers to
// send hand-built frames from the peer and collect what the flight side sent.
#pragma once

#include <cstdint>
#include <initializer_list>

#include "fsw/core/event_log.hpp"
#include "fsw/core/static_vector.hpp"
#include "hal/can/memory_can_bus.hpp"

namespace rse::test {

struct CanRig {
    core::VirtualClock clock;
    core::EventLog events{clock};
    hal::MemoryCanBus wire{clock};
    hal::MemoryCanEndpoint* flight = wire.attach("flight");
    hal::MemoryCanEndpoint* peer = wire.attach("peer");

    static hal::CanFrame make(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
        hal::CanFrame f;
        f.id = id;
        for (std::uint8_t b : bytes) {
            if (f.dlc < 8) {
                f.data[f.dlc++] = b;
            }
        }
        return f;
    }
    void peerSends(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) { (void)peer->send(make(id, bytes)); }

    // Every frame the flight side sent since the last call.
    core::StaticVector<hal::CanFrame, 256> sent() {
        core::StaticVector<hal::CanFrame, 256> out;
        hal::CanFrame f;
        while (core::isOk(peer->receive(&f))) {
            (void)out.push_back(f);
        }
        return out;
    }
    // Next frame the flight side must receive (feeds protocol objects by hand).
    bool flightReceives(hal::CanFrame* f) { return core::isOk(flight->receive(f)); }
};

}  // namespace rse::test

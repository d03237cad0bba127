// Watches one CanBus once per cycle and turns its state changes and counter
// increases into events, so every backend (SocketCAN, in-memory) is reported the
// same way and drivers stay free of event policy. Repeated trouble is evented on
// its 1st, 2nd, 4th ... cycle with further losses; the counters themselves are exact.
#pragma once

#include "fsw/core/event_log.hpp"
#include "hal/can/can_bus.hpp"

namespace rse::hal {

class CanLinkMonitor {
public:
    CanLinkMonitor(const CanBus& bus, core::EventLog& events, const char* linkName)
        : bus_(bus), events_(events), name_(linkName) {}

    void check();

    std::uint32_t overrunEpisodes() const { return overrunEpisodes_; }
    std::uint32_t txRefusedEpisodes() const { return txRefusedEpisodes_; }

private:
    const CanBus& bus_;
    core::EventLog& events_;
    const char* name_;
    bool first_ = true;
    CanBusState lastState_ = CanBusState::kDown;
    CanBusStats last_;
    std::uint32_t overrunEpisodes_ = 0;
    std::uint32_t txRefusedEpisodes_ = 0;
    std::uint32_t txInvalidEpisodes_ = 0;
};

}  // namespace rse::hal

// What the deliberative layer publishes goes through here: a message the bus
// refuses is counted and evented (918, the 1st, 2nd, 4th ... time) naming
// what was not published, so every part that publishes (legs, plan paths, the
// safe request, PLAN status) shares one count (DeliberativeCounters::publishFailures).
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/core/status.hpp"

namespace rse::deliberative {

class Publisher {
public:
    Publisher(core::SoftwareBus& bus, core::EventLog& events) : bus_(bus), events_(events) {}

    // what: the event's name for the message ("leg", "plan status", ...).
    template <typename M>
    void publish(const M& message, const char* what) {
        published(bus_.publish(message), what);
    }
    // The bus's answer to a publish: a refusal is counted and evented.
    void published(core::Status status, const char* what);

    std::uint32_t failures() const { return failures_; }

private:
    core::SoftwareBus& bus_;
    core::EventLog& events_;
    std::uint32_t failures_ = 0;
};

}  // namespace rse::deliberative

// Test helpers: how many events with one id are waiting in a log, and the
// numbers (event data) of the last of them (each drains the log).
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::test {

inline unsigned drainEventsWithId(core::EventLog& log, core::EventId id) {
    unsigned n = 0;
    core::Event e;
    while (core::isOk(log.pop(&e))) {
        n += (e.id == id) ? 1U : 0U;
    }
    return n;
}

// The numbers of the last event with this id, by name (Layout: a
// cmdtlm::event_data struct); false when none came or it carried none of that layout.
template <typename Layout>
bool lastEventData(core::EventLog& log, core::EventId id, Layout* out) {
    core::EventData last{};
    bool seen = false;
    core::Event e;
    while (core::isOk(log.pop(&e))) {
        if (e.id == id) {
            last = e.data;
            seen = true;
        }
    }
    return seen && out->unpack(id, last);
}

}  // namespace rse::test

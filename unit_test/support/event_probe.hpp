// Test helper: how many events with one id are waiting in a log (drains it).
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

}  // namespace rse::test

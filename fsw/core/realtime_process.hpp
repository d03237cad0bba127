// Puts the calling process in a real-time posture where the OS allows it:
// memory locked (no page faults mid-frame) and SCHED_FIFO priority. Each step
// that is refused (no privilege, no RT scheduler) is evented, not fatal: the
// executive still runs, with more jitter, and housekeeping shows it.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::core {

struct RealtimePosture {
    bool memoryLocked = false;
    bool fifoScheduling = false;
    int priority = 0;
};

RealtimePosture enterRealtimePosture(EventLog& events, int fifoPriority);

}  // namespace rse::core

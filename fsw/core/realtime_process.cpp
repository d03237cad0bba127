#include "fsw/core/realtime_process.hpp"

#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

#include "fsw/core/core_events.hpp"

namespace rse::core {

RealtimePosture enterRealtimePosture(EventLog& events, int fifoPriority) {
    RealtimePosture posture;
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
        posture.memoryLocked = true;
    } else {
        events.report(events::kRealtimeDegraded, Severity::kWarning,
                      "rt: mlockall refused (%s); page faults may add jitter", std::strerror(errno));
    }
    sched_param param{};
    param.sched_priority = fifoPriority;
    if (sched_setscheduler(0, SCHED_FIFO, &param) == 0) {
        posture.fifoScheduling = true;
        posture.priority = fifoPriority;
    } else {
        events.report(events::kRealtimeDegraded, Severity::kWarning,
                      "rt: SCHED_FIFO %d refused (%s); running time-shared", fifoPriority,
                      std::strerror(errno));
    }
    return posture;
}

}  // namespace rse::core

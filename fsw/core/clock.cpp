// clock.hpp's clocks that read the operating system's.
#include "fsw/core/clock.hpp"

#include <cerrno>
#include <ctime>

namespace rse::core {

namespace {

timespec toTimespec(TimeNs t) {
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(t / kNsPerSec);
    ts.tv_nsec = static_cast<long>(t % kNsPerSec);
    return ts;
}

TimeNs read(clockid_t id) {
    timespec ts{};
    clock_gettime(id, &ts);
    return static_cast<TimeNs>(ts.tv_sec) * kNsPerSec + static_cast<TimeNs>(ts.tv_nsec);
}

}  // namespace

TimeNs MonotonicClock::now() const { return read(CLOCK_MONOTONIC); }

void MonotonicClock::sleepUntil(TimeNs deadline) {
    const timespec target = toTimespec(deadline);
    // EINTR (a signal such as SIGINT) resumes the same absolute sleep; the
    // executive checks its stop flag once per frame, so shutdown is at most one
    // frame late and frames never start early.
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &target, nullptr) == EINTR) {
    }
}

TimeNs ThreadCpuClock::now() const { return read(CLOCK_THREAD_CPUTIME_ID); }

}  // namespace rse::core

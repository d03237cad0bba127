// clock.hpp's clocks that read the operating system's.
#include "fsw/core/clock.hpp"

#include <cerrno>
#include <cstdint>
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
    const TimeNs wakeAt = deadline - spinMargin_;
    const timespec target = toTimespec(wakeAt);
    // EINTR (a signal such as SIGINT) resumes the same absolute sleep; the
    // executive checks its stop flag once per frame, so shutdown is at most one
    // frame late and frames never start early.
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &target, nullptr) == EINTR) {
    }
    // The spin: bounded by the deadline itself, at most spinMargin_ after a timely
    // wake-up (CLOCK_MONOTONIC only advances); nothing when the sleep woke late.
    if (spinMargin_ > 0) {
        while (now() < deadline) {
        }
    }
}

bool MonotonicClock::setSpinMargin(TimeNs margin) {
    if (margin < 0 || margin > kMaxSpinMargin) {
        return false;
    }
    spinMargin_ = margin;
    return true;
}

bool ScaledMonotonicClock::start(std::uint32_t factor) {
    if (started_ || factor < 1 || factor > kMaxFactor) {
        return false;
    }
    anchor_ = wall_.now();
    factor_ = factor;
    started_ = true;
    return true;
}

TimeNs ScaledMonotonicClock::now() const {
    const TimeNs wall = wall_.now();
    return anchor_ + (wall - anchor_) / static_cast<TimeNs>(factor_);
}

void ScaledMonotonicClock::sleepUntil(TimeNs deadline) {
    // deadline - anchor_ is mission time since the start: at most a few 1e16 ns
    // for any run (rse-fsw --duration is capped at 1e7 s), times kMaxFactor
    // stays far below the range of TimeNs. A deadline before the anchor has
    // passed already.
    const TimeNs since = deadline - anchor_;
    if (since <= 0) {
        return;
    }
    const TimeNs limit = (INT64_MAX - anchor_) / static_cast<TimeNs>(factor_);
    wall_.sleepUntil(since >= limit ? INT64_MAX : anchor_ + since * static_cast<TimeNs>(factor_));
}

TimeNs ThreadCpuClock::now() const { return read(CLOCK_THREAD_CPUTIME_ID); }

}  // namespace rse::core

// The executive's timeline.
//
// Two implementations: MonotonicClock (CLOCK_MONOTONIC, absolute-deadline sleeps,
// used on the rover and over vcan) and VirtualClock (lockstep simulation: sleeping
// jumps straight to the deadline, so a mission runs as fast as the CPU allows and
// the same inputs always give the same timeline). Beside them ThreadCpuClock,
// which is no timeline (nothing can sleep on it) but a meter of the calling
// thread's own CPU time.
#pragma once

#include <cstdint>

namespace rse::core {

// Nanoseconds on a monotonic timeline; zero is the clock's own epoch.
using TimeNs = std::int64_t;

constexpr TimeNs kNsPerUs = 1000;
constexpr TimeNs kNsPerMs = 1000 * kNsPerUs;
constexpr TimeNs kNsPerSec = 1000 * kNsPerMs;

class Clock {
public:
    virtual TimeNs now() const = 0;
    // Returns at or after the absolute time deadline (at once if it has passed).
    virtual void sleepUntil(TimeNs deadline) = 0;

protected:
    ~Clock() = default;  // not owned through this interface
};

class VirtualClock final : public Clock {
public:
    explicit VirtualClock(TimeNs start = 0) : now_(start) {}

    TimeNs now() const override { return now_; }
    void sleepUntil(TimeNs deadline) override {
        if (deadline > now_) {
            now_ = deadline;
        }
    }
    // Simulated work: a test task "takes" dt of the timeline.
    void advance(TimeNs dt) {
        if (dt > 0) {
            now_ += dt;
        }
    }

private:
    TimeNs now_;
};

class MonotonicClock final : public Clock {
public:
    // Spin margins above this are refused: a spin is CPU time taken from every
    // other thread on the core, and a kernel that wakes this late needs fixing,
    // not spinning (docs/performance.md, "Frame-start jitter").
    static constexpr TimeNs kMaxSpinMargin = 2 * kNsPerMs;

    TimeNs now() const override;
    // clock_nanosleep(TIMER_ABSTIME): deadlines are absolute, so lateness in one
    // frame does not shift the next; interrupted sleeps resume to the same deadline.
    // With a spin margin m > 0 (hybrid wait) it sleeps only to deadline - m and
    // spins on now() for the rest: the kernel's timer wake-up latency (tens to
    // hundreds of microseconds on a VM) is then paid inside the margin instead of
    // after the deadline, at the price of up to m of CPU time a wait.
    void sleepUntil(TimeNs deadline) override;
    // 0 = sleep only (the default). Returns false (and keeps the margin it had)
    // outside 0..kMaxSpinMargin. rse-fsw --spin-margin-us sets it.
    bool setSpinMargin(TimeNs margin);
    TimeNs spinMargin() const { return spinMargin_; }

private:
    TimeNs spinMargin_ = 0;
};

// CLOCK_MONOTONIC slowed down by a whole factor, for the lab only: a machine
// too slow to keep the rover's timeline (the qemu VM, which emulates its CPU)
// runs rse-fsw and rse-sim both with the same factor (their --time-scale N), so
// that every second of mission time takes N seconds of wall time. Each process
// then sees the same mission as in real time (frame periods, timeouts, the
// simulator's physics and fault times are all in mission time), with N times the
// CPU time per frame. Until start() it reads and sleeps exactly as
// MonotonicClock (factor 1). start(N) anchors the scaling at the current
// CLOCK_MONOTONIC reading t0, with mission time continuous there:
//   mission(t) = t0 + (t - t0) / N,  sleepUntil(d) waits for t = t0 + (d - t0) * N.
// Task times and budgets are judged on this clock: a run that took N ms of
// wall time counts as 1 ms, as on a computer N times faster than this one.
// Not scaled: the receive stamps hal::SocketCanBus puts on CAN frames (on
// CLOCK_MONOTONIC; no flight code reads them) and the executive's host-time
// statistics (TaskStats::host*, wall time whatever the clock).
class ScaledMonotonicClock final : public Clock {
public:
    static constexpr std::uint32_t kMaxFactor = 100;
    // Returns false (and changes nothing) for a factor outside 1..kMaxFactor or
    // when already started. Called once, before the first frame.
    bool start(std::uint32_t factor);
    std::uint32_t factor() const { return factor_; }
    // The hybrid wait of MonotonicClock::setSpinMargin, in wall time (not scaled).
    bool setSpinMargin(TimeNs margin) { return wall_.setSpinMargin(margin); }
    TimeNs now() const override;
    void sleepUntil(TimeNs deadline) override;

private:
    MonotonicClock wall_;
    TimeNs anchor_ = 0;
    std::uint32_t factor_ = 1;
    bool started_ = false;
};

// The calling thread's CPU time (CLOCK_THREAD_CPUTIME_ID, user and system): what
// a task's own work cost, without the time the scheduler gave to other threads
// meanwhile, which wall-clock timing cannot tell apart. A kernel without IRQ time
// accounting charges interrupt work to the interrupted thread, and a VM without
// steal-time accounting (the development VM) the hypervisor's stalls too
// (docs/performance.md, "Ground-link floods"). Not free: unlike
// CLOCK_MONOTONIC it is a system call, not a vDSO read (about 1.9 us on the
// development VM, bench_executive), so the executive reads it only for the rows
// that ask (RateGroupEntry::cpuTimed).
class ThreadCpuClock final {
public:
    TimeNs now() const;
};

}  // namespace rse::core

// make bench: the cyclic executive's own cost and its timing quality.
//
//  1. Overhead per minor frame with empty tasks: frames run back to back on the
//     real clock (sleeps skipped), so the figure is the executive's bookkeeping
//     plus its clock reads, per frame, for 0, 1, 8 and 16 tasks; and the same on
//     the virtual clock (lockstep).
//  2. Frame-start jitter in real-time mode: 100 Hz for BENCH_JITTER_SECONDS
//     (default 10) per wait with rse-fsw's real-time posture (mlockall +
//     SCHED_FIFO where the OS allows); lateness = actual - scheduled start of
//     each frame; sleep only beside the hybrid sleep-then-spin wait, with the
//     CPU time each costs.
// Host-side program: it may allocate; the executive under test does not.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/realtime_process.hpp"
#include "unit_test/bench/bench_targets.hpp"

using namespace rse::core;

namespace {

class EmptyTask final : public Task {
public:
    void run(const FrameContext&) override {}
};

// The real clock, but frames never wait: measures pure executive cost.
class NoWaitMonotonicClock final : public Clock {
public:
    TimeNs now() const override { return real_.now(); }
    void sleepUntil(TimeNs) override {}

private:
    MonotonicClock real_;
};

class LatenessRecorder final : public Task {
public:
    explicit LatenessRecorder(std::size_t frames) { samples.reserve(frames); }
    void run(const FrameContext& frame) override {
        if (samples.size() < samples.capacity()) {
            samples.push_back(frame.actualStart - frame.scheduledStart);
        }
    }
    std::vector<TimeNs> samples;
};

EmptyTask g_empty[kMaxTasks];

// The first cpuTimedCount rows are timed in thread CPU time as well (RateGroupEntry::cpuTimed).
double overheadNsPerFrame(Clock& clock, std::size_t taskCount, std::uint64_t frames, std::size_t cpuTimedCount = 0) {
    EventLog events(clock);
    Executive exec(clock, events);
    RateGroupEntry table[kMaxTasks];
    for (std::size_t i = 0; i < taskCount; ++i) {
        table[i] = RateGroupEntry{"empty", &g_empty[i], 1, 0, 1000, i < cpuTimedCount};
    }
    if (!isOk(exec.init(ExecutiveConfig{}, table, taskCount))) {
        std::fprintf(stderr, "bench: executive init failed\n");
        std::exit(1);
    }
    MonotonicClock wall;
    exec.runFrame();  // start-up (event, origin) outside the timed region
    const TimeNs begin = wall.now();
    for (std::uint64_t f = 0; f < frames; ++f) {
        exec.runFrame();
    }
    const TimeNs took = wall.now() - begin;
    return static_cast<double>(took) / static_cast<double>(frames);
}

TimeNs percentile(std::vector<TimeNs> v, double p) {
    std::sort(v.begin(), v.end());
    const auto index = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
    return v[index];
}

double us(TimeNs ns) { return static_cast<double>(ns) / 1000.0; }

}  // namespace

int main() {
    rse::bench::Targets targets;
    const std::uint64_t frames = 200000;
    std::printf("== executive overhead per minor frame, empty tasks (%llu frames, best of 5)\n",
                static_cast<unsigned long long>(frames));
    std::printf("   %-26s %6s %12s\n", "clock", "tasks", "ns/frame");
    double worstReal = 0.0;
    for (std::size_t tasks : {0UL, 1UL, 8UL, 16UL}) {
        for (int clockKind = 0; clockKind < 2; ++clockKind) {
            double best = 1e18;
            for (int rep = 0; rep < 5; ++rep) {
                NoWaitMonotonicClock real;
                VirtualClock virt;
                Clock& clock = clockKind == 0 ? static_cast<Clock&>(real) : static_cast<Clock&>(virt);
                best = std::min(best, overheadNsPerFrame(clock, tasks, frames));
            }
            if (clockKind == 0 && tasks == 8) {
                worstReal = best;
            }
            std::printf("   %-26s %6zu %12.1f\n", clockKind == 0 ? "real (CLOCK_MONOTONIC)" : "virtual (lockstep)",
                        tasks, best);
        }
    }
    std::printf("   target: < 5000 ns/frame -> %s (8 empty tasks, real clock: %.1f ns)\n",
                targets.check(worstReal < 5000.0) ? "met" : "MISSED", worstReal);
    // What a row timed in thread CPU time costs (two clock_gettime system calls a
    // run): why it is opt-in. A figure, not a target.
    for (const std::size_t cpuTimed : {1UL, 16UL}) {
        double best = 1e18;
        for (int rep = 0; rep < 5; ++rep) {
            NoWaitMonotonicClock real;
            best = std::min(best, overheadNsPerFrame(real, 16, frames / 4, cpuTimed));
        }
        std::printf("   real, %2zu of 16 rows CPU-timed %12.1f\n", cpuTimed, best);
    }

    const char* env = std::getenv("BENCH_JITTER_SECONDS");
    const double seconds = env != nullptr ? std::atof(env) : 10.0;
    const auto jitterFrames = static_cast<std::size_t>(seconds * 100.0);
    MonotonicClock clock;
    EventLog events(clock);
    const RealtimePosture posture = enterRealtimePosture(events, 50);
    static Executive exec(clock, events);
    std::printf("\n== frame-start jitter, real time, 100 Hz, %.0f s (%zu frames) per wait\n", seconds, jitterFrames);
    std::printf("   posture: mlockall %s, SCHED_FIFO %s\n", posture.memoryLocked ? "yes" : "no",
                posture.fifoScheduling ? "yes (priority 50)" : "no (time-shared)");
    std::printf("   %-24s %10s %10s %10s %9s %14s %12s\n", "wait", "p50 us", "p99 us", "max us", "overruns",
                "CPU us/frame", "CPU % core");
    // One run per wait, one after the other in this process: the sleep-only wait
    // (margin 0) and the hybrid at three spin margins (MonotonicClock::setSpinMargin,
    // rse-fsw --spin-margin-us). The CPU column is this thread's CPU time over the
    // run: the executive's bookkeeping plus the spin.
    const TimeNs marginsUs[] = {0, 100, 300, 500};
    constexpr TimeNs kTargetMarginUs = 500;  // the margin docs/performance.md recommends
    TimeNs sleepOnlyP99 = 0, targetP99 = 0;
    for (const TimeNs marginUs : marginsUs) {
        if (!clock.setSpinMargin(marginUs * kNsPerUs)) {
            std::fprintf(stderr, "bench: spin margin %lld us refused\n", static_cast<long long>(marginUs));
            return 1;
        }
        LatenessRecorder recorder(jitterFrames);
        const RateGroupEntry table[] = {{"recorder", &recorder, 1, 0, 1000}};
        if (!isOk(exec.init(ExecutiveConfig{}, table, 1))) {
            std::fprintf(stderr, "bench: executive init failed\n");
            return 1;
        }
        ThreadCpuClock cpu;
        const TimeNs cpuBefore = cpu.now(), wallBefore = clock.now();
        exec.run(nullptr, jitterFrames);
        const TimeNs cpuSpent = cpu.now() - cpuBefore, wallSpent = clock.now() - wallBefore;
        const auto& s = recorder.samples;
        const TimeNs p50 = percentile(s, 0.50), p99 = percentile(s, 0.99);
        const TimeNs mx = *std::max_element(s.begin(), s.end());
        char label[40];
        std::snprintf(label, sizeof label, marginUs == 0 ? "sleep only" : "hybrid, spin %lld us",
                      static_cast<long long>(marginUs));
        std::printf("   %-24s %10.1f %10.1f %10.1f %9u %14.1f %11.1f%%\n", label, us(p50), us(p99), us(mx),
                    static_cast<unsigned>(exec.stats().frameOverruns),
                    us(cpuSpent) / static_cast<double>(s.size()),
                    100.0 * static_cast<double>(cpuSpent) / static_cast<double>(wallSpent));
        if (marginUs == 0) {
            sleepOnlyP99 = p99;
        }
        if (marginUs == kTargetMarginUs) {
            targetP99 = p99;
        }
    }
    // Sleep only is reported against the old 200 us goal as a figure (the kernel's
    // wake-up, not ours); the target is the hybrid's.
    std::printf("   sleep only: p99 %.1f us (%s 200 us)\n", us(sleepOnlyP99),
                sleepOnlyP99 < 200 * kNsPerUs ? "below" : "above");
    std::printf("   target: hybrid (spin %lld us) p99 < 50 us -> %s\n", static_cast<long long>(kTargetMarginUs),
                targets.check(targetP99 < 50 * kNsPerUs) ? "met" : "MISSED");
    return targets.finish();
}

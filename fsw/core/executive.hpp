// The cyclic executive: a major frame of minor frames, tasks in rate groups.
//
// One table lists every task with its rate divisor (runs every N-th minor frame),
// its offset (which of those N frames) and its time budget. Tasks run in table
// order within a frame. Every run is timed on the executive's clock (last, max,
// mean); a run over budget is counted and evented, as is a frame that runs past
// the start of the next one (a "cycle slip"). Budgets are judged on the
// executive's clock, so lockstep runs are deterministic; each run's host time
// (CLOCK_MONOTONIC, wall time) is recorded beside it as a statistic, which is what
// tells the cost of a task when the timeline is virtual. Wall time also counts
// the time the task was off the CPU (descheduled, blocked), so a row may ask for
// its thread CPU time as well (cpuTimed): runs over budget in CPU time are the
// task's own doing (see ThreadCpuClock for what else a VM charges to it), the
// rest of its over-budget runs were time off the CPU. Frames whose whole slot has passed
// during an overrun are skipped, not run late back-to-back, so the frame index
// always matches the timeline (cFS SCH's skipped-slot rule); they are counted.
#pragma once

#include <csignal>
#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/static_vector.hpp"
#include "fsw/core/status.hpp"

namespace rse::core {

constexpr std::size_t kMaxTasks = 16;  // rows in the rate-group table

struct FrameContext {
    std::uint64_t frame = 0;      // minor frames since start, skipped ones included
    std::uint32_t slot = 0;       // frame % minor frames per major frame
    TimeNs scheduledStart = 0;    // when the frame was due
    TimeNs actualStart = 0;       // when it started (>= scheduledStart)
};

class Task {
public:
    virtual void run(const FrameContext& frame) = 0;

protected:
    ~Task() = default;  // tasks are owned by the application, not the executive
};

struct RateGroupEntry {
    const char* name;
    Task* task;
    std::uint16_t rateDivisor;  // runs when slot % rateDivisor == offset
    std::uint16_t offset;       // 0 .. rateDivisor-1, spreads tasks of one rate
    std::uint32_t budgetUs;     // longest acceptable run
    // Also time each run in the thread's CPU time (TaskStats::cpu*). Opt-in: the
    // clock is a system call, about 3.7 us a run on the development VM, and for
    // every row of a full table that is over 50 us a frame (bench_executive; its
    // target for the executive's own cost is 5 us a frame).
    bool cpuTimed = false;
};

struct ExecutiveConfig {
    TimeNs minorFramePeriod = 10 * kNsPerMs;  // 100 Hz
    std::uint16_t minorFramesPerMajor = 100;  // 1 s major frame
};

struct TaskStats {
    std::uint32_t runs = 0;
    std::uint32_t overBudget = 0;
    TimeNs last = 0;       // on the executive's clock (simulated time in lockstep)
    TimeNs max = 0;
    TimeNs total = 0;
    TimeNs hostMax = 0;    // host wall time (CLOCK_MONOTONIC), whatever the clock
    TimeNs hostTotal = 0;
    // Thread CPU time, for cpuTimed rows only (zero for the others): a run over
    // budget on the executive's clock but not here was off the CPU, not busy.
    std::uint32_t cpuOverBudget = 0;  // runs whose CPU time exceeded the budget
    TimeNs cpuLast = 0;
    TimeNs cpuMax = 0;
    TimeNs cpuTotal = 0;
    TimeNs mean() const { return runs == 0 ? 0 : total / runs; }
    TimeNs hostMean() const { return runs == 0 ? 0 : hostTotal / runs; }
    TimeNs cpuMean() const { return runs == 0 ? 0 : cpuTotal / runs; }
};

// When a task last finished a run, on the executive's clock: its liveness, read
// by the health monitor. Not a counter, so resetCounters() leaves it alone.
struct TaskLiveness {
    TimeNs lastRunEnd = 0;  // 0: never ran
    bool enabled = true;
};

struct ExecutiveStats {
    std::uint64_t framesRun = 0;
    std::uint32_t frameOverruns = 0;   // frames that ended after the next was due
    std::uint32_t framesSkipped = 0;   // frames never run because their slot passed
    TimeNs lastLateness = 0;           // actual - scheduled start of the last frame
    TimeNs maxLateness = 0;
    TimeNs lastBusy = 0;               // time spent running tasks in the last frame
    TimeNs maxBusy = 0;
    TimeNs totalBusy = 0;
};

class Executive {
public:
    Executive(Clock& clock, EventLog& events) : clock_(clock), events_(events) {}

    // Validates and copies the table; nothing runs until it succeeds.
    Status init(const ExecutiveConfig& config, const RateGroupEntry* table, std::size_t count);

    // Sets the timeline origin: frame 0 is due now. Called by run() if needed.
    void start();
    // Runs one minor frame: waits for its start, runs its tasks, accounts overruns.
    void runFrame();
    // Runs until *stop becomes non-zero (checked once per frame) or maxFrames
    // frames have run (0: no limit). Returns the number of frames run.
    std::uint64_t run(const volatile std::sig_atomic_t* stop, std::uint64_t maxFrames);

    const ExecutiveStats& stats() const { return stats_; }
    std::size_t taskCount() const { return tasks_.size(); }
    const RateGroupEntry* entry(std::size_t index) const;
    // The row of the task called `name` (rows are in frame-schedule order, not
    // a contract); taskCount() when there is none.
    std::size_t findTask(const char* name) const;
    const TaskStats* taskStats(std::size_t index) const;
    const TaskLiveness* taskLiveness(std::size_t index) const;
    // Maintenance hook: a disabled row is skipped (and evented once per change),
    // so its task stops running and the health monitor sees it stall.
    Status setTaskEnabled(std::size_t index, bool enabled);
    const ExecutiveConfig& config() const { return config_; }
    std::uint64_t nextFrame() const { return frame_; }
    void resetCounters();

private:
    struct Slot {
        RateGroupEntry entry{};
        TaskStats stats;
        TaskLiveness liveness;
    };

    Status reject(const char* reason, std::size_t row);
    void runTask(Slot& slot, const FrameContext& context);

    Clock& clock_;
    MonotonicClock hostTimer_;
    ThreadCpuClock cpuTimer_;
    EventLog& events_;
    ExecutiveConfig config_;
    StaticVector<Slot, kMaxTasks> tasks_;
    ExecutiveStats stats_;
    bool initialized_ = false;
    bool started_ = false;
    TimeNs origin_ = 0;
    std::uint64_t frame_ = 0;
};

}  // namespace rse::core

#include <csignal>
#include <cstdint>
#include <ctime>
#include <string>

#include "fsw/core/core_events.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/static_vector.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::core;

namespace {

struct RunRecord {
    std::uint64_t frame;
    int taskId;
    TimeNs scheduled;
    TimeNs actual;
};

using RunLog = StaticVector<RunRecord, 4096>;

// Records each run; optionally "works" by advancing the virtual clock.
class RecordingTask final : public Task {
public:
    RecordingTask(int id, RunLog& log, VirtualClock& clock) : id_(id), log_(log), clock_(clock) {}
    void run(const FrameContext& frame) override {
        (void)log_.push_back(RunRecord{frame.frame, id_, frame.scheduledStart, frame.actualStart});
        clock_.advance(workAt(frame.frame));
    }
    // Work per run: a fixed amount, plus a one-off spike in one frame.
    TimeNs work = 0;
    std::uint64_t spikeFrame = UINT64_MAX;
    TimeNs spike = 0;

private:
    TimeNs workAt(std::uint64_t frame) const { return frame == spikeFrame ? spike : work; }
    int id_;
    RunLog& log_;
    VirtualClock& clock_;
};

const ExecutiveConfig k100Hz{10 * kNsPerMs, 100};

}  // namespace

TEST_GROUP(Executive) {
    VirtualClock clock;
    EventLog events{clock};
    Executive exec{clock, events};
    RunLog log;
    RecordingTask fast{0, log, clock};
    RecordingTask tenHzA{1, log, clock};
    RecordingTask tenHzB{2, log, clock};
    RecordingTask oneHz{3, log, clock};

    // Runs `frames` frames of a table holding only `fast`, every frame.
    void runFastOnly(std::uint32_t budgetUs, int frames) {
        const RateGroupEntry table[] = {{"fast", &fast, 1, 0, budgetUs}};
        CHECK(Status::kOk == exec.init(k100Hz, table, 1));
        for (int i = 0; i < frames; ++i) {
            exec.runFrame();
        }
    }
};

TEST(Executive, RunsEachTaskAtItsRateAndOffsetInDeclaredOrder) {
    const RateGroupEntry table[] = {
        {"fast", &fast, 1, 0, 1000},
        {"tenHzA", &tenHzA, 10, 0, 1000},
        {"tenHzB", &tenHzB, 10, 3, 1000},
        {"oneHz", &oneHz, 100, 5, 1000},
    };
    CHECK(Status::kOk == exec.init(k100Hz, table, 4));
    for (int i = 0; i < 1000; ++i) {
        exec.runFrame();
    }
    LONGS_EQUAL(1000, exec.stats().framesRun);
    LONGS_EQUAL(1000, exec.taskStats(0)->runs);
    LONGS_EQUAL(100, exec.taskStats(1)->runs);
    LONGS_EQUAL(100, exec.taskStats(2)->runs);
    LONGS_EQUAL(10, exec.taskStats(3)->runs);
    LONGS_EQUAL(1000 + 100 + 100 + 10, log.size());

    int lastTaskInFrame = -1;
    std::uint64_t currentFrame = UINT64_MAX;
    for (const RunRecord& r : log) {
        if (r.frame != currentFrame) {
            currentFrame = r.frame;
            lastTaskInFrame = -1;
        }
        CHECK_TEXT(r.taskId > lastTaskInFrame, "tasks ran out of declared order");
        lastTaskInFrame = r.taskId;
        switch (r.taskId) {
            case 1: LONGS_EQUAL(0, r.frame % 10); break;
            case 2: LONGS_EQUAL(3, r.frame % 10); break;
            case 3: LONGS_EQUAL(5, r.frame % 100); break;
            default: break;
        }
        // On the virtual clock with no work, every frame starts exactly on time.
        CHECK_EQUAL(static_cast<TimeNs>(r.frame) * 10 * kNsPerMs, r.scheduled);
        CHECK_EQUAL(r.scheduled, r.actual);
    }
    LONGS_EQUAL(0, exec.stats().frameOverruns);
}

TEST(Executive, FindsATaskRowByItsName) {
    const RateGroupEntry table[] = {{"fast", &fast, 1, 0, 1000}, {"oneHz", &oneHz, 100, 5, 1000}};
    CHECK(Status::kOk == exec.init(k100Hz, table, 2));
    LONGS_EQUAL(1, exec.findTask("oneHz"));
    LONGS_EQUAL(0, exec.findTask("fast"));
    LONGS_EQUAL(2, exec.findTask("one"));  // a prefix is not a name
    LONGS_EQUAL(2, exec.findTask(nullptr));
}

TEST(Executive, FrameOverrunIsCountedEventedAndSkipsPassedFrames) {
    fast.spikeFrame = 3;
    fast.spike = 25 * kNsPerMs;  // frame 3 starts at 30 ms and ends at 55 ms
    runFastOnly(5000, 6);
    LONGS_EQUAL(1, exec.stats().frameOverruns);
    // Frame 4's slot [40, 50) ms passed entirely: skipped. Frame 5 ran late at 55 ms.
    LONGS_EQUAL(1, exec.stats().framesSkipped);
    LONGS_EQUAL(6, exec.stats().framesRun);
    const RunRecord* late = log.at(4);
    LONGS_EQUAL(5, late->frame);
    CHECK_EQUAL(50 * kNsPerMs, late->scheduled);
    CHECK_EQUAL(55 * kNsPerMs, late->actual);
    CHECK_EQUAL(5 * kNsPerMs, exec.stats().maxLateness);
    LONGS_EQUAL(6, log.at(5)->frame);  // back on the timeline
    CHECK_EQUAL(60 * kNsPerMs, log.at(5)->actual);
    LONGS_EQUAL(1, exec.taskStats(0)->overBudget);

    Event e;
    unsigned overrun = 0, skipped = 0, overBudget = 0;
    while (isOk(events.pop(&e))) {
        overrun += e.id == events::kExecFrameOverrun ? 1U : 0U;
        skipped += e.id == events::kExecFramesSkipped ? 1U : 0U;
        overBudget += e.id == events::kExecTaskOverBudget ? 1U : 0U;
    }
    LONGS_EQUAL(1, overrun);
    LONGS_EQUAL(1, skipped);
    LONGS_EQUAL(1, overBudget);
}

TEST(Executive, OverrunWithinOneFrameSkipsNothing) {
    fast.spikeFrame = 2;
    fast.spike = 12 * kNsPerMs;
    runFastOnly(20000, 5);
    LONGS_EQUAL(1, exec.stats().frameOverruns);
    LONGS_EQUAL(0, exec.stats().framesSkipped);
    LONGS_EQUAL(0, exec.taskStats(0)->overBudget);  // within its generous budget
    LONGS_EQUAL(3, log.at(3)->frame);
    CHECK_EQUAL(32 * kNsPerMs, log.at(3)->actual);
}

TEST(Executive, TaskOverBudgetWithoutFrameOverrunIsCounted) {
    fast.work = 3 * kNsPerMs;
    runFastOnly(2000, 8);
    LONGS_EQUAL(8, exec.taskStats(0)->overBudget);
    LONGS_EQUAL(0, exec.stats().frameOverruns);
    CHECK_EQUAL(3 * kNsPerMs, exec.taskStats(0)->last);
    CHECK_EQUAL(3 * kNsPerMs, exec.taskStats(0)->max);
    CHECK_EQUAL(3 * kNsPerMs, exec.taskStats(0)->mean());
    // Evented on occurrences 1, 2, 4 and 8 only; the counter has all eight.
    LONGS_EQUAL(4, rse::test::drainEventsWithId(events, events::kExecTaskOverBudget));
}

TEST(Executive, VirtualClockRunsAreDeterministic) {
    // Two independent executives fed the same irregular work give identical timelines.
    struct Rig {
        VirtualClock clock;
        EventLog events{clock};
        Executive exec{clock, events};
        RunLog log;
        RecordingTask a{0, log, clock};
        RecordingTask b{1, log, clock};
    };
    static Rig rigs[2];
    for (Rig& rig : rigs) {
        rig.a.work = 1 * kNsPerMs;
        rig.b.work = 4 * kNsPerMs;
        rig.b.spikeFrame = 42;  // b runs in frames 2, 7, 12, ...
        rig.b.spike = 37 * kNsPerMs;
        const RateGroupEntry table[] = {{"a", &rig.a, 1, 0, 2000}, {"b", &rig.b, 5, 2, 5000}};
        CHECK(Status::kOk == rig.exec.init(k100Hz, table, 2));
        for (int i = 0; i < 500; ++i) {
            rig.exec.runFrame();
        }
    }
    LONGS_EQUAL(rigs[0].log.size(), rigs[1].log.size());
    for (std::size_t i = 0; i < rigs[0].log.size(); ++i) {
        LONGS_EQUAL(rigs[0].log.at(i)->frame, rigs[1].log.at(i)->frame);
        CHECK_EQUAL(rigs[0].log.at(i)->actual, rigs[1].log.at(i)->actual);
    }
    CHECK_EQUAL(rigs[0].clock.now(), rigs[1].clock.now());
    LONGS_EQUAL(rigs[0].exec.stats().framesSkipped, rigs[1].exec.stats().framesSkipped);
    CHECK(rigs[0].exec.stats().framesSkipped > 0);  // the spike really did cost frames
}

TEST(Executive, InvalidTablesAreRejectedWithAnEventAndNothingRuns) {
    const RateGroupEntry zeroDivisor[] = {{"t", &fast, 0, 0, 100}};
    const RateGroupEntry notDividing[] = {{"t", &fast, 7, 0, 100}};
    const RateGroupEntry badOffset[] = {{"t", &fast, 10, 10, 100}};
    const RateGroupEntry noTask[] = {{"t", nullptr, 1, 0, 100}};
    CHECK(Status::kInvalidArgument == exec.init(k100Hz, zeroDivisor, 1));
    CHECK(Status::kInvalidArgument == exec.init(k100Hz, notDividing, 1));
    CHECK(Status::kInvalidArgument == exec.init(k100Hz, badOffset, 1));
    CHECK(Status::kInvalidArgument == exec.init(k100Hz, noTask, 1));
    CHECK(Status::kInvalidArgument == exec.init(ExecutiveConfig{0, 100}, nullptr, 0));
    RateGroupEntry tooMany[kMaxTasks + 1];
    for (RateGroupEntry& e : tooMany) {
        e = RateGroupEntry{"t", &fast, 1, 0, 100};
    }
    CHECK(Status::kNoCapacity == exec.init(k100Hz, tooMany, kMaxTasks + 1));
    LONGS_EQUAL(6, rse::test::drainEventsWithId(events, events::kExecConfigRejected));

    exec.runFrame();
    LONGS_EQUAL(0, log.size());
    LONGS_EQUAL(0, exec.stats().framesRun);
}

TEST(Executive, StopFlagIsCheckedOncePerFrame) {
    static volatile std::sig_atomic_t stop = 0;
    stop = 0;
    class StopAt final : public Task {
    public:
        void run(const FrameContext& frame) override {
            if (frame.frame == 36) {
                stop = 1;
            }
        }
    } stopper;
    const RateGroupEntry table[] = {{"stopper", &stopper, 1, 0, 100}};
    CHECK(Status::kOk == exec.init(k100Hz, table, 1));
    LONGS_EQUAL(37, exec.run(&stop, 0));
    LONGS_EQUAL(37, exec.stats().framesRun);
    // And a frame limit stops it too.
    stop = 0;
    LONGS_EQUAL(5, exec.run(&stop, 5));
}

TEST(Executive, HostCpuTimeIsRecordedWhileTheVirtualTimelineStandsStill) {
    class Busy final : public Task {
    public:
        void run(const FrameContext&) override {
            for (int i = 0; i < 2000; ++i) {
                sink = sink + static_cast<double>(i) * 0.5;
            }
        }
        volatile double sink = 0.0;
    } busy;
    const RateGroupEntry table[] = {{"busy", &busy, 1, 0, 1000}};
    CHECK(Status::kOk == exec.init(k100Hz, table, 1));
    for (int i = 0; i < 100; ++i) {
        exec.runFrame();
    }
    CHECK_EQUAL(0, exec.taskStats(0)->total);  // no simulated work
    CHECK(exec.taskStats(0)->hostTotal > 0);   // but real CPU was spent
    CHECK(exec.taskStats(0)->hostMax >= exec.taskStats(0)->hostMean());
    LONGS_EQUAL(0, exec.taskStats(0)->overBudget);  // budgets judge the timeline
}

// Thread CPU time against wall time, on the real clock: a task that burns CPU
// past its budget is over budget in both; one that sleeps past it (as a task
// off the CPU mid-run would be) is over budget in wall time only. The margins are
// wide (5 ms against a 1 ms budget) so a loaded machine cannot flip either.
namespace {

constexpr std::uint32_t kCpuTestBudgetUs = 1000;
constexpr TimeNs kPastBudget = 5 * kNsPerMs;

// Spins until this thread has used `cpu` of CPU time, however long that takes.
class CpuBurner final : public Task {
public:
    void run(const FrameContext&) override {
        const TimeNs end = cpu_.now() + kPastBudget;
        while (cpu_.now() < end) {
        }
    }

private:
    ThreadCpuClock cpu_;
};

class Sleeper final : public Task {
public:
    void run(const FrameContext&) override {
        const timespec pause{0, static_cast<long>(kPastBudget)};
        nanosleep(&pause, nullptr);
    }
};

}  // namespace

TEST_GROUP(ExecutiveCpuTime) {
    MonotonicClock clock;
    EventLog events{clock};
    Executive exec{clock, events};

    // Runs one frame of a one-row table and returns the over-budget event's text ("" if none).
    std::string runOnce(Task& task, bool cpuTimed) {
        const RateGroupEntry table[] = {{"t", &task, 1, 0, kCpuTestBudgetUs, cpuTimed}};
        CHECK(Status::kOk == exec.init(k100Hz, table, 1));
        exec.runFrame();
        std::string text;
        Event e;
        while (isOk(events.pop(&e))) {
            if (e.id == events::kExecTaskOverBudget) {
                text = e.text;
            }
        }
        return text;
    }
};

TEST(ExecutiveCpuTime, WorkPastTheBudgetIsOverBudgetInCpuTimeToo) {
    CpuBurner burner;
    const std::string event = runOnce(burner, true);
    const TaskStats& s = *exec.taskStats(0);
    LONGS_EQUAL(1, s.overBudget);
    LONGS_EQUAL(1, s.cpuOverBudget);
    CHECK(s.cpuLast >= kPastBudget);
    CHECK_EQUAL(s.cpuLast, s.cpuMax);
    CHECK_EQUAL(s.cpuLast, s.cpuMean());
    // The event gives the CPU time beside the wall time.
    CHECK_TEXT(event.find(", CPU ") != std::string::npos, event.c_str());
    CHECK_TEXT(event.find("(1 overruns, 1 CPU)") != std::string::npos, event.c_str());
}

TEST(ExecutiveCpuTime, SleepingPastTheBudgetIsOverBudgetInWallTimeOnly) {
    Sleeper sleeper;
    const std::string event = runOnce(sleeper, true);
    const TaskStats& s = *exec.taskStats(0);
    LONGS_EQUAL(1, s.overBudget);
    LONGS_EQUAL(0, s.cpuOverBudget);
    CHECK(s.last >= kPastBudget);
    CHECK(s.cpuLast < static_cast<TimeNs>(kCpuTestBudgetUs) * kNsPerUs);
    CHECK_TEXT(event.find("(1 overruns, 0 CPU)") != std::string::npos, event.c_str());
}

TEST(ExecutiveCpuTime, RowsNotCpuTimedRecordNoCpuTime) {
    CpuBurner burner;
    const std::string event = runOnce(burner, false);
    const TaskStats& s = *exec.taskStats(0);
    LONGS_EQUAL(1, s.overBudget);
    LONGS_EQUAL(0, s.cpuOverBudget);
    CHECK_EQUAL(0, s.cpuLast);
    CHECK_EQUAL(0, s.cpuMax);
    CHECK_EQUAL(0, s.cpuTotal);
    CHECK_TEXT(event.find("CPU") == std::string::npos, event.c_str());
    const RateGroupEntry unsaid{"t", &burner, 1, 0, kCpuTestBudgetUs};
    CHECK_FALSE(unsaid.cpuTimed);  // a row that does not ask is not CPU-timed
}

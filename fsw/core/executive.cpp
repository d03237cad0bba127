#include "fsw/core/executive.hpp"

#include <cstring>

#include "fsw/core/core_events.hpp"

namespace rse::core {

Status Executive::reject(const char* reason, std::size_t row) {
    events_.report(events::kExecConfigRejected, Severity::kError,
                   "exec: rate-group table row %zu rejected: %s", row, reason);
    return Status::kInvalidArgument;
}

Status Executive::init(const ExecutiveConfig& config, const RateGroupEntry* table,
                       std::size_t count) {
    initialized_ = false;
    tasks_.clear();
    if (config.minorFramePeriod <= 0 || config.minorFramesPerMajor == 0) {
        return reject("frame period and frames per major frame must be positive", 0);
    }
    if (table == nullptr && count != 0) {
        return reject("null table", 0);
    }
    if (count > kMaxTasks) {
        events_.report(events::kExecConfigRejected, Severity::kError,
                       "exec: %zu tasks exceed kMaxTasks=%zu", count, kMaxTasks);
        return Status::kNoCapacity;
    }
    for (std::size_t row = 0; row < count; ++row) {
        const RateGroupEntry& e = table[row];
        if (e.task == nullptr || e.name == nullptr) {
            return reject("task and name are required", row);
        }
        if (e.rateDivisor == 0 || config.minorFramesPerMajor % e.rateDivisor != 0) {
            return reject("rate divisor must divide the minor frames per major frame", row);
        }
        if (e.offset >= e.rateDivisor) {
            return reject("offset must be below the rate divisor", row);
        }
        Slot slot;
        slot.entry = e;
        if (!isOk(tasks_.push_back(slot))) {
            return reject("table full", row);
        }
    }
    config_ = config;
    stats_ = ExecutiveStats{};
    frame_ = 0;
    started_ = false;
    initialized_ = true;
    return Status::kOk;
}

void Executive::start() {
    events_.report(events::kExecStarted, Severity::kInfo,
                   "exec: started, %zu tasks, minor frame %lld us, %u frames per major",
                   tasks_.size(), static_cast<long long>(config_.minorFramePeriod / kNsPerUs),
                   static_cast<unsigned>(config_.minorFramesPerMajor));
    origin_ = clock_.now();  // after the event, so its cost is not frame 0's lateness
    frame_ = 0;
    started_ = true;
}

void Executive::runTask(Slot& slot, const FrameContext& context) {
    const bool cpuTimed = slot.entry.cpuTimed;
    const TimeNs begin = clock_.now();
    const TimeNs hostBegin = hostTimer_.now();
    const TimeNs cpuBegin = cpuTimed ? cpuTimer_.now() : 0;  // innermost: the task's work only
    slot.entry.task->run(context);
    const TimeNs cpuTook = cpuTimed ? cpuTimer_.now() - cpuBegin : 0;
    const TimeNs hostTook = hostTimer_.now() - hostBegin;
    const TimeNs end = clock_.now();
    const TimeNs took = end - begin;
    slot.liveness.lastRunEnd = end;

    TaskStats& s = slot.stats;
    const TimeNs budget = static_cast<TimeNs>(slot.entry.budgetUs) * kNsPerUs;
    ++s.runs;
    s.hostTotal += hostTook;
    if (hostTook > s.hostMax) {
        s.hostMax = hostTook;
    }
    s.last = took;
    s.total += took;
    if (took > s.max) {
        s.max = took;
    }
    if (cpuTimed) {
        s.cpuLast = cpuTook;
        s.cpuTotal += cpuTook;
        if (cpuTook > s.cpuMax) {
            s.cpuMax = cpuTook;
        }
        // Counted, not evented: in lockstep the CPU time is the host's, and the
        // event stream must stay the same for the same inputs. In real time CPU
        // time cannot exceed wall time, so such a run is evented just below.
        if (cpuTook > budget) {
            ++s.cpuOverBudget;
        }
    }
    if (took > budget) {
        ++s.overBudget;
        if (!isReportableOccurrence(s.overBudget)) {
            return;
        }
        // With the CPU time beside it the operator can tell a task that did too
        // much work (CPU time over budget too) from one that was off the CPU
        // (descheduled or blocked).
        if (cpuTimed) {
            events_.report(events::kExecTaskOverBudget, Severity::kWarning,
                           "exec: task %s took %lld us, CPU %lld us, budget %u us (%u overruns, %u CPU)",
                           slot.entry.name, static_cast<long long>(took / kNsPerUs),
                           static_cast<long long>(cpuTook / kNsPerUs), static_cast<unsigned>(slot.entry.budgetUs),
                           static_cast<unsigned>(s.overBudget), static_cast<unsigned>(s.cpuOverBudget));
        } else {
            events_.report(events::kExecTaskOverBudget, Severity::kWarning,
                           "exec: task %s took %lld us, budget %u us (%u overruns)",
                           slot.entry.name, static_cast<long long>(took / kNsPerUs),
                           static_cast<unsigned>(slot.entry.budgetUs),
                           static_cast<unsigned>(s.overBudget));
        }
    }
}

void Executive::runFrame() {
    if (!initialized_) {
        return;
    }
    if (!started_) {
        start();
    }
    const TimeNs period = config_.minorFramePeriod;
    FrameContext context;
    context.frame = frame_;
    context.slot = static_cast<std::uint32_t>(frame_ % config_.minorFramesPerMajor);
    context.scheduledStart = origin_ + static_cast<TimeNs>(frame_) * period;

    clock_.sleepUntil(context.scheduledStart);
    context.actualStart = clock_.now();
    const TimeNs lateness = context.actualStart - context.scheduledStart;
    stats_.lastLateness = lateness;
    if (lateness > stats_.maxLateness) {
        stats_.maxLateness = lateness;
    }

    for (Slot& slot : tasks_) {  // bounded by kMaxTasks
        if (slot.liveness.enabled && context.slot % slot.entry.rateDivisor == slot.entry.offset) {
            runTask(slot, context);
        }
    }

    const TimeNs end = clock_.now();
    const TimeNs busy = end - context.actualStart;
    ++stats_.framesRun;
    stats_.lastBusy = busy;
    stats_.totalBusy += busy;
    if (busy > stats_.maxBusy) {
        stats_.maxBusy = busy;
    }

    ++frame_;
    const TimeNs nextStart = origin_ + static_cast<TimeNs>(frame_) * period;
    if (end > nextStart) {
        ++stats_.frameOverruns;
        // Frames whose whole slot has already passed are skipped; the frame in
        // progress at `end` runs at once (late), keeping frame index == time.
        const auto skipped = static_cast<std::uint64_t>((end - nextStart) / period);
        frame_ += skipped;
        stats_.framesSkipped += static_cast<std::uint32_t>(skipped);
        if (isReportableOccurrence(stats_.frameOverruns)) {
            events_.report(events::kExecFrameOverrun, Severity::kWarning,
                           "exec: frame %llu overran by %lld us (%u overruns)",
                           static_cast<unsigned long long>(context.frame),
                           static_cast<long long>((end - nextStart) / kNsPerUs),
                           static_cast<unsigned>(stats_.frameOverruns));
        }
        if (skipped > 0) {
            events_.report(events::kExecFramesSkipped, Severity::kWarning,
                           "exec: %llu frames skipped after frame %llu (%u in total)",
                           static_cast<unsigned long long>(skipped),
                           static_cast<unsigned long long>(context.frame),
                           static_cast<unsigned>(stats_.framesSkipped));
        }
    }
}

std::uint64_t Executive::run(const volatile std::sig_atomic_t* stop, std::uint64_t maxFrames) {
    std::uint64_t ran = 0;
    if (!initialized_) {
        return ran;
    }
    while ((stop == nullptr || *stop == 0) && (maxFrames == 0 || ran < maxFrames)) {
        runFrame();
        ++ran;
    }
    events_.report(events::kExecStopped, Severity::kInfo, "exec: stopped after %llu frames",
                   static_cast<unsigned long long>(stats_.framesRun));
    return ran;
}

const RateGroupEntry* Executive::entry(std::size_t index) const {
    const Slot* slot = tasks_.at(index);
    return slot == nullptr ? nullptr : &slot->entry;
}

std::size_t Executive::findTask(const char* name) const {
    for (std::size_t i = 0; name != nullptr && i < tasks_.size(); ++i) {
        const char* rowName = tasks_.at(i)->entry.name;
        if (rowName != nullptr && std::strcmp(rowName, name) == 0) {
            return i;
        }
    }
    return tasks_.size();
}

const TaskStats* Executive::taskStats(std::size_t index) const {
    const Slot* slot = tasks_.at(index);
    return slot == nullptr ? nullptr : &slot->stats;
}

const TaskLiveness* Executive::taskLiveness(std::size_t index) const {
    const Slot* slot = tasks_.at(index);
    return slot == nullptr ? nullptr : &slot->liveness;
}

Status Executive::setTaskEnabled(std::size_t index, bool enabled) {
    Slot* slot = tasks_.at(index);
    if (slot == nullptr) {
        return Status::kInvalidArgument;
    }
    if (slot->liveness.enabled != enabled) {
        slot->liveness.enabled = enabled;
        events_.report(events::kExecTaskEnabled, enabled ? Severity::kInfo : Severity::kWarning,
                       "exec: task %s %s", slot->entry.name, enabled ? "enabled" : "disabled");
    }
    return Status::kOk;
}

void Executive::resetCounters() {
    stats_ = ExecutiveStats{};
    for (Slot& slot : tasks_) {
        slot.stats = TaskStats{};
    }
}

}  // namespace rse::core

#include "fsw/cmdtlm/housekeeping_task.hpp"

#include <cstdio>

namespace rse::cmdtlm {

namespace {

std::uint32_t toUs(core::TimeNs ns) {
    if (ns <= 0) {
        return 0;
    }
    const core::TimeNs us = ns / core::kNsPerUs;
    return us > static_cast<core::TimeNs>(UINT32_MAX) ? UINT32_MAX : static_cast<std::uint32_t>(us);
}

}  // namespace

void HousekeepingTask::collect(msg::HousekeepingMsg* msg, core::TimeNs now) const {
    *msg = msg::HousekeepingMsg{};
    const core::ExecutiveStats& exec = executive_.stats();
    msg->timeNs = now;
    msg->framesRun = exec.framesRun;
    msg->frameOverruns = exec.frameOverruns;
    msg->framesSkipped = exec.framesSkipped;
    msg->frameBusyLastUs = toUs(exec.lastBusy);
    msg->frameBusyMaxUs = toUs(exec.maxBusy);
    msg->frameLatenessMaxUs = toUs(exec.maxLateness);

    const core::BusStats& bus = bus_.stats();
    msg->busPublished = bus.published;
    msg->busDelivered = bus.delivered;
    msg->busDropped = bus.dropped;
    msg->busRejectedTooLarge = bus.rejectedTooLarge;
    msg->busNoSubscribers = bus.noSubscribers;

    msg->eventsTotal = events_.total();
    msg->eventsLost = events_.lost();
    for (std::size_t s = 0; s < core::kSeverityCount; ++s) {
        msg->eventsBySeverity[s] = events_.count(static_cast<core::Severity>(s));
    }
    msg->housekeepingCount = published_;

    const std::size_t count = executive_.taskCount();
    msg->taskCount = static_cast<std::uint8_t>(count);
    for (std::size_t i = 0; i < count && i < core::kMaxTasks; ++i) {
        const core::RateGroupEntry* entry = executive_.entry(i);
        const core::TaskStats* stats = executive_.taskStats(i);
        msg::TaskTimingTlm& t = msg->tasks[i];
        std::snprintf(t.name, sizeof t.name, "%s", entry->name);
        t.runs = stats->runs;
        t.overBudget = stats->overBudget;
        t.lastUs = toUs(stats->last);
        t.maxUs = toUs(stats->max);
        t.meanUs = toUs(stats->mean());
        t.hostMeanUs = toUs(stats->hostMean());
        t.hostMaxUs = toUs(stats->hostMax);
        t.cpuOverBudget = stats->cpuOverBudget;
        t.cpuTimed = entry->cpuTimed;
    }
}

void HousekeepingTask::run(const core::FrameContext& frame) {
    ++published_;
    collect(&message_, frame.actualStart);
    (void)bus_.publish(message_);  // failures are counted and evented by the bus
}

}  // namespace rse::cmdtlm

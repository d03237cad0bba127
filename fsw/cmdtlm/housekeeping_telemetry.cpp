#include "fsw/cmdtlm/housekeeping_telemetry.hpp"

#include <algorithm>
#include <cstring>

namespace rse::cmdtlm {

core::Status HousekeepingTelemetry::addContributor(const HousekeepingContributor* contributor) {
    if (contributor == nullptr) {
        return core::Status::kInvalidArgument;
    }
    if (contributorCount_ >= kMaxHousekeepingContributors) {
        return core::Status::kNoCapacity;
    }
    contributors_[contributorCount_++] = contributor;
    return core::Status::kOk;
}

void HousekeepingTelemetry::pack(const core::FrameContext& frame, TelemetrySink& sink) {
    if (frame.slot == 0 || requested_) {
        requested_ = false;
        sendHousekeeping(frame.actualStart, sink);
    }
    if (frame.slot >= kTaskTimingSlot && frame.slot < kTaskTimingSlot + collected_.taskCount) {
        sendTaskTiming(frame.slot - kTaskTimingSlot, sink);
    }
}

void HousekeepingTelemetry::sendHousekeeping(core::TimeNs now, TelemetrySink& sink) {
    collection_.collect(&collected_, now);
    const msg::HousekeepingMsg& c = collected_;
    hk_ = HK_Tlm{};
    hk_.utc_at_met_zero = utcAtMetZero_;
    hk_.time_scale = timeScale_;
    hk_.frames_run = c.framesRun;
    hk_.frame_overruns = c.frameOverruns;
    hk_.frames_skipped = c.framesSkipped;
    hk_.frame_busy_last_us = c.frameBusyLastUs;
    hk_.frame_busy_max_us = c.frameBusyMaxUs;
    hk_.frame_lateness_max_us = c.frameLatenessMaxUs;
    hk_.task_count = c.taskCount;
    hk_.bus_published = c.busPublished;
    hk_.bus_dropped = c.busDropped;
    hk_.bus_rejected = c.busRejectedTooLarge;
    hk_.events_total = c.eventsTotal;
    hk_.events_lost = c.eventsLost;
    for (std::size_t i = 0; i < core::kSeverityCount; ++i) {
        hk_.events_by_severity[i] = c.eventsBySeverity[i];
    }
    for (std::size_t i = 0; i < contributorCount_; ++i) {
        contributors_[i]->fillHousekeeping(hk_);
    }
    sink.send(hk_);
    ++housekeepingSent_;
}

void HousekeepingTelemetry::sendTaskTiming(std::size_t index, TelemetrySink& sink) const {
    if (index >= collected_.taskCount || index >= core::kMaxTasks) {
        return;
    }
    const msg::TaskTimingTlm& t = collected_.tasks[index];
    TASK_TIMING_Tlm tlm{};
    tlm.task_index = static_cast<std::uint8_t>(index);
    std::memcpy(tlm.task_name, t.name, std::min(sizeof tlm.task_name, sizeof t.name));
    tlm.runs = t.runs;
    tlm.over_budget = t.overBudget;
    tlm.last_us = t.lastUs;
    tlm.mean_us = t.meanUs;
    tlm.max_us = t.maxUs;
    tlm.cpu_mean_us = t.hostMeanUs;
    tlm.cpu_max_us = t.hostMaxUs;
    tlm.cpu_timed = t.cpuTimed ? 1 : 0;
    tlm.cpu_over_budget = t.cpuOverBudget;
    sink.send(tlm);
}

}  // namespace rse::cmdtlm

// Housekeeping: the executive's, bus's and event log's counters, once a second.
#pragma once

#include <cstdint>

#include "fsw/core/executive.hpp"
#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

constexpr std::size_t kTaskNameSize = 16;

struct TaskTimingTlm {
    char name[kTaskNameSize];   // NUL-terminated, truncated
    std::uint32_t runs;
    std::uint32_t overBudget;
    std::uint32_t lastUs;
    std::uint32_t maxUs;
    std::uint32_t meanUs;
    std::uint32_t hostMeanUs;   // host wall time (differs from the above in lockstep)
    std::uint32_t hostMaxUs;
    std::uint32_t cpuOverBudget;  // TaskStats::cpuOverBudget (0 unless cpuTimed)
    bool cpuTimed;
};

struct HousekeepingMsg {
    static constexpr core::MsgId kMsgId = ids::kHousekeeping;

    std::int64_t timeNs;              // executive clock at collection
    std::uint64_t framesRun;
    std::uint32_t frameOverruns;
    std::uint32_t framesSkipped;
    std::uint32_t frameBusyLastUs;
    std::uint32_t frameBusyMaxUs;
    std::uint32_t frameLatenessMaxUs;  // worst frame-start jitter
    std::uint32_t busPublished;
    std::uint32_t busDelivered;
    std::uint32_t busDropped;
    std::uint32_t busRejectedTooLarge;
    std::uint32_t busNoSubscribers;
    std::uint32_t eventsTotal;
    std::uint32_t eventsLost;
    std::uint32_t eventsBySeverity[core::kSeverityCount];
    std::uint32_t housekeepingCount;   // HK packets produced since start
    std::uint8_t taskCount;
    std::uint8_t pad[7];
    TaskTimingTlm tasks[core::kMaxTasks];
};
static_assert(sizeof(HousekeepingMsg) <= core::kBusMaxPayload, "housekeeping must fit one bus message");

}  // namespace rse::msg

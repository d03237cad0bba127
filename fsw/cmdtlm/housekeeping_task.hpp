// Collects the executive's, bus's and event log's counters into a
// HousekeepingMsg and publishes it (1 Hz in the rate-group table).
#pragma once

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/housekeeping_msg.hpp"

namespace rse::cmdtlm {

class HousekeepingTask final : public core::Task {
public:
    HousekeepingTask(const core::Executive& executive, core::SoftwareBus& bus,
                     const core::EventLog& events)
        : executive_(executive), bus_(bus), events_(events) {}

    void run(const core::FrameContext& frame) override;

    // Fills msg from the current counters (also used by tests).
    void collect(msg::HousekeepingMsg* msg, core::TimeNs now) const;
    std::uint32_t published() const { return published_; }

private:
    const core::Executive& executive_;
    core::SoftwareBus& bus_;
    const core::EventLog& events_;
    std::uint32_t published_ = 0;
    msg::HousekeepingMsg message_{};  // reused; kept out of the task's stack
};

}  // namespace rse::cmdtlm

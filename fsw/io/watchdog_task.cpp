#include "fsw/io/watchdog_task.hpp"

#include "fsw/io/io_events.hpp"

namespace rse::io {

namespace {
constexpr std::uint16_t kPipeDepth = 4;  // the health task publishes on change and at 1 Hz; this runs at 10 Hz

std::uint64_t stallMask() {
    std::uint64_t mask = 0;
    for (std::uint32_t i = 0; i < msg::fault::kTaskStalledCount; ++i) {
        mask |= std::uint64_t{1} << (msg::fault::kTaskStalled + i);
    }
    return mask;
}
}  // namespace

WatchdogTask::WatchdogTask(core::SoftwareBus& bus, core::EventLog& events)
    : events_(events),
      input_(bus, events, core::InputPipeConfig{"watchdog", kPipeDepth, events::kBusMessageMalformed, "watchdog"}) {}

core::Status WatchdogTask::init() {
    core::Status s = input_.create();
    return core::isOk(s) ? input_.route<&WatchdogTask::takeFaultStatus>(this) : s;
}

void WatchdogTask::takeFaultStatus(const msg::FaultStatusMsg& status) {
    latest_ = status;
    latestAt_ = now_;
}

void WatchdogTask::run(const core::FrameContext& frame) {
    const core::TimeNs now = frame.actualStart;
    now_ = now;
    (void)input_.drain();
    const bool fresh = latestAt_ >= 0 && now - latestAt_ <= kFaultStatusFreshNs;
    const std::uint64_t stalled = latest_.activeMask & stallMask();
    const bool live = fresh && stalled == 0;
    if (live != feeding_) {
        if (live) {
            events_.report(events::kWatchdogFeeding, core::Severity::kInfo, "app: watchdog fed again: every task live");
        } else {
            events_.report(events::kWatchdogWithheld, core::Severity::kCritical,
                           "app: watchdog NOT fed: %s (stall faults 0x%llx): the computer restarts at its timeout",
                           fresh ? "a task stalled" : "no fresh fault status",
                           static_cast<unsigned long long>(stalled >> msg::fault::kTaskStalled));
        }
        feeding_ = live;
    }
    if (!live) {
        ++withheld_;
        return;
    }
    if (watchdog_ != nullptr && core::isOk(watchdog_->feed())) {
        ++feeds_;
    }
}

}  // namespace rse::io

#include "fsw/app/watchdog_task.hpp"

#include "fsw/app/app_events.hpp"

namespace rse::app {

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

core::Status WatchdogTask::init() {
    core::Status s = bus_.createPipe("watchdog", kPipeDepth, &pipe_);
    return core::isOk(s) ? bus_.subscribe(pipe_, msg::ids::kFaultStatus) : s;
}

void WatchdogTask::run(const core::FrameContext& frame) {
    const core::TimeNs now = frame.actualStart;
    for (std::uint16_t i = 0; i < kPipeDepth && core::isOk(bus_.receive(pipe_, &inbox_)); ++i) {
        if (core::isOk(inbox_.decode(&latest_))) {
            latestAt_ = now;
        } else if (core::isReportableOccurrence(++malformed_)) {
            events_.report(events::kBusMessageMalformed, core::Severity::kError,
                           "app: watchdog ignored a malformed fault status (%u so far)", static_cast<unsigned>(malformed_));
        }
    }
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

}  // namespace rse::app

// Feeds the computer's watchdog (hal::Watchdog; rse-fsw --watchdog DEV) at
// 10 Hz, but only while every flight task is live: the health task's latest
// FaultStatusMsg is fresh (it publishes at least once a second, so a stalled
// health task stops the feed too) and shows no task-stalled fault (ids 20..35).
// A hung rse-fsw (no frame runs, so this task does not either), a crash, or a
// task stalled for longer than fault protection's restarts and the watchdog's
// timeout together, restarts the computer, as on a flight computer. A clean
// stop disarms the device (magic close) so it does not.
// Feeding stopped and resumed are evented (222 critical, 223); a fault status
// that does not decode is counted and evented (211) by its input pipe.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "hal/watchdog/watchdog.hpp"

namespace rse::io {

// A FaultStatusMsg older than this no longer vouches for the tasks.
constexpr core::TimeNs kFaultStatusFreshNs = 2 * core::kNsPerSec;

class WatchdogTask final : public core::Task {
public:
    WatchdogTask(core::SoftwareBus& bus, core::EventLog& events);

    // nullptr: no watchdog attached; the task still judges liveness (telemetry, tests).
    void attach(hal::Watchdog* watchdog) { watchdog_ = watchdog; }
    core::Status init();
    void run(const core::FrameContext& frame) override;

    bool feeding() const { return feeding_; }
    std::uint32_t feeds() const { return feeds_; }
    std::uint32_t withheld() const { return withheld_; }
    std::uint32_t malformed() const { return input_.malformed(); }

private:
    void takeFaultStatus(const msg::FaultStatusMsg& status);

    core::EventLog& events_;
    core::InputPipe input_;
    hal::Watchdog* watchdog_ = nullptr;
    core::TimeNs now_ = 0;  // this run's frame start, for the messages it takes
    msg::FaultStatusMsg latest_{};
    core::TimeNs latestAt_ = -1;
    bool feeding_ = true;
    std::uint32_t feeds_ = 0;
    std::uint32_t withheld_ = 0;
};

}  // namespace rse::io

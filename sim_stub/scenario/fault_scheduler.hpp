// Applies a scenario's fault schedule: stepped with the time, it calls the
// FaultTarget hooks for every event whose time has come, in time order (events
// at the same time in the order of the file).
//
// Each FaultSpec expands into one or two events at construction: a start, and
// for interval faults an end (heartbeat back, dropout over, babbling stops) or a
// restart (crashes with a restart time). The event list is sorted once there
// (stable), so step() only walks forward: no allocation, no exceptions.
#pragma once

#include <cstddef>
#include <vector>

#include "fsw/core/clock.hpp"
#include "sim_stub/scenario/fault_target.hpp"
#include "sim_stub/scenario/scenario.hpp"

namespace rse::sim {

enum class FaultAction : std::uint8_t {
    kDegradeMotor,
    kFailMotor,
    kHeartbeatLossStart,
    kHeartbeatLossEnd,
    kCrashDrive,
    kRestartDrive,
    kDropoutStart,
    kDropoutEnd,
    kCrashDevice,
    kRestartDevice,
    kImuBiasStep,
    kBusFault,
    kBabbleStart,
    kBabbleEnd,
    kPositionFixOutlier,
    kOverheatMotor,
    kDriveFault,
    kSlide,
    kTaskStallStart,
    kTaskStallEnd,
    kInstrumentFailStart,
    kInstrumentFailEnd,
};

struct FaultEvent {
    core::TimeNs at = 0;
    FaultAction action = FaultAction::kFailMotor;
    std::size_t spec = 0;  // index into the scheduler's copy of the schedule
};

class FaultScheduler {
public:
    FaultScheduler(const std::vector<FaultSpec>& faults, FaultTarget& target);

    // Fires every event with at <= now not fired yet.
    void step(core::TimeNs now);

    std::size_t eventCount() const { return events_.size(); }
    std::size_t fired() const { return next_; }
    // Time of the next event, kNever when all have fired.
    core::TimeNs nextAt() const { return next_ < events_.size() ? events_[next_].at : kNever; }
    const FaultEvent& event(std::size_t index) const { return events_[index]; }

private:
    void fire(const FaultEvent& event);

    FaultTarget& target_;
    std::vector<FaultSpec> specs_;
    std::vector<FaultEvent> events_;
    std::size_t next_ = 0;
};

}  // namespace rse::sim

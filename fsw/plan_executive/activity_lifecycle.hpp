// Dispatch and the activities' lifecycle (docs/plan_executive.md "Each run",
// "Dispatch to the devices and the deliberative layer"). Each run while the
// plan dispatches: one dispatcher tick at the plan time, its Start commands
// to the devices (956) and its Cancels (961; a timeout past the ub: late,
// 959), a running wait or communicate completed at its lb, and the plan
// complete when every event executed (964). The devices' reports go to the
// dispatcher: completed (957; before its end's earliest: early, held to it,
// 958; after its end's latest: late, 959; an extended activity says how much
// later, 977) or failed (960; an instrument giving up at the ub is late, 959,
// and the regeneration's reason late). The dispatch stopped (a new plan,
// abort, the operator called): the running activities cancelled. Counts
// started, completed, early, late and failed for PLAN_EXEC.
#pragma once

#include <cstdint>

#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/plan_executive/activity_devices.hpp"
#include "fsw/plan_executive/executive_context.hpp"
#include "fsw/plan_executive/plan_extension.hpp"

namespace rse::plan_executive {

struct ActivityCounters {
    std::uint32_t started = 0;
    std::uint32_t completed = 0;
    std::uint32_t early = 0;
    std::uint32_t late = 0;
    std::uint32_t failed = 0;
};

class ActivityLifecycle {
public:
    ActivityLifecycle(ExecutiveContext& ctx, ActivityDevices& devices, PlanExtension& extension)
        : ctx_(ctx), devices_(devices), extension_(extension) {}

    // One run's dispatch at nowMs: the tick and its commands, the waits and
    // communicates due. True when the plan completed in it (964).
    bool advance(std::int32_t nowMs);
    // An instrument's status: for each science activity running on it, the
    // pending follow-on's answer, then its completion or failure.
    void takeInstrument(const msg::InstrumentStatusMsg& m);
    // The deliberative layer's status: the drive under way completed or failed.
    void takePlanStatus(const msg::PlanStatusMsg& m);
    // Running activity a is done, or failed (late: the instrument gave up at
    // its ub: counted and evented late, 959, the dispatcher told failed()).
    void completed(std::uint16_t a);
    void failed(std::uint16_t a, const char* why, bool late = false);
    // Its device stops what the plan no longer runs (a pending follow-on dropped).
    void cancel(std::uint16_t a);
    // Stops dispatch: the check dropped, running activities cancelled.
    void cancelDispatch();
    // A new plan adopted: no command, drive or follow-on of the old one is followed.
    void newPlan();
    // An instrument gave up at an activity's ub since the last call: the
    // regeneration is for lateness. Cleared by the call.
    bool takeLateByDevice();
    const ActivityCounters& counters() const { return counters_; }

private:
    void handleOutput(const DispatchOutput& out, std::int32_t nowMs);
    void start(std::uint16_t a, std::int32_t nowMs);
    void stop(std::uint16_t a, std::int32_t nowMs);
    void completeTimedActivities(std::int32_t nowMs);
    void reportCompletion(std::uint16_t a, std::int32_t startMs, std::int32_t nowMs);

    ExecutiveContext& ctx_;
    ActivityDevices& devices_;
    PlanExtension& extension_;
    DispatchOutput out_{};
    ActivityCounters counters_{};
    bool lateByDevice_ = false;
};

}  // namespace rse::plan_executive

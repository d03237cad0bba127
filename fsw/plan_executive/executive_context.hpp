// What the plan executive's parts share (docs/plan_executive.md "Parts"): the
// bus and the event log, this run's time, the two plans (the one running and
// the one staged), the dispatcher, where the executive stands, what the
// selector and the dispatcher's check are doing, and whether the status
// changed since it was last published. The task owns it (static storage in
// FswApp, inside the task); each part holds a reference to it and owns the
// rest of its own state.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/plan_dispatcher.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

// What the selector is doing for the executive: nothing, a new plan's
// selection, or a regeneration's. One at a time.
enum class SelectionJob : std::uint8_t { kNone, kSelectNew, kRegenerate };

struct ExecutiveContext {
    ExecutiveContext(core::SoftwareBus& busIn, core::EventLog& eventsIn) : bus(busIn), events(eventsIn) {}

    // The plan running (or the one last run).
    const Tpn& plan() const { return tpn[active]; }
    // Where a new plan is parsed and selected while the one running runs on.
    Tpn& staged() { return tpn[1 - active]; }
    // ms since the plan running's start (event 0), within [0, kMaxBoundMs].
    std::int32_t planMs() const;
    // A plan dispatching or regenerating: a refusal leaves it running.
    bool planRunning() const {
        return planLoaded &&
               (state == msg::PlanExecutiveState::kDispatching || state == msg::PlanExecutiveState::kRegenerating);
    }

    core::SoftwareBus& bus;
    core::EventLog& events;
    core::TimeNs now = 0;          // this run's scheduled start
    core::TimeNs planStartNs = 0;  // the plan running's event 0
    // Plans: tpn[active] running (or last run), the other staged.
    Tpn tpn[2];
    std::size_t active = 0;
    bool planLoaded = false;  // tpn[active] is a plan the dispatcher has (had) loaded
    bool goalPlan = false;    // tpn[active] was made from the goal list
    PlanDispatcher dispatcher;
    msg::PlanExecutiveState state = msg::PlanExecutiveState::kIdle;
    SelectionJob job = SelectionJob::kNone;
    bool checking = false;  // the dispatcher's sliced check is under way
    bool changed = true;    // the status is published at the end of the run
    // Messages the bus refused (status, safe request, goal, instrument
    // command): one count, so the status's throttled event counts them all.
    std::uint32_t publishFailures = 0;
};

// A regeneration started in the middle of a part's work (an extension
// committed leaves the network out of its range): the task hands it to the
// selection.
class RegenerationStarter {
public:
    virtual void startRegeneration(std::int32_t nowMs) = 0;

protected:
    ~RegenerationStarter() = default;
};

}  // namespace rse::plan_executive

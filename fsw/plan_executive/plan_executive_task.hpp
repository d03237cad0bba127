// The plan executive task (docs/plan_executive.md "The task", "Parts"):
// mission plans from the ground to a running plan. A shell over its parts:
// it creates the pipes and routes each input to its part, and each run does
// the work in this order:
//
//   1. the plan commands' PlanCommandMsg ("plan_exec", at most
//      kPipeDepth): PLAN_LOAD chunks to the upload (PlanUpload), PLAN_START
//      (the assembled text's length and CRC-32) and PLAN_SHORT to a new
//      plan's parse and selection (PlanAdoption; busy while a selection is
//      under way), PLAN_ABORT, PLAN_EXTEND (PlanExtension);
//   2. what the others say ("plan_exec_in", at most kStatusPipeDepth): drive
//      modes and instrument states to the components (ComponentStates), the
//      instruments' and the deliberative layer's reports to the activities
//      they concern (ActivityDevices, ActivityLifecycle), the operator's goal
//      list to GoalPlans;
//   3. a goal list's new revision becomes a plan when no selection runs;
//   4. a selection under way (a new plan's or a regeneration's) steps, and
//      when it ends is adopted or refused; a dispatcher check under way steps;
//   5. dispatching: the components checked against the activities not yet
//      done (PlanRegeneration: failed, deprecated, regenerate), one
//      dispatcher tick with its starts, cancels and completions
//      (ActivityLifecycle), the plan complete, or regenerated when the
//      dispatcher holds (a goal plan stops instead: GoalPlans);
//   6. PlanExecutiveStatusMsg (PlanStatusReport) on any change and every
//      kStatusPeriodRuns runs.
//
// States (msg::PlanExecutiveState): idle -> selecting (a plan's selection
// with none running) -> dispatching -> complete; dispatching -> regenerating
// -> dispatching (a regeneration adopted); dispatching or regenerating ->
// failed (no method left: the operator called, SafeRequestMsg kPlanNoMethod;
// or a goal plan's drive failed); any -> idle on PLAN_ABORT or an empty goal
// list stopping a goal plan. A new plan is staged while the plan running keeps running; anything
// refused on the way leaves the plan running as it was. Every step is an
// event (plan_executive_events.hpp, 950-989).
//
// Work per run (10 Hz, deliberative rate group, before the deliberative
// task): at most kPipeDepth + kStatusPipeDepth messages (one parse each at
// most: linear in the text, under 16 KiB); kSelectionUnitsPerRun of
// MethodSelector::step (about 0.2-0.65 ms on the development host);
// kCheckUnitsPerRun rows of the dispatcher's sliced STN check (each row n
// min-adds: about 0.75 ms for 256 events); one dispatcher tick (O(n^2) plus
// at most 8 event executions) and at most one completion per running
// wait/communicate activity.
//
// Memory: sizeof 447 936 B on x86-64: two Tpns (47 024 B each) and the
// dispatcher (its STN nearly all of it) in the context, the selector, the
// upload's 16 KiB text buffer and the two pipes: static storage in FswApp,
// never a stack; no heap.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/activity_devices.hpp"
#include "fsw/plan_executive/activity_lifecycle.hpp"
#include "fsw/plan_executive/component_states.hpp"
#include "fsw/plan_executive/executive_context.hpp"
#include "fsw/plan_executive/goal_plan.hpp"
#include "fsw/plan_executive/plan_adoption.hpp"
#include "fsw/plan_executive/plan_extension.hpp"
#include "fsw/plan_executive/plan_regeneration.hpp"
#include "fsw/plan_executive/plan_status.hpp"
#include "fsw/plan_executive/plan_upload.hpp"

namespace rse::plan_executive {

class PlanExecutiveTask final : public core::Task, private RegenerationStarter {
public:
    static constexpr std::uint32_t kSelectionUnitsPerRun = PlanAdoption::kSelectionUnitsPerRun;
    static constexpr std::uint32_t kCheckUnitsPerRun = PlanAdoption::kCheckUnitsPerRun;
    static constexpr std::uint32_t kStatusPeriodRuns = 10;  // 1 Hz at 10 Hz
    // Pipe depths: the bus's 256 queue slots are nearly all taken (a test
    // probe and rse-demo's pipe included). Commands: 12 between two runs (the
    // command task executes up to 20 in 100 ms: a burst of chunks beyond 12 is
    // lost and shows as a gap). Status: drive modes (10 Hz), the instruments
    // (on change, 1 Hz), the deliberative status and goal lists.
    static constexpr std::uint16_t kPipeDepth = 12;
    static constexpr std::uint16_t kStatusPipeDepth = 12;
    static constexpr std::uint32_t kGoalRevisionBase = ActivityDevices::kGoalRevisionBase;
    static constexpr std::size_t kGoalPlanTextBytes = plan_executive::kGoalPlanTextBytes;
    static constexpr std::uint32_t kMaxExtendMs = PlanExtension::kMaxExtendMs;

    PlanExecutiveTask(core::SoftwareBus& bus, core::EventLog& events);

    // Creates the pipes and routes their inputs; a refusal is evented (969)
    // and returned, and run() then does nothing.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    // Queries (tests, the app's summary).
    msg::PlanExecutiveState state() const { return ctx_.state; }
    const msg::PlanExecutiveStatusMsg& status() const { return status_.message(); }
    const Tpn& plan() const { return ctx_.plan(); }
    const PlanDispatcher& dispatcher() const { return ctx_.dispatcher; }
    const Selection& selection() const { return adoption_.selection(); }
    std::size_t uploadLength() const { return upload_.length(); }
    // Inputs refused on either pipe (did not decode, or out of range).
    std::uint32_t malformed() const { return commandPipe_.malformed() + inputs_.malformed(); }

private:
    // The pipes' handlers: a message out of range is refused (malformed).
    core::Status takeCommand(const msg::PlanCommandMsg& m);
    core::Status takeInstrument(const msg::InstrumentStatusMsg& m);
    core::Status takeDriveModes(const msg::DriveModesMsg& m);
    void takePlanStatus(const msg::PlanStatusMsg& m);
    core::Status takeGoalList(const msg::GoalListMsg& m);
    void takeChunk(const msg::PlanCommandMsg& m);
    void startUpload(const msg::PlanCommandMsg& m);
    void startShort(const msg::PlanCommandMsg& m);
    // A dispatcher check or a new plan's or a regeneration's selection would run: dispatch waits.
    bool dispatchDue() const;
    void dispatch();
    void startRegeneration(std::int32_t nowMs) override;
    void publishStatus();

    ExecutiveContext ctx_;
    PlanUpload upload_;
    ComponentStates components_;
    ActivityDevices devices_;
    PlanExtension extension_;
    ActivityLifecycle lifecycle_;
    PlanRegeneration regeneration_;
    PlanAdoption adoption_;
    GoalPlans goals_;
    PlanStatusReport status_;
    // The plan commands' PlanCommandMsg ("plan_exec"), and what the
    // devices, mode estimation, the deliberative layer and the operator's goal
    // list say ("plan_exec_in").
    core::InputPipe commandPipe_;
    core::InputPipe inputs_;
    bool ready_ = false;
    std::uint32_t runs_ = 0;
};

}  // namespace rse::plan_executive

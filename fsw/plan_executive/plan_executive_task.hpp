// The plan executive task (docs/plan_executive.md "The task"): mission plans
// from the ground to a running plan. It takes the command handlers'
// PlanCommandMsg (PLAN_LOAD chunks into a static 16 KiB text buffer,
// PLAN_START with the assembled text's length and CRC-32, PLAN_SHORT, PLAN_ABORT,
// PLAN_EXTEND),
// parses the plan into a Tpn, selects its methods (MethodSelector, sliced),
// checks and dispatches it (PlanDispatcher, sliced check then one tick a
// run), regenerates it when the dispatcher asks (late, missed window,
// early-inconsistent, failed), and calls the operator (SafeRequestMsg,
// CallHomeReason::kPlanNoMethod) when no method remains. Every step is an
// event (plan_executive_events.hpp, 950-989); PlanExecutiveStatusMsg says
// where it stands, on change and every kStatusPeriodRuns runs.
//
// A new plan is staged: the text is parsed into the Tpn not in use and
// selected there while the plan running keeps running; only a plan with a
// valid selection replaces it (its running activities cancelled). Anything
// refused on the way (a chunk with a gap or past the buffer, a bad length or
// CRC, a parse error, no valid selection) is evented with its reason and
// counted, and leaves the plan running as it was. One selection at a time:
// a PLAN_START or PLAN_SHORT while a new plan's selection or a regeneration
// is under way is refused (busy).
//
// Activities (docs/plan_executive.md "Dispatch to the devices"). Start(drive):
// a PlanGoalMsg of one goal (the activity's point, the operator's risk bound)
// for the deliberative layer; done when its PlanStatusMsg reports that goal
// list complete, failed on a call home or when another goal list replaces
// it. Start(sample / dig / image): an InstrumentCommandMsg to the grinder /
// camera with a fresh command id and the activity's ub as max duration; done
// on the instrument's status done for that id; failed on failed, refused or
// offline. Wait and communicate complete at their lb. Cancel: an empty goal
// list, or the instrument's cancel.
//
// Opportunistic science (PLAN_EXTEND, docs/plan_executive.md). A follow-on
// request names a running science activity and asks for extra time. It is
// refused (event 976, counted, the plan untouched) when no activity has that
// name, a selection, regeneration or check is under way or another extension
// awaits its instrument (busy), or the dispatcher's check refuses it (not
// running, not science, beyond its ub, a later bound of the plan would break:
// PlanDispatcher::checkExtension, with the end expected from the instrument's
// progress). Else the instrument is sent an extend (a new command id
// continuing the running one, the extra work; event 974) and, when its status
// names the new id, the extension is committed in the network (event 975):
// the activity completes when the extended work is done (event 977 says how
// much later). The instrument refusing it is a refusal too (the activity goes
// on as it was).
//
// Components. Drive modes (DriveModesMsg: nominal ok, degraded degraded,
// failed failed, unknown degraded) and the instruments (offline, or failed
// with a fault code: failed; else ok) are the SelectionInput's components.
// When an activity of the selection not yet done asks what a component no
// longer is: a running one is failed(), every option with a waiting one is
// deprecated, and the plan is regenerated from where it stands (reason
// component failed, event 962/963 with the costs); no method left: operator.
// While a regeneration's selection runs, the dispatcher is not ticked (no
// activity starts from the old selection); completions are still taken.
//
// Work per run (10 Hz, deliberative rate group, before the deliberative
// task): at most kPipeDepth messages (one parse each at most: linear in the
// text, under 16 KiB); kSelectionUnitsPerRun of MethodSelector::step (about
// 0.2-0.65 ms on the development host); kCheckUnitsPerRun rows of the
// dispatcher's sliced STN check (each row n min-adds: about 0.75 ms for 256
// events); one dispatcher tick (O(n^2) plus at most 8 event executions) and
// at most one completion per running wait/communicate activity.
//
// Memory: sizeof 448 320 B on x86-64: two Tpns (47 024 B each), the
// selector, the dispatcher (its STN nearly all of it)
// and the text buffer: static storage in FswApp, never a stack; no heap.
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
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/plan_dispatcher.hpp"
#include "fsw/plan_executive/plan_parser.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

class PlanExecutiveTask final : public core::Task {
public:
    static constexpr std::uint32_t kSelectionUnitsPerRun = 150000;
    static constexpr std::uint32_t kCheckUnitsPerRun = 4096;
    static constexpr std::uint32_t kStatusPeriodRuns = 10;  // 1 Hz at 10 Hz
    // Pipe depths: the bus's 256 queue slots are nearly all taken (a test
    // probe and rse-demo's pipe included). Commands: 12 between two runs (the
    // command task executes up to 20 in 100 ms: a burst of chunks beyond 12 is
    // lost and shows as a gap). Status: drive modes (10 Hz), the instruments
    // (on change, 1 Hz), the deliberative status and goal lists.
    static constexpr std::uint16_t kPipeDepth = 12;
    static constexpr std::uint16_t kStatusPipeDepth = 12;
    static constexpr std::uint32_t kGoalRevisionBase = 0x80000000U;
    // A goal plan's text: a header and "end" (32 B), then a goal's event line
    // (at most 24 B) and drive line (at most 87 B: coordinates up to 100 km
    // to the mm and " within 50.000"); a longer text is refused (overflow),
    // never cut.
    static constexpr std::size_t kGoalPlanTextBytes = 32 + msg::kMaxGoals * (24 + 88);
    // The most extra time one PLAN_EXTEND may ask: the instrument's field (6553.5 s).
    static constexpr std::uint32_t kMaxExtendMs = 6553500;

    PlanExecutiveTask(core::SoftwareBus& bus, core::EventLog& events);

    // Creates the pipe and subscribes; a refusal is evented (969) and
    // returned, and run() then does nothing.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    // Queries (tests, the app's summary).
    msg::PlanExecutiveState state() const { return state_; }
    const msg::PlanExecutiveStatusMsg& status() const { return status_; }
    const Tpn& plan() const { return tpn_[active_]; }
    const PlanDispatcher& dispatcher() const { return dispatcher_; }
    const Selection& selection() const { return selection_; }
    std::size_t uploadLength() const { return uploadLength_; }
    // Inputs refused on either pipe (did not decode, or out of range).
    std::uint32_t malformed() const { return commands_.malformed() + inputs_.malformed(); }

private:
    enum class Job : std::uint8_t { kNone, kSelectNew, kRegenerate };

    // The pipes' handlers: a message out of range is refused (malformed).
    core::Status takeCommand(const msg::PlanCommandMsg& m);
    core::Status takeInstrument(const msg::InstrumentStatusMsg& m);
    core::Status takeDriveModes(const msg::DriveModesMsg& m);
    void takePlanStatus(const msg::PlanStatusMsg& m);
    core::Status takeGoalList(const msg::GoalListMsg& m);
    void onInstrument(const msg::InstrumentStatusMsg& m);
    void onDriveModes(const msg::DriveModesMsg& m);
    void onPlanStatus(const msg::PlanStatusMsg& m);
    void startActivity(std::uint16_t a);
    void cancelActivity(std::uint16_t a);
    // A drive activity's goal (kNoIndex: none, the drive cancelled).
    void publishGoal(std::uint16_t a);
    void commandInstrument(std::uint16_t a, msg::InstrumentAction action);
    // Completion / failure of a running activity reported by a device.
    void deviceCompleted(std::uint16_t a);
    // late: the instrument gave up at the activity's ub (its max duration):
    // counted and evented as late (959), the dispatcher told failed().
    void deviceFailed(std::uint16_t a, const char* why, bool late = false);
    bool askHolds(const Condition& c) const;
    bool checkComponents(std::int32_t nowMs);
    void handle(const msg::PlanCommandMsg& m);
    // PLAN_EXTEND: judged, then the follow-on sent to the instrument.
    void extendActivity(const msg::PlanCommandMsg& m);
    // When the running science activity a would end without an extension:
    // start + the instrument's elapsed / progress for its command, else its
    // lb; at least nowMs.
    std::int32_t expectedOwnEndMs(std::uint16_t a, std::int32_t nowMs) const;
    // The pending follow-on's answer in the instrument's status (taken, or refused).
    void answerExtension(std::uint16_t a, const msg::InstrumentStatusMsg& m);
    // Activity a stopped running while its follow-on awaited an answer.
    void dropExtension(std::uint16_t a);
    void refuseExtension(msg::PlanExtensionRefusal why, const char* name, std::int32_t extraMs, const char* detail);
    void loadChunk(const msg::PlanCommandMsg& m);
    void startUpload(const msg::PlanCommandMsg& m);
    void beginNewPlan(const char* text, std::size_t length, bool fromGoals);
    void onGoalList(const msg::GoalListMsg& m);
    void beginGoalPlan();
    void stopGoalPlan();
    // Stops dispatch: the check dropped, running activities cancelled.
    void cancelDispatch();
    void refuse(msg::PlanRefusal why, core::EventId id, const char* detail);
    // PLAN_START's length or CRC (what) not the text's.
    void refuseStart(msg::PlanRefusal why, const char* what, std::uint32_t said, std::uint32_t found);
    void abortPlan(bool superseded);
    void stepSelection();
    void adoptNewPlan(const SelectionResult& r);
    void adoptRegeneration(const SelectionResult& r);
    void stepCheck();
    void dispatch();
    void completeTimedActivities(std::int32_t nowMs);
    void startRegeneration(std::int32_t nowMs);
    void handleOutput(const DispatchOutput& out, std::int32_t nowMs);
    void callOperator(const char* why);
    std::int32_t planMs() const;
    void fillStatus();
    void publishStatus();

    core::SoftwareBus& bus_;
    core::EventLog& events_;
    // The command handlers' PlanCommandMsg ("plan_exec"), and what the
    // devices, mode estimation, the deliberative layer and the operator's goal
    // list say ("plan_exec_in").
    core::InputPipe commands_;
    core::InputPipe inputs_;
    bool ready_ = false;
    core::TimeNs now_ = 0;
    std::uint32_t runs_ = 0;
    bool changed_ = true;

    // The upload: text_[0 .. uploadLength_), open since a chunk at offset 0,
    // spoiled (uploadError_) by a gap or an overflow until the next offset 0.
    char text_[kMaxPlanText] = {};
    std::size_t uploadLength_ = 0;
    bool uploadOpen_ = false;
    msg::PlanRefusal uploadError_ = msg::PlanRefusal::kNone;
    char shortText_[msg::kPlanChunkBytes] = {};
    std::size_t stagedLength_ = 0;

    // Plans: tpn_[active_] running (or last run), the other staged.
    Tpn tpn_[2];
    std::size_t active_ = 0;
    MethodSelector selector_;
    SelectionParams params_{};
    SelectionInput newInput_{};    // a new plan's selection
    SelectionInput input_{};       // the selection in force was made under this
    SelectionInput regenInput_{};  // a regeneration under way
    Selection selection_{};
    SelectionStatus selectionStatus_ = SelectionStatus::kRunning;
    double cost_ = 0.0;
    double costBefore_ = 0.0;
    Job job_ = Job::kNone;
    std::uint32_t selectionRuns_ = 0;
    ComponentState components_[kComponentCount] = {};
    // Options the executive deprecated (a component they ask failed; stage 2).
    bool deprecated_[kMaxChoices][kMaxOptions] = {};

    // Devices: the instruments' latest status, the command id of each science
    // activity's command, the drive activity whose goal the deliberative layer has.
    msg::InstrumentStatusMsg instruments_[msg::kInstrumentCount] = {};
    std::uint16_t commandId_[kMaxActivities] = {};
    std::uint16_t nextCommandId_ = 0;
    std::uint16_t driveActivity_ = kNoIndex;
    std::uint32_t driveRevision_ = 0;
    bool driveAdopted_ = false;   // the deliberative layer reported working on driveRevision_
    std::uint32_t goalRevision_ = kGoalRevisionBase;
    double riskBound_ = 1e-3;     // the operator's, from the last GoalListMsg
    msg::PlanGoalMsg goal_{};
    // The operator's goal list (GoalListMsg) and the plan made from it.
    msg::GoalListMsg goalList_{};
    bool goalListSeen_ = false;
    bool goalsPending_ = false;    // a new revision to turn into a plan when no selection runs
    bool stagedGoalPlan_ = false;  // the plan being selected was made from the goal list
    bool goalPlan_ = false;        // tpn_[active_] was made from the goal list
    char goalText_[kGoalPlanTextBytes] = {};
    std::uint32_t goalPlans_ = 0;
    msg::InstrumentCommandMsg instrumentCommand_{};
    bool regenerateForComponent_ = false;
    bool lateByDevice_ = false;  // an instrument gave up at an activity's ub: the regeneration is for lateness
    std::uint16_t componentActivity_ = kNoIndex;  // the first activity a component failure hit

    // The follow-on sent and not yet answered (activity kNoIndex: none).
    struct PendingExtension {
        std::uint16_t activity = kNoIndex;
        std::uint16_t commandId = 0;  // the follow-on's id
        std::int32_t extraMs = 0;
        std::int32_t ownEndMs = 0;    // as expected at the request
        std::int32_t requestMs = 0;   // plan time of the request
    };
    PendingExtension pending_{};
    std::int32_t endBeforeExtensionMs_[kMaxActivities] = {};  // expected end at the first extension (event 977)
    std::uint32_t extensionsAccepted_ = 0;
    std::uint32_t extensionsRefused_ = 0;
    msg::PlanExtensionRefusal lastExtensionRefusal_ = msg::PlanExtensionRefusal::kNone;

    PlanDispatcher dispatcher_;
    ActivityRecord carried_{};
    DispatchOutput out_{};
    bool checking_ = false;
    bool planLoaded_ = false;  // tpn_[active_] is a plan the dispatcher has (had) loaded
    core::TimeNs planStartNs_ = 0;
    msg::PlanExecutiveState state_ = msg::PlanExecutiveState::kIdle;

    // Counters and the last refusal / regeneration.
    std::uint32_t plansAccepted_ = 0;
    std::uint32_t plansRefused_ = 0;
    std::uint32_t regenerations_ = 0;
    std::uint32_t started_ = 0;
    std::uint32_t completed_ = 0;
    std::uint32_t early_ = 0;
    std::uint32_t late_ = 0;
    std::uint32_t failed_ = 0;
    std::uint32_t operatorCalls_ = 0;
    std::uint32_t publishFailures_ = 0;
    msg::PlanRefusal lastRefusal_ = msg::PlanRefusal::kNone;
    ParseResult lastParse_{};
    msg::PlanRegeneration lastRegeneration_ = msg::PlanRegeneration::kNone;
    std::uint8_t callHomeReason_ = 0;
    msg::PlanExecutiveStatusMsg status_{};
};

}  // namespace rse::plan_executive

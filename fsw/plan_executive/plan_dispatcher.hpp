// Plan dispatch: the execution engine of a selected plan (docs/plan_executive.md
// "Dispatch"). Pure logic: no bus, no clock read. The plan executive task
// drives it each cycle with the time in ms since the plan's start (event 0,
// at 0), turns its commands into activity commands (drive, sample, image...)
// and tells it when an activity completes or fails.
//
// The network. start() loads the selection's STN (loadStn with where
// execution stands, SelectionInput "Regeneration": the network the selector
// judged) into its own Stn and checks it fully; executing an event is then an
// O(n^2) Stn::execute(), never a full recomputation. The closed network is
// dispatchable: events executed in any order within their windows, each
// propagated, never make a later event impossible.
//
// Rules, each tick(nowMs):
//   1. A running activity past its ub (nowMs - start > ub) or whose to-event's
//      latest time has passed is late: Cancel, timed out, regeneration (kLate).
//   2. An event with no existing incoming activity is executed at nowMs when
//      every event that must precede it (d(e, p) <= 0: t_p <= t_e; of two
//      events pinned together, the lower index first) is executed and nowMs
//      has reached its window's earliest; its latest passed unexecuted:
//      regeneration (kMissedWindow). An event whose existing incoming
//      activities are all done is executed at max(nowMs, earliest) (after a
//      regeneration that carried them over, or a completion that could not
//      execute it). At most kMaxExecutionsPerTick events a tick (each an
//      O(n^2) update); the others wait for the next tick.
//   3. A waiting activity whose from-event is executed (and nowMs has reached
//      that event's time) is started: Start(activity).
// completed(): the activity is done; when its to-event's other existing
// incoming activities are done too, the event is executed at
// max(nowMs, earliest): a completion before the earliest is EARLY (counted,
// reported in the output) and the event is held to its earliest (the
// schedule tightened); after the latest it is late (regeneration, kLate).
// failed(): the activity failed (an instrument fault): regeneration
// (kActivityFailed).
// Once regeneration is needed the dispatcher holds: no event is executed by
// tick() and nothing is started; late running activities are still
// cancelled, and completions are still recorded (and executed when
// consistent), so the executive re-selects from where execution stands.
//
// Regeneration. regenerationInput() writes where execution stands into a
// SelectionInput (executed times, not before = now, and the options already
// under way forced by deprecating their choices' other options); the
// executive re-selects and restarts this dispatcher with start(...,
// &carried), carried a copy of activities() taken before: activities done or
// running in the previous dispatch that exist in the new selection keep their
// state and times (a running one is not restarted); a running one the new
// selection drops is cancelled at the first tick (kCancelled, Cancel); every
// other activity starts afresh (a failed or timed-out activity the new
// selection keeps is run again). The plan must be the same plan.
//
// Extension (opportunistic science). checkExtension() judges a follow-on
// request for a running science activity (sample, image, dig): nowMs the
// request's time, ownEndMs when the executive expects the activity to end
// without it (the instrument's progress), extraMs the extra time asked. The
// expected end is max(ownEndMs, nowMs) + extraMs; refused (nothing changed)
// when the activity is not running (kNotRunning), not science (kNotScience),
// the expected end passes start + ub (kBeyondUb) or passes its end event's
// latest time in the network as it stands (kInconsistent: a later bound of
// the plan, a deadline or the activities after it, would break), or the
// dispatcher is checking or holding (kBusy). The closed network is
// dispatchable, so an end anywhere in its window keeps the rest of the plan
// consistent: the check is O(1), no recomputation. extend() checks again and
// commits: the end event no earlier than nowMs + extraMs (the extra work
// cannot be done sooner; Stn::tighten, O(n^2)), recorded with the activity
// (carried over, and passed to a regeneration as the event's floor). The late
// checks are unchanged (ub and the end's latest, which the extension lies
// within: never beyond ub); a completion before the floor is early (held).
//
// Work. tick() is O(n^2) for its checks plus O(n^2) per event executed (at
// most kMaxExecutionsPerTick); completed() and failed() one O(n^2) update at
// most. start() runs the full check (n^2 units of Stn::step(), n^3 min-adds:
// 1.1 ms at 116 events, docs/plan_executive.md); begin() and stepCheck()
// slice it.
//
// Time. nowMs is ms since the plan's start, >= 0 and never decreasing from
// call to call (an earlier time is refused, kInvalidArgument).
//
// Memory: sizeof(PlanDispatcher) = 269 360 B on x86-64, the Stn's matrix
// (262 192 B) nearly all of it. Static storage (a member), never a stack. The plan
// is read, not copied: it must stay unchanged while dispatched.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/stn.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

constexpr std::uint16_t kNoIndex = 0xFFFF;  // no activity / no event

enum class ActivityState : std::uint8_t {
    kInactive = 0,  // not in the selection (or not dispatched)
    kWaiting,       // in the selection, not started
    kRunning,       // started (a Start command was given)
    kDone,          // completed
    kTimedOut,      // late: cancelled by the dispatcher
    kFailed,        // reported failed
    kCancelled,     // running when a new selection dropped it, or abort()
};
constexpr std::size_t kActivityStateCount = 7;
const char* toString(ActivityState s);

enum class RegenerationReason : std::uint8_t {
    kNone = 0,
    kLate,            // an activity past its ub or its end's latest time (or completed after it)
    kMissedWindow,    // an event with no incoming activity passed its latest unexecuted
    kEarly,           // an early completion held to its earliest was inconsistent
    kActivityFailed,  // failed() (instrument fault)
};
const char* toString(RegenerationReason r);

// Why an extension of a running science activity is refused (kNone: accepted).
enum class ExtensionRefusal : std::uint8_t {
    kNone = 0,
    kNotRunning,    // the activity is not running (or no plan is dispatched)
    kNotScience,    // not a sample, image or dig
    kBeyondUb,      // its expected end with the extra time passes start + ub
    kInconsistent,  // its expected end passes its end event's latest: a later bound would break
    kBusy,          // the dispatcher is checking a network or holding for a regeneration
    kInvalid,       // extra time not in (0, kMaxBoundMs], or a time out of range
};
const char* toString(ExtensionRefusal r);

// What checkExtension() / extend() found (times in ms since the plan's start).
struct ExtensionCheck {
    ExtensionRefusal refusal = ExtensionRefusal::kNone;
    std::int32_t expectedEndMs = kInfiniteMs;  // max(ownEnd, now) + extra
    std::int32_t ubEndMs = kInfiniteMs;        // start + ub (kInfiniteMs: no ub)
    std::int32_t latestMs = kInfiniteMs;       // the end event's latest in the network
    std::int32_t floorMs = kInfiniteMs;        // now + extra: the end no earlier than this
};

enum class DispatchCommandKind : std::uint8_t { kStart = 0, kCancel };

struct DispatchCommand {
    DispatchCommandKind kind = DispatchCommandKind::kStart;
    std::uint16_t activity = kNoIndex;
};

// What one call asks of the executive. Each call that takes one fills it
// afresh. Capacity: a tick gives an activity at most one command (Cancel
// only to one running, or dropped, when the tick begins; Start only to one
// waiting), so kMaxActivities commands always fit.
struct DispatchOutput {
    static constexpr std::size_t kCapacity = kMaxActivities;
    DispatchCommand commands[kCapacity];
    std::uint16_t count = 0;
    // Regeneration is needed (the dispatcher holds): the first reason, with
    // its activity or event (kNoIndex where none).
    bool regenerate = false;
    RegenerationReason reason = RegenerationReason::kNone;
    std::uint16_t activity = kNoIndex;
    std::uint16_t event = kNoIndex;
    // completed(): the completion was early; its end event is held until heldToMs.
    bool early = false;
    std::int32_t heldToMs = kInfiniteMs;
    void clear();
};

// The activities' states and times (ms since the plan's start; kInfiniteMs
// until known), as carried over to a regenerated dispatch; the extensions
// accepted (their total, and the floor of the activity's end: 0 none).
struct ActivityRecord {
    ActivityState state[kMaxActivities] = {};
    std::int32_t startMs[kMaxActivities];
    std::int32_t endMs[kMaxActivities];
    std::int32_t extendedMs[kMaxActivities] = {};
    std::int32_t floorMs[kMaxActivities] = {};
    ActivityRecord();
};

struct DispatchCounts {
    std::uint32_t started = 0;
    std::uint32_t completed = 0;
    std::uint32_t early = 0;      // completions before their end event's earliest
    std::uint32_t late = 0;       // activities timed out, or completed after their end's latest
    std::uint32_t failed = 0;
    std::uint32_t cancelled = 0;  // dropped by a new selection, or abort()
    std::uint32_t eventsExecuted = 0;
    std::uint32_t extended = 0;   // extensions committed (extend())
};

enum class DispatchPhase : std::uint8_t {
    kIdle = 0,     // nothing loaded, or start() refused the inputs
    kChecking,     // begin() done, the check under way (stepCheck())
    kDispatching,  // tick() runs the plan
    kHolding,      // regeneration needed
    kComplete,     // every existing event executed
};
const char* toString(DispatchPhase p);

// For telemetry (fixed size).
struct DispatchSnapshot {
    DispatchPhase phase = DispatchPhase::kIdle;
    RegenerationReason reason = RegenerationReason::kNone;
    std::uint16_t reasonActivity = kNoIndex;
    std::uint16_t reasonEvent = kNoIndex;
    std::uint16_t events = 0;          // existing under the selection
    std::uint16_t eventsExecuted = 0;
    std::uint16_t activities = 0;      // existing under the selection
    std::uint16_t waiting = 0;
    std::uint16_t running = 0;
    std::uint16_t done = 0;
    std::int32_t slackMs = kInfiniteMs;  // slackMs(nowMs)
    DispatchCounts counts;
};

class PlanDispatcher {
public:
    static constexpr std::size_t kMaxExecutionsPerTick = 8;

    // Loads the selection's network with where execution stands (input's
    // executed times and not before), marks what exists under the selection,
    // carries activities over from a previous dispatch of the same plan
    // (carried may be null, or this dispatcher's own activities()), and
    // begins the full check. kInvalidArgument (phase kIdle): the plan or
    // times outside the limits, a selection that leaves a choice without an
    // option, or carried activities that contradict the executed times (a
    // done or running one whose start event is not executed, or one not done
    // whose end event is).
    core::Status begin(const Tpn& plan, const Selection& selection, const SelectionInput& input,
                       const ActivityRecord* carried);
    // At most maxUnits rows of the check (Stn::step()); true when it is over:
    // phase() then kDispatching, or kIdle when the network is not consistent.
    bool stepCheck(std::uint32_t maxUnits);
    // begin() and the whole check: kOk when dispatching, else kInvalidArgument.
    core::Status start(const Tpn& plan, const Selection& selection, const SelectionInput& input,
                       const ActivityRecord* carried = nullptr);

    // One cycle's dispatch (the rules above); *out filled afresh.
    // kNotInitialized unless dispatching or holding (a complete plan: kOk,
    // nothing to do); kInvalidArgument for an earlier or negative time.
    core::Status tick(std::int32_t nowMs, DispatchOutput* out);
    // The activity completed at nowMs (see above). kInvalidArgument: not a
    // running activity, or nowMs before its start or before the last call.
    core::Status completed(std::uint16_t activity, std::int32_t nowMs, DispatchOutput* out);
    // The activity failed at nowMs: kFailed, regeneration. Refused as completed().
    core::Status failed(std::uint16_t activity, std::int32_t nowMs, DispatchOutput* out);
    // Opportunistic science (see "Extension" above): judges a follow-on
    // request, changing nothing.
    ExtensionCheck checkExtension(std::uint16_t activity, std::int32_t nowMs, std::int32_t ownEndMs,
                                  std::int32_t extraMs) const;
    // Judges it again against the network as it stands and, passed, commits
    // it (the end event's floor nowMs + extraMs, O(n^2)). nowMs is the
    // request's time: it may be before the last call's (the device answered
    // later), not before the activity's start.
    ExtensionCheck extend(std::uint16_t activity, std::int32_t nowMs, std::int32_t ownEndMs, std::int32_t extraMs);

    // Stops the plan (no alternative remains): every running activity
    // cancelled (Cancel in *out; with out null nothing is cancelled, the
    // dispatcher only stops), the dispatcher idle.
    void abort(DispatchOutput* out);

    // Where execution stands, for a re-selection at nowMs: not before nowMs,
    // every executed event's time, the activities done or running marked
    // started, the floor of a running extended activity's end event
    // (notBeforeEventMs; 0 for every other), and for each of them (and every executed event) under an
    // option, that option forced: its choice's other options deprecated, up
    // its nesting. Components and other deprecations are left as they are.
    // A running activity whose component has failed is to be reported
    // failed() first (else it stays forced and its Ask is not judged).
    void regenerationInput(std::int32_t nowMs, SelectionInput* input) const;

    // Queries.
    DispatchPhase phase() const { return phase_; }
    bool complete() const { return phase_ == DispatchPhase::kComplete; }
    bool regenerationNeeded() const { return phase_ == DispatchPhase::kHolding; }
    RegenerationReason reason() const { return reason_; }
    ActivityState state(std::uint16_t activity) const;
    std::int32_t startMs(std::uint16_t activity) const;  // kInfiniteMs: not started
    std::int32_t endMs(std::uint16_t activity) const;    // kInfiniteMs: not ended
    std::int32_t eventTimeMs(std::uint16_t event) const; // kInfiniteMs: not executed
    bool eventExists(std::uint16_t event) const;
    bool constraintExists(std::uint16_t constraint) const;
    // The least slack among existing events not executed: latest - nowMs
    // (kInfiniteMs when none has a latest time; negative: a window passed).
    std::int32_t slackMs(std::int32_t nowMs) const;
    const DispatchCounts& counts() const { return counts_; }
    const ActivityRecord& activities() const { return record_; }
    const Stn& network() const { return stn_; }
    DispatchSnapshot snapshot(std::int32_t nowMs) const;

private:
    bool timeOk(std::int32_t nowMs) const { return nowMs >= 0 && nowMs >= lastNowMs_; }
    bool runningActivity(std::uint16_t activity, std::int32_t nowMs) const;
    void finishStart();
    void needRegeneration(RegenerationReason r, std::uint16_t activity, std::uint16_t event);
    // Executes event e at timeMs (marks, counts, completes the plan); false
    // when the network refused it.
    bool executeEvent(std::uint16_t e, std::int32_t timeMs);
    // Event e when its incoming activities are all done: at max(nowMs,
    // earliest); refused: regeneration (kEarly when held, else lateReason).
    void executeAfterActivities(std::uint16_t e, std::uint16_t activity, std::int32_t nowMs,
                                RegenerationReason lateReason);
    bool predecessorsExecuted(std::uint16_t e) const;
    void cancelLate(std::int32_t nowMs, DispatchOutput* out);
    void executeReadyEvents(std::int32_t nowMs);
    void startReady(std::int32_t nowMs, DispatchOutput* out);
    void fillOutput(DispatchOutput* out) const;
    static bool push(DispatchOutput* out, DispatchCommandKind kind, std::uint16_t activity);

    const Tpn* plan_ = nullptr;
    Stn stn_;
    Selection selection_;
    DispatchPhase phase_ = DispatchPhase::kIdle;
    std::uint16_t n_ = 0;
    bool eventExists_[kMaxEvents] = {};
    bool constraintExists_[kMaxConstraints] = {};
    std::int32_t eventTimeMs_[kMaxEvents] = {};
    // Existing incoming activities of each event not yet done.
    std::uint16_t pendingIncoming_[kMaxEvents] = {};
    std::uint16_t incoming_[kMaxEvents] = {};  // existing incoming activities
    bool cancelPending_[kMaxActivities] = {};
    ActivityRecord record_;
    std::int32_t lastNowMs_ = 0;
    RegenerationReason reason_ = RegenerationReason::kNone;
    std::uint16_t reasonActivity_ = kNoIndex;
    std::uint16_t reasonEvent_ = kNoIndex;
    std::uint16_t eventsExisting_ = 0;
    std::uint16_t eventsExecuted_ = 0;
    std::uint16_t activitiesExisting_ = 0;
    DispatchCounts counts_{};
};

}  // namespace rse::plan_executive

// Event ids raised by the plan executive: its task's (range 950-989, texts
// start with "plan_exec: ") and its goal commands' 208, which keeps the number
// and the "app: " text it had when the goal commands lived in fsw/app (the
// golden console and the ground read it as before). Documented in
// docs/plan_executive.md ("Events").
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::plan_executive::events {

// The goal commands (goal_commands.hpp). A goal command, or start-up, left the
// goal list thus (count, risk bound; event data GOALS_COMMANDED). Text "app: ...".
constexpr core::EventId kGoalsCommanded = 208;     // INFO

constexpr core::EventId kPlanAccepted = 950;       // INFO: plan name, text size, events / activities / choices, cost: dispatch begins
constexpr core::EventId kChunkAccepted = 951;      // DEBUG: a PLAN_LOAD chunk written (offset, length, text so far)
constexpr core::EventId kUploadRefused = 952;      // ERROR: a chunk or PLAN_START refused: gap, overflow, bad length, bad CRC, nothing uploaded, busy (the plan running kept)
constexpr core::EventId kParseRefused = 953;       // ERROR: the plan text refused by the parser: reason, line, token (the plan running kept)
constexpr core::EventId kSelectionRefused = 954;   // ERROR: a new plan with no valid selection (status), or refused by the selector (the plan running kept)
constexpr core::EventId kSelectionDone = 955;      // INFO: selection finished: status, cost, work, runs
constexpr core::EventId kActivityStarted = 956;    // INFO: activity started (name, kind, plan time)
constexpr core::EventId kActivityCompleted = 957;  // INFO: activity completed (name, duration)
constexpr core::EventId kActivityEarly = 958;      // WARN: activity completed before its end event's earliest: held to it
constexpr core::EventId kActivityLate = 959;       // WARN: activity timed out (cancelled) or completed after its end's latest time
constexpr core::EventId kActivityFailed = 960;     // WARN: activity failed
constexpr core::EventId kActivityCancelled = 961;  // INFO: activity cancelled (dropped by a regeneration, abort, or a new plan)
constexpr core::EventId kRegenerating = 962;       // WARN: regeneration begun: reason, activity or event, cost before
constexpr core::EventId kRegenerated = 963;        // WARN: plan regenerated: cost before -> after, status
constexpr core::EventId kPlanComplete = 964;       // INFO: every event of the plan executed
constexpr core::EventId kPlanAborted = 965;        // WARN: PLAN_ABORT: selection dropped, running activities cancelled
constexpr core::EventId kOperatorCalled = 966;     // CRITICAL: no method remains (reason): SafeRequestMsg sent, plan stopped
constexpr core::EventId kPlanSuperseded = 967;     // INFO: a new plan replaced the one running (its running activities cancelled)
constexpr core::EventId kMalformedInput = 968;     // ERROR: a bus message that does not decode or fails its checks (throttled)
constexpr core::EventId kInitFailed = 969;         // ERROR: pipe creation or subscription refused at init
constexpr core::EventId kPublishFailed = 970;      // ERROR: a status or safe request the bus refused (throttled)
constexpr core::EventId kComponentState = 972;     // INFO/WARN: a component's state changed (drive mode declared, instrument usable or not)
constexpr core::EventId kComponentFailed = 973;    // WARN: activities not done ask what a component no longer is: running ones failed, options deprecated, regenerating
constexpr core::EventId kGoalPlan = 978;          // INFO: a goal list revision (GOTO, ADD_TARGET, SET_RISK_BOUND) became plan goal_list of its drives
constexpr core::EventId kGoalPlanStopped = 979;   // WARN: a goal plan's drive failed (the deliberative layer called home): plan stopped, no second call
constexpr core::EventId kGoalListEmpty = 980;     // INFO: an empty goal list (CLEAR_GOALS): a goal plan running stopped; a mission plan runs on
constexpr core::EventId kExtensionRequested = 974;  // INFO: PLAN_EXTEND passed the checks: follow-on sent to the instrument (expected end, ub end, latest)
constexpr core::EventId kExtensionAccepted = 975;   // INFO: the instrument took the follow-on: extension committed, the end no earlier than the floor
constexpr core::EventId kExtensionRefused = 976;    // WARN: PLAN_EXTEND refused (reason: unknown, not running, not science, beyond ub, inconsistent, busy, invalid, instrument): plan untouched
constexpr core::EventId kExtendedCompleted = 977;   // INFO: an extended activity completed: duration, extra time, expected without it
constexpr core::EventId kNetworkRefused = 971;     // ERROR: the dispatcher found the selected network inconsistent (or refused it): plan stopped

}  // namespace rse::plan_executive::events

// The plan executive across the bus (docs/plan_executive.md "The task"): what
// the plan commands (plan_commands.hpp) send it from the ground (PLAN_LOAD chunks, PLAN_START,
// PLAN_SHORT, PLAN_ABORT, PLAN_EXTEND, one message kind each) and what it says it is doing
// (PlanExecutiveStatusMsg, the PLAN_EXEC packet).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

constexpr std::size_t kPlanChunkBytes = 200;      // PLAN_LOAD / PLAN_SHORT blob (dictionary.def)
constexpr std::size_t kPlanNameBytes = 24;        // plan_executive::kNameSize
constexpr std::size_t kPlanStatusOptions = 32;    // chosen options shown: choices 0..31
constexpr std::size_t kPlanStatusActivities = 64; // activity states shown: activities 0..63, two per byte

enum class PlanCommandKind : std::uint8_t {
    kChunk = 0,  // PLAN_LOAD: data[0 .. length) at offset; offset 0 starts a new upload
    kStart = 1,  // PLAN_START: the assembled text must be `length` bytes with CRC-32 `crc32`
    kShort = 2,  // PLAN_SHORT: data[0 .. length) is a whole plan (';' separates lines)
    kAbort = 3,  // PLAN_ABORT
    kExtend = 4, // PLAN_EXTEND: the running science activity named data[0 .. length) for extendMs more
};

// Published by the plan commands (one per command), taken by the plan
// executive task in its next run. Hostile until checked: a kind out of range
// or a length over kPlanChunkBytes is dropped (malformed, evented).
struct PlanCommandMsg {
    static constexpr core::MsgId kMsgId = ids::kPlanCommand;
    std::int64_t timeNs;
    PlanCommandKind kind;
    std::uint8_t pad;
    std::uint16_t length;  // kChunk, kShort: bytes of data used
    std::uint32_t offset;  // kChunk: byte offset in the plan text
    std::uint32_t textLength;  // kStart: length of the assembled text
    std::uint32_t crc32;       // kStart: its CRC-32 (fsw/core/crc32.hpp)
    std::uint32_t extendMs;    // kExtend: the extra time asked, ms
    char data[kPlanChunkBytes];
};

enum class PlanExecutiveState : std::uint8_t {
    kIdle = 0,          // no plan (none yet, aborted)
    kSelecting = 1,     // a new plan's methods being selected (sliced)
    kDispatching = 2,   // a plan running (its network checked, then dispatched)
    kRegenerating = 3,  // re-selecting the running plan from where it stands
    kComplete = 4,      // every event of the plan executed
    kFailed = 5,        // no method remains: the operator was called
};

// Why the last plan (or chunk) was refused.
enum class PlanRefusal : std::uint8_t {
    kNone = 0,
    kParse = 1,        // the parser's PlanError (lastParseError), line and token
    kBadLength = 2,    // PLAN_START's length is not the assembled text's
    kBadCrc = 3,       // PLAN_START's CRC-32 is not the assembled text's
    kGap = 4,          // a chunk beyond the end of the text assembled so far
    kOverflow = 5,     // a chunk past kMaxPlanText bytes
    kNoUpload = 6,     // PLAN_START with no text uploaded since the last start
    kNoSelection = 7,  // no valid selection of methods: inconsistent, unschedulable, or every option unusable
    kBadPlan = 8,      // method selection refused the plan (outside its checks)
    kBusy = 9,         // a new plan's selection is under way: wait for it
};

// Why the last PLAN_EXTEND (a follow-on request for a running science
// activity) was refused (docs/plan_executive.md "Opportunistic science").
enum class PlanExtensionRefusal : std::uint8_t {
    kNone = 0,
    kUnknownActivity = 1,  // no activity of that name in the plan running (or no plan)
    kNotRunning = 2,       // the activity is not running (or ended before the instrument answered)
    kNotScience = 3,       // not a sample, image or dig
    kBeyondUb = 4,         // its expected duration with the extra time passes its ub
    kInconsistent = 5,     // its expected end passes its end event's latest: a later bound of the plan would break
    kBusy = 6,             // a selection, regeneration or network check under way, or another extension pending
    kInvalid = 7,          // the extra time out of range
    kInstrument = 8,       // the instrument refused the follow-on (or it could not be sent)
};

// Why the running plan was last regenerated (plan_executive::RegenerationReason, and a component).
enum class PlanRegeneration : std::uint8_t {
    kNone = 0,
    kLate = 1,
    kMissedWindow = 2,
    kEarly = 3,
    kActivityFailed = 4,
    kComponentFailed = 5,  // a component an activity asks failed (mode estimation or the device)
};

// A drive activity's goal for the deliberative layer, its only source of
// goals: a goal list of one goal (the activity's point and region radius, its
// `within R` or 0, priority 0, the operator's risk bound from the last
// GoalListMsg) when the activity starts,
// of none when it is cancelled. Revisions count from 0x80000000, apart from
// the goal commands'; PlanStatusMsg's goalRevision says which list the
// deliberative layer is working on. listIndex: the goal's index in the
// operator's goal list when the plan is one made from it (GOTO, ADD_TARGET),
// else 0; the deliberative layer reports it as PlanStatusMsg.goalIndex.
struct PlanGoalMsg {
    static constexpr core::MsgId kMsgId = ids::kPlanGoal;
    GoalListMsg goals;
    std::uint8_t listIndex;
    std::uint8_t pad[7];
};

// Published on every change of state, selection or activity, and at 1 Hz.
struct PlanExecutiveStatusMsg {
    static constexpr core::MsgId kMsgId = ids::kPlanExecutiveStatus;
    std::int64_t timeNs;
    PlanExecutiveState state;
    std::uint8_t selectionStatus;   // plan_executive::SelectionStatus of the selection in force
    PlanRefusal lastRefusal;
    std::uint8_t lastParseError;    // plan_executive::PlanError with kParse
    PlanRegeneration lastRegeneration;
    std::uint8_t choiceCount;
    std::uint8_t deprecatedCount;   // options deprecated by the executive (components failed)
    std::uint8_t callHomeReason;    // CallHomeReason of the executive's last call (0 none)
    char planName[kPlanNameBytes];  // NUL-padded; empty when none
    char refusalToken[kPlanNameBytes];
    std::uint32_t refusalLine;
    std::uint16_t activityCount;
    std::uint16_t running;          // activities running now
    double cost;                    // expected cost of the selection in force
    double costBefore;              // the cost before the last regeneration (0 none yet)
    std::int32_t slackMs;           // least slack of the events not executed (INT32_MAX: none bounded)
    std::int32_t planTimeMs;        // ms since the plan started (0 when none runs)
    std::uint32_t plansAccepted;
    std::uint32_t plansRefused;
    std::uint32_t regenerations;
    std::uint32_t activitiesStarted;
    std::uint32_t activitiesCompleted;
    std::uint32_t activitiesEarly;
    std::uint32_t activitiesLate;
    std::uint32_t activitiesFailed;
    std::uint32_t operatorCalls;
    std::uint8_t options[kPlanStatusOptions];  // chosen option per choice (0xFF: the choice does not exist)
    // plan_executive::ActivityState of activity i in the low nibble of byte
    // i / 2 for even i, the high nibble for odd i.
    std::uint8_t activityStates[kPlanStatusActivities / 2];
    std::uint32_t extensionsAccepted;  // PLAN_EXTEND follow-ons taken by the instrument and committed
    std::uint32_t extensionsRefused;   // PLAN_EXTEND refused (each with an event 976)
    PlanExtensionRefusal lastExtensionRefusal;
    std::uint8_t pad[3];
};

}  // namespace rse::msg

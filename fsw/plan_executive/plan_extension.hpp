// Opportunistic science: PLAN_EXTEND (docs/plan_executive.md "Opportunistic
// science"). A follow-on request names a running science activity and asks
// for extra time. It is refused (event 976, counted, the plan untouched) when
// the extra time is out of range (invalid), no activity has that name
// (unknown), a selection, regeneration or check is under way or another
// extension awaits its instrument (busy), or the dispatcher's check refuses
// it (not running, not science, beyond its ub, a later bound of the plan
// would break: PlanDispatcher::checkExtension, with the end expected from the
// instrument's progress). Else the instrument is sent a follow-on (a new
// command id continuing the running one, the extra work; event 974) and,
// when its status names the new id, the extension is committed in the
// network (event 975): the activity completes when the extended work is done
// (ActivityLifecycle's event 977 says how much later). The instrument
// refusing it is a refusal too (the activity goes on as it was); the activity
// ending before the answer drops it (not running). One extension at a time.
#pragma once

#include <cstdint>

#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/activity_devices.hpp"
#include "fsw/plan_executive/executive_context.hpp"

namespace rse::plan_executive {

// PLAN_EXEC's extension figures.
struct ExtensionCounters {
    std::uint32_t accepted = 0;
    std::uint32_t refused = 0;
    msg::PlanExtensionRefusal lastRefusal = msg::PlanExtensionRefusal::kNone;
};

class PlanExtension {
public:
    // The most extra time one PLAN_EXTEND may ask: the instrument's field (6553.5 s).
    static constexpr std::uint32_t kMaxExtendMs = 6553500;

    PlanExtension(ExecutiveContext& ctx, ActivityDevices& devices, RegenerationStarter& regeneration)
        : ctx_(ctx), devices_(devices), regeneration_(regeneration) {}

    // PLAN_EXTEND (m.data[0 .. m.length): the activity's name, as sent;
    // m.extendMs): judged, then the follow-on sent to the instrument.
    void request(const msg::PlanCommandMsg& m);
    // A follow-on sent for activity a awaits the instrument's answer.
    bool pendingFor(std::uint16_t a) const { return pending_.activity == a && a != kNoIndex; }
    std::uint16_t pendingCommandId() const { return pending_.commandId; }
    // The instrument's status while a's follow-on is pending: taken (the
    // activity's command is the follow-on from now on; committed, 975), or
    // refused (976). A commit that leaves the network out of its range
    // starts a regeneration.
    void answer(std::uint16_t a, const msg::InstrumentStatusMsg& m);
    // Activity a stopped running while its follow-on awaited an answer: refused (not running).
    void drop(std::uint16_t a);
    // Activity a started: no extension of it yet.
    void activityStarted(std::uint16_t a) { endBeforeExtensionMs_[a] = 0; }
    // The end expected for activity a before its first extension (0: never extended).
    std::int32_t endBeforeExtensionMs(std::uint16_t a) const { return endBeforeExtensionMs_[a]; }
    // A new plan: no follow-on of the old one is awaited.
    void clear() { pending_ = PendingExtension{}; }
    const ExtensionCounters& counters() const { return counters_; }

private:
    // The follow-on sent and not yet answered (activity kNoIndex: none).
    struct PendingExtension {
        std::uint16_t activity = kNoIndex;
        std::uint16_t commandId = 0;  // the follow-on's id
        std::int32_t extraMs = 0;
        std::int32_t ownEndMs = 0;    // as expected at the request
        std::int32_t requestMs = 0;   // plan time of the request
    };

    // The plan running's activity named m.data[0 .. m.length) (kNoIndex: none).
    std::uint16_t findActivity(const msg::PlanCommandMsg& m) const;
    // When the running science activity a would end without an extension:
    // start + the instrument's elapsed / progress for its command, else its
    // lb; at least nowMs.
    std::int32_t expectedOwnEndMs(std::uint16_t a, std::int32_t nowMs) const;
    void refuse(msg::PlanExtensionRefusal why, const char* name, std::int32_t extraMs, const char* detail);

    ExecutiveContext& ctx_;
    ActivityDevices& devices_;
    RegenerationStarter& regeneration_;
    PendingExtension pending_{};
    std::int32_t endBeforeExtensionMs_[kMaxActivities] = {};  // expected end at the first extension (event 977)
    ExtensionCounters counters_{};
};

}  // namespace rse::plan_executive

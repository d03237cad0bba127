// The devices' side of the plan's activities (docs/plan_executive.md "Dispatch
// to the devices and the deliberative layer"): what the executive sends to
// start, stop or extend an activity, and what a device's report says of it.
//
// Start(drive): a PlanGoalMsg of one goal (the activity's point and region,
// the operator's risk bound, the goal's index in the operator's list for a
// goal plan) for the deliberative layer; its revisions count from
// kGoalRevisionBase, apart from the goal commands'. Start(sample / dig /
// image): an InstrumentCommandMsg to the grinder / camera with a fresh
// command id (1..65535, wrapping) and the activity's ub as the instrument's
// own limit. Cancel: a PlanGoalMsg of no goal, or the instrument's cancel.
// Extend: a follow-on (a fresh id continuing the activity's command, the
// extra work). It keeps each science activity's command id, the drive
// activity whose goal the deliberative layer has, and the instruments' latest
// status. It reads the plan running and the time from the context; a message
// the bus refuses is counted (publishFailures) and evented (970).
#pragma once

#include <cstdint>

#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/executive_context.hpp"

namespace rse::plan_executive {

// What a device's report says of an activity under way.
enum class DeviceReport : std::uint8_t {
    kNone,        // nothing about it
    kDone,        // the instrument's done for its command; the deliberative layer's complete for its goal
    kTimedOut,    // the instrument gave up at the activity's ub (its max duration)
    kFailed,      // the instrument reports its command failed
    kRefused,     // the instrument refused its command
    kOffline,     // the instrument is offline
    kCalledHome,  // the deliberative layer called home on its goal
    kReplaced,    // another goal list replaced the drive's (after the deliberative layer took it)
};

class ActivityDevices {
public:
    static constexpr std::uint32_t kGoalRevisionBase = 0x80000000U;

    explicit ActivityDevices(ExecutiveContext& ctx) : ctx_(ctx) {}

    // Activity a of the plan running started: its goal or its command sent
    // (wait and communicate: nothing; they complete at their lb).
    void start(std::uint16_t a);
    // Activity a cancelled: a drive whose goal is out gets an empty goal
    // list; a commanded science activity its instrument's cancel. True when
    // an instrument command was cancelled (then cancelFollowOn, forget).
    bool cancel(std::uint16_t a);
    // The follow-on the instrument may have taken already runs under its id: cancelled too.
    void cancelFollowOn(std::uint16_t a, std::uint16_t followOnId);
    // Activity a has no command any more (it ended or was cancelled).
    void forget(std::uint16_t a) { commandId_[a] = 0; }
    // A new plan: no command and no drive of the old one are followed.
    void forgetAll();
    // The extension's follow-on for activity a (extraMs of work); its command id.
    std::uint16_t sendFollowOn(std::uint16_t a, std::int32_t extraMs);
    // The instrument took the follow-on: the activity's command is it from now on.
    void adoptFollowOn(std::uint16_t a, std::uint16_t followOnId) { commandId_[a] = followOnId; }
    // The command id of science activity a's command (0: none).
    std::uint16_t commandId(std::uint16_t a) const { return commandId_[a]; }

    // An instrument's status (instrument within msg::kInstrumentCount): kept as its latest.
    void record(const msg::InstrumentStatusMsg& m) { instruments_[static_cast<std::size_t>(m.instrument)] = m; }
    const msg::InstrumentStatusMsg& latest(msg::Instrument i) const {
        return instruments_[static_cast<std::size_t>(i)];
    }
    // Activity a is commanded on the instrument m reports on.
    bool commandedOn(std::uint16_t a, const msg::InstrumentStatusMsg& m) const;
    // What m says of activity a's command.
    DeviceReport judge(std::uint16_t a, const msg::InstrumentStatusMsg& m) const;
    // What the deliberative layer's status says of the drive whose goal it
    // has (*a: that activity); the drive is let go on anything but kNone.
    DeviceReport takePlanStatus(const msg::PlanStatusMsg& m, std::uint16_t* a);
    // Activity a ended otherwise: if its goal is the deliberative layer's, let it go.
    void releaseDrive(std::uint16_t a);

    // The operator's risk bound (the last GoalListMsg's), for the next drive.
    void setRiskBound(double riskBound) { riskBound_ = riskBound; }

private:
    // A drive activity's goal (kNoIndex: none, the drive cancelled).
    void publishGoal(std::uint16_t a);
    void commandInstrument(std::uint16_t a, msg::InstrumentAction action, std::int32_t extraMs = 0);
    std::uint16_t nextCommandId();

    ExecutiveContext& ctx_;
    msg::InstrumentStatusMsg instruments_[msg::kInstrumentCount] = {};
    std::uint16_t commandId_[kMaxActivities] = {};
    std::uint16_t nextCommandId_ = 0;
    std::uint16_t driveActivity_ = kNoIndex;
    std::uint32_t driveRevision_ = 0;
    bool driveAdopted_ = false;  // the deliberative layer reported working on driveRevision_
    std::uint32_t goalRevision_ = kGoalRevisionBase;
    double riskBound_ = 1e-3;
    // The messages are built in place (members, not the stack).
    msg::PlanGoalMsg goal_{};
    msg::InstrumentCommandMsg instrumentCommand_{};
};

}  // namespace rse::plan_executive

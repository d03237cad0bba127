#include "fsw/plan_executive/activity_devices.hpp"

#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

void ActivityDevices::start(std::uint16_t a) {
    switch (ctx_.plan().activities[a].kind) {
        case ActivityKind::kDrive:
            driveActivity_ = a;
            driveAdopted_ = false;
            publishGoal(a);
            break;
        case ActivityKind::kSample: commandInstrument(a, msg::InstrumentAction::kSample); break;
        case ActivityKind::kDig: commandInstrument(a, msg::InstrumentAction::kDig); break;
        case ActivityKind::kImage: commandInstrument(a, msg::InstrumentAction::kImage); break;
        case ActivityKind::kWait:
        case ActivityKind::kCommunicate: break;  // complete at their lb (ActivityLifecycle)
    }
}

bool ActivityDevices::cancel(std::uint16_t a) {
    if (ctx_.plan().activities[a].kind == ActivityKind::kDrive && driveActivity_ == a) {
        driveActivity_ = kNoIndex;
        publishGoal(kNoIndex);
        return false;
    }
    if (commandId_[a] == 0) {
        return false;
    }
    commandInstrument(a, msg::InstrumentAction::kCancel);
    return true;
}

void ActivityDevices::cancelFollowOn(std::uint16_t a, std::uint16_t followOnId) {
    commandId_[a] = followOnId;
    commandInstrument(a, msg::InstrumentAction::kCancel);
}

void ActivityDevices::forgetAll() {
    for (std::uint16_t& id : commandId_) {
        id = 0;
    }
    driveActivity_ = kNoIndex;
}

std::uint16_t ActivityDevices::sendFollowOn(std::uint16_t a, std::int32_t extraMs) {
    commandInstrument(a, msg::InstrumentAction::kExtend, extraMs);
    return nextCommandId_;
}

bool ActivityDevices::commandedOn(std::uint16_t a, const msg::InstrumentStatusMsg& m) const {
    const ActivityKind k = ctx_.plan().activities[a].kind;
    const bool camera = m.instrument == msg::Instrument::kCamera;
    return isScience(k) && (k == ActivityKind::kImage) == camera && commandId_[a] != 0;
}

DeviceReport ActivityDevices::judge(std::uint16_t a, const msg::InstrumentStatusMsg& m) const {
    const std::uint16_t id = commandId_[a];
    if (m.commandId == id && m.state == msg::InstrumentState::kDone) {
        return DeviceReport::kDone;
    }
    if (m.commandId == id && m.state == msg::InstrumentState::kFailed) {
        return m.result == msg::InstrumentResult::kTimedOut ? DeviceReport::kTimedOut : DeviceReport::kFailed;
    }
    if (m.lastRefusedCommandId == id && m.lastRefusal != msg::InstrumentRefusal::kNone) {
        return DeviceReport::kRefused;
    }
    return m.state == msg::InstrumentState::kOffline ? DeviceReport::kOffline : DeviceReport::kNone;
}

DeviceReport ActivityDevices::takePlanStatus(const msg::PlanStatusMsg& m, std::uint16_t* a) {
    *a = driveActivity_;
    if (driveActivity_ == kNoIndex) {
        return DeviceReport::kNone;
    }
    DeviceReport report = DeviceReport::kNone;
    if (m.goalRevision == driveRevision_) {
        driveAdopted_ = true;
        if (m.state == msg::DeliberativeState::kComplete) {
            report = DeviceReport::kDone;
        } else if (m.state == msg::DeliberativeState::kCalledHome) {
            report = DeviceReport::kCalledHome;
        }
    } else if (driveAdopted_) {
        report = DeviceReport::kReplaced;
    }
    if (report != DeviceReport::kNone) {
        driveActivity_ = kNoIndex;
    }
    return report;
}

void ActivityDevices::releaseDrive(std::uint16_t a) {
    if (driveActivity_ == a) {
        driveActivity_ = kNoIndex;
    }
}

void ActivityDevices::publishGoal(std::uint16_t a) {
    goal_ = msg::PlanGoalMsg{};
    msg::GoalListMsg& g = goal_.goals;
    g.timeNs = ctx_.now;
    g.riskBound = riskBound_;
    ++goalRevision_;
    if (goalRevision_ < kGoalRevisionBase) {
        goalRevision_ = kGoalRevisionBase;  // wrapped: stay apart from the goal commands' revisions
    }
    g.revision = goalRevision_;
    if (a != kNoIndex) {
        const Activity& drive = ctx_.plan().activities[a];
        g.count = 1;
        g.goals[0].xM = drive.x;
        g.goals[0].yM = drive.y;
        // `within R`: the deliberative layer claims the goal, and the habitual
        // layer stops, anywhere within R of the point.
        g.goals[0].radiusM = static_cast<float>(drive.radiusMm) / 1000.0F;
        driveRevision_ = goalRevision_;
        // A goal plan's activities are the operator's goals in order.
        goal_.listIndex = ctx_.goalPlan && a < msg::kMaxGoals ? static_cast<std::uint8_t>(a) : 0;
    }
    if (!core::isOk(ctx_.bus.publish(goal_))) {
        ++ctx_.publishFailures;
        ctx_.events.report(events::kPublishFailed, core::Severity::kError, "plan_exec: drive goal refused by the bus");
    }
}

std::uint16_t ActivityDevices::nextCommandId() {
    nextCommandId_ = static_cast<std::uint16_t>(nextCommandId_ == 0xFFFF ? 1 : nextCommandId_ + 1);
    return nextCommandId_;
}

void ActivityDevices::commandInstrument(std::uint16_t a, msg::InstrumentAction action, std::int32_t extraMs) {
    const Activity& act = ctx_.plan().activities[a];
    msg::InstrumentCommandMsg& c = instrumentCommand_;
    c = msg::InstrumentCommandMsg{};
    c.timeNs = ctx_.now;
    c.instrument = act.kind == ActivityKind::kImage ? msg::Instrument::kCamera : msg::Instrument::kGrinder;
    c.action = action;
    c.targetId = act.target;
    if (action == msg::InstrumentAction::kCancel) {
        c.commandId = commandId_[a];
    } else if (action == msg::InstrumentAction::kExtend) {
        // A follow-on: a fresh id continuing the activity's command, the extra work (whole 0.1 s).
        c.commandId = nextCommandId();
        c.extendsCommandId = commandId_[a];
        c.maxDurationS = static_cast<double>(extraMs) / 1000.0;
    } else {
        commandId_[a] = nextCommandId();
        c.commandId = commandId_[a];
        // The activity's ub as the instrument's own limit (0: none; at most 6553.5 s).
        const std::int32_t ub = act.duration.ubMs;
        c.maxDurationS = ub == kInfiniteMs ? 0.0 : (ub > 6553500 ? 6553.5 : static_cast<double>(ub) / 1000.0);
    }
    if (!core::isOk(ctx_.bus.publish(c))) {
        ++ctx_.publishFailures;
        ctx_.events.report(events::kPublishFailed, core::Severity::kError,
                           "plan_exec: instrument command %u refused by the bus", static_cast<unsigned>(c.commandId));
    }
}

}  // namespace rse::plan_executive

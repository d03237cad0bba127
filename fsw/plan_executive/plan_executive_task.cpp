#include "fsw/plan_executive/plan_executive_task.hpp"

#include <cstdio>
#include <cstring>

#include "fsw/core/crc32.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

namespace {

const char* refusalName(msg::PlanRefusal r) {
    switch (r) {
        case msg::PlanRefusal::kNone: return "none";
        case msg::PlanRefusal::kParse: return "parse error";
        case msg::PlanRefusal::kBadLength: return "bad length";
        case msg::PlanRefusal::kBadCrc: return "bad CRC-32";
        case msg::PlanRefusal::kGap: return "gap";
        case msg::PlanRefusal::kOverflow: return "overflow";
        case msg::PlanRefusal::kNoUpload: return "nothing uploaded";
        case msg::PlanRefusal::kNoSelection: return "no valid selection";
        case msg::PlanRefusal::kBadPlan: return "bad plan";
        case msg::PlanRefusal::kBusy: return "busy selecting";
    }
    return "?";
}

msg::PlanRegeneration regenerationOf(RegenerationReason r) {
    switch (r) {
        case RegenerationReason::kNone: return msg::PlanRegeneration::kNone;
        case RegenerationReason::kLate: return msg::PlanRegeneration::kLate;
        case RegenerationReason::kMissedWindow: return msg::PlanRegeneration::kMissedWindow;
        case RegenerationReason::kEarly: return msg::PlanRegeneration::kEarly;
        case RegenerationReason::kActivityFailed: return msg::PlanRegeneration::kActivityFailed;
    }
    return msg::PlanRegeneration::kNone;
}

bool completesAtLb(ActivityKind k) { return k == ActivityKind::kWait || k == ActivityKind::kCommunicate; }

bool science(ActivityKind k) { return k == ActivityKind::kSample || k == ActivityKind::kImage || k == ActivityKind::kDig; }

const char* extensionRefusalName(msg::PlanExtensionRefusal r) {
    switch (r) {
        case msg::PlanExtensionRefusal::kNone: return "none";
        case msg::PlanExtensionRefusal::kUnknownActivity: return "unknown activity";
        case msg::PlanExtensionRefusal::kNotRunning: return "not running";
        case msg::PlanExtensionRefusal::kNotScience: return "not a science activity";
        case msg::PlanExtensionRefusal::kBeyondUb: return "beyond its ub";
        case msg::PlanExtensionRefusal::kInconsistent: return "plan inconsistent";
        case msg::PlanExtensionRefusal::kBusy: return "busy";
        case msg::PlanExtensionRefusal::kInvalid: return "invalid extra time";
        case msg::PlanExtensionRefusal::kInstrument: return "instrument refused";
    }
    return "?";
}

msg::PlanExtensionRefusal extensionRefusalOf(ExtensionRefusal r) {
    switch (r) {
        case ExtensionRefusal::kNone: return msg::PlanExtensionRefusal::kNone;
        case ExtensionRefusal::kNotRunning: return msg::PlanExtensionRefusal::kNotRunning;
        case ExtensionRefusal::kNotScience: return msg::PlanExtensionRefusal::kNotScience;
        case ExtensionRefusal::kBeyondUb: return msg::PlanExtensionRefusal::kBeyondUb;
        case ExtensionRefusal::kInconsistent: return msg::PlanExtensionRefusal::kInconsistent;
        case ExtensionRefusal::kBusy: return msg::PlanExtensionRefusal::kBusy;
        case ExtensionRefusal::kInvalid: return msg::PlanExtensionRefusal::kInvalid;
    }
    return msg::PlanExtensionRefusal::kInvalid;
}

double seconds(std::int32_t ms) { return static_cast<double>(ms) / 1000.0; }

}  // namespace

PlanExecutiveTask::PlanExecutiveTask(core::SoftwareBus& bus, core::EventLog& events)
    : bus_(bus),
      events_(events),
      commands_(bus, events, core::InputPipeConfig{"plan_exec", kPipeDepth, events::kMalformedInput, "plan_exec"}),
      inputs_(bus, events,
              core::InputPipeConfig{"plan_exec_in", kStatusPipeDepth, events::kMalformedInput, "plan_exec"}) {}

core::Status PlanExecutiveTask::init() {
    // The status pipe's ids are routed in the order they were subscribed before.
    core::Status status = commands_.create();
    if (core::isOk(status)) {
        status = commands_.route<&PlanExecutiveTask::takeCommand>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.create();
    }
    if (core::isOk(status)) {
        status = inputs_.route<&PlanExecutiveTask::takeInstrument>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&PlanExecutiveTask::takeDriveModes>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&PlanExecutiveTask::takePlanStatus>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&PlanExecutiveTask::takeGoalList>(this);
    }
    if (!core::isOk(status)) {
        events_.report(events::kInitFailed, core::Severity::kError, "plan_exec: init failed (%s)",
                       core::toString(status));
        return status;
    }
    ready_ = true;
    return core::Status::kOk;
}

void PlanExecutiveTask::run(const core::FrameContext& frame) {
    if (!ready_) {
        return;
    }
    now_ = frame.scheduledStart;
    ++runs_;
    commands_.drain();
    inputs_.drain();
    if (goalsPending_ && job_ == Job::kNone) {
        beginGoalPlan();
    }
    if (job_ != Job::kNone) {
        stepSelection();
    }
    if (checking_) {
        stepCheck();
    }
    // A plan with nothing to run is complete when its check ends: seen here too.
    if (!checking_ && state_ != msg::PlanExecutiveState::kRegenerating &&
        (dispatcher_.phase() == DispatchPhase::kDispatching ||
                       dispatcher_.phase() == DispatchPhase::kHolding ||
                       (dispatcher_.complete() && state_ == msg::PlanExecutiveState::kDispatching))) {
        dispatch();
    }
    if (changed_ || runs_ % kStatusPeriodRuns == 0) {
        changed_ = false;
        publishStatus();
    }
}

// A command whose kind or length is out of range is refused: counted and
// evented as malformed by the pipe.
core::Status PlanExecutiveTask::takeCommand(const msg::PlanCommandMsg& m) {
    if (static_cast<std::uint8_t>(m.kind) > static_cast<std::uint8_t>(msg::PlanCommandKind::kExtend) ||
        m.length > msg::kPlanChunkBytes) {
        return core::Status::kInvalidArgument;
    }
    handle(m);
    return core::Status::kOk;
}

core::Status PlanExecutiveTask::takeInstrument(const msg::InstrumentStatusMsg& m) {
    if (static_cast<std::size_t>(m.instrument) >= msg::kInstrumentCount ||
        static_cast<std::uint8_t>(m.state) > static_cast<std::uint8_t>(msg::InstrumentState::kFailed)) {
        return core::Status::kInvalidArgument;
    }
    onInstrument(m);
    return core::Status::kOk;
}

core::Status PlanExecutiveTask::takeDriveModes(const msg::DriveModesMsg& m) {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (static_cast<std::uint8_t>(m.drives[w].declared) >= msg::kDriveModeCount) {
            return core::Status::kInvalidArgument;
        }
    }
    onDriveModes(m);
    return core::Status::kOk;
}

void PlanExecutiveTask::takePlanStatus(const msg::PlanStatusMsg& m) { onPlanStatus(m); }

core::Status PlanExecutiveTask::takeGoalList(const msg::GoalListMsg& m) {
    if (!msg::goalListUsable(m)) {
        return core::Status::kInvalidArgument;
    }
    onGoalList(m);
    return core::Status::kOk;
}

void PlanExecutiveTask::onInstrument(const msg::InstrumentStatusMsg& m) {
    const auto i = static_cast<std::size_t>(m.instrument);
    instruments_[i] = m;
    const Component component = i == 0 ? Component::kGrinder : Component::kCamera;
    const bool unusable = m.state == msg::InstrumentState::kOffline ||
                          (m.state == msg::InstrumentState::kFailed && m.faultCode != 0);
    const ComponentState now = unusable ? ComponentState::kFailed : ComponentState::kOk;
    ComponentState& c = components_[static_cast<std::size_t>(component)];
    if (c != now) {
        c = now;
        changed_ = true;
        events_.report(events::kComponentState, now == ComponentState::kOk ? core::Severity::kInfo
                                                                            : core::Severity::kWarning,
                       "plan_exec: %s now %s (instrument state %u, fault %u)", toString(component), toString(now),
                       static_cast<unsigned>(m.state), static_cast<unsigned>(m.faultCode));
    }
    if (!planLoaded_) {
        return;
    }
    const Tpn& p = tpn_[active_];
    for (std::uint16_t a = 0; a < p.activityCount; ++a) {
        const ActivityKind k = p.activities[a].kind;
        const bool onThis = (k == ActivityKind::kImage) == (i == 1) &&
                            (k == ActivityKind::kSample || k == ActivityKind::kDig || k == ActivityKind::kImage);
        if (!onThis || commandId_[a] == 0 || dispatcher_.state(a) != ActivityState::kRunning) {
            continue;
        }
        if (pending_.activity == a) {
            answerExtension(a, m);  // may move the activity's command to the follow-on's id
        }
        const std::uint16_t id = commandId_[a];
        if (m.commandId == id && m.state == msg::InstrumentState::kDone) {
            deviceCompleted(a);
        } else if (m.commandId == id && m.state == msg::InstrumentState::kFailed &&
                   m.result == msg::InstrumentResult::kTimedOut) {
            deviceFailed(a, "timed out at its ub (the instrument's limit)", true);
        } else if (m.commandId == id && m.state == msg::InstrumentState::kFailed) {
            deviceFailed(a, "the instrument reports it failed");
        } else if (m.lastRefusedCommandId == id && m.lastRefusal != msg::InstrumentRefusal::kNone) {
            deviceFailed(a, "the instrument refused it");
        } else if (m.state == msg::InstrumentState::kOffline) {
            deviceFailed(a, "the instrument is offline");
        }
    }
}

void PlanExecutiveTask::onDriveModes(const msg::DriveModesMsg& m) {
    for (std::size_t w = 0; w < msg::kWheelCount && w < kComponentCount; ++w) {
        ComponentState now = ComponentState::kDegraded;  // degraded, and unknown: not known to be ok
        if (m.drives[w].declared == msg::DriveMode::kNominal) {
            now = ComponentState::kOk;
        } else if (m.drives[w].declared == msg::DriveMode::kFailed) {
            now = ComponentState::kFailed;
        }
        if (components_[w] != now) {
            components_[w] = now;
            changed_ = true;
            events_.report(events::kComponentState, now == ComponentState::kOk ? core::Severity::kInfo
                                                                                : core::Severity::kWarning,
                           "plan_exec: %s now %s (declared drive mode %u)", toString(static_cast<Component>(w)),
                           toString(now), static_cast<unsigned>(m.drives[w].declared));
        }
    }
}

void PlanExecutiveTask::onPlanStatus(const msg::PlanStatusMsg& m) {
    if (driveActivity_ == kNoIndex) {
        return;
    }
    const std::uint16_t a = driveActivity_;
    if (m.goalRevision == driveRevision_) {
        driveAdopted_ = true;
        if (m.state == msg::DeliberativeState::kComplete) {
            driveActivity_ = kNoIndex;
            deviceCompleted(a);
        } else if (m.state == msg::DeliberativeState::kCalledHome) {
            driveActivity_ = kNoIndex;
            deviceFailed(a, "the deliberative layer called home");
        }
    } else if (driveAdopted_) {
        driveActivity_ = kNoIndex;
        deviceFailed(a, "another goal list replaced the drive's");
    }
}

void PlanExecutiveTask::deviceCompleted(std::uint16_t a) {
    const std::int32_t nowMs = planMs();
    if (dispatcher_.state(a) != ActivityState::kRunning) {
        return;
    }
    const std::int32_t start = dispatcher_.startMs(a);
    if (!core::isOk(dispatcher_.completed(a, nowMs, &out_))) {
        return;
    }
    commandId_[a] = 0;
    dropExtension(a);
    ++completed_;
    changed_ = true;
    const Activity& act = tpn_[active_].activities[a];
    events_.report(events::kActivityCompleted, core::Severity::kInfo, "plan_exec: %s %s completed after %.1f s",
                   toString(act.kind), act.name, static_cast<double>(nowMs - start) / 1000.0);
    const std::int32_t extended = dispatcher_.activities().extendedMs[a];
    if (extended > 0) {
        events_.report(events::kExtendedCompleted, core::Severity::kInfo,
                       "plan_exec: %s extended %.1f s: done after %.1f s (expected %.1f s without)", act.name,
                       seconds(extended), seconds(nowMs - start), seconds(endBeforeExtensionMs_[a] - start));
    }
    if (out_.early) {
        ++early_;
        events_.report(events::kActivityEarly, core::Severity::kWarning,
                       "plan_exec: %s completed early at %.1f s (lb %.1f s): its end held to %.1f s", act.name,
                       static_cast<double>(nowMs) / 1000.0, static_cast<double>(act.duration.lbMs) / 1000.0,
                       static_cast<double>(out_.heldToMs) / 1000.0);
    }
    handleOutput(out_, nowMs);
}

void PlanExecutiveTask::deviceFailed(std::uint16_t a, const char* why, bool late) {
    const std::int32_t nowMs = planMs();
    if (dispatcher_.state(a) != ActivityState::kRunning || !core::isOk(dispatcher_.failed(a, nowMs, &out_))) {
        return;
    }
    commandId_[a] = 0;
    dropExtension(a);
    if (driveActivity_ == a) {
        driveActivity_ = kNoIndex;
    }
    ++(late ? late_ : failed_);
    lateByDevice_ = lateByDevice_ || late;
    changed_ = true;
    const Activity& act = tpn_[active_].activities[a];
    events_.report(late ? events::kActivityLate : events::kActivityFailed, core::Severity::kWarning,
                   "plan_exec: %s %s %s at %.1f s: %s", toString(act.kind), act.name, late ? "late" : "failed",
                   static_cast<double>(nowMs) / 1000.0, why);
    handleOutput(out_, nowMs);
}

void PlanExecutiveTask::startActivity(std::uint16_t a) {
    const Activity& act = tpn_[active_].activities[a];
    endBeforeExtensionMs_[a] = 0;
    switch (act.kind) {
        case ActivityKind::kDrive:
            driveActivity_ = a;
            driveAdopted_ = false;
            publishGoal(a);
            break;
        case ActivityKind::kSample: commandInstrument(a, msg::InstrumentAction::kSample); break;
        case ActivityKind::kDig: commandInstrument(a, msg::InstrumentAction::kDig); break;
        case ActivityKind::kImage: commandInstrument(a, msg::InstrumentAction::kImage); break;
        case ActivityKind::kWait:
        case ActivityKind::kCommunicate: break;  // complete at their lb (completeTimedActivities)
    }
}

void PlanExecutiveTask::cancelActivity(std::uint16_t a) {
    const Activity& act = tpn_[active_].activities[a];
    if (act.kind == ActivityKind::kDrive && driveActivity_ == a) {
        driveActivity_ = kNoIndex;
        publishGoal(kNoIndex);
    } else if (commandId_[a] != 0) {
        commandInstrument(a, msg::InstrumentAction::kCancel);
        if (pending_.activity == a) {
            // The instrument may have taken the follow-on already: it runs under its id then.
            commandId_[a] = pending_.commandId;
            commandInstrument(a, msg::InstrumentAction::kCancel);
            dropExtension(a);
        }
        commandId_[a] = 0;
    }
}

void PlanExecutiveTask::publishGoal(std::uint16_t a) {
    goal_ = msg::PlanGoalMsg{};
    msg::GoalListMsg& g = goal_.goals;
    g.timeNs = now_;
    g.riskBound = riskBound_;
    ++goalRevision_;
    if (goalRevision_ < kGoalRevisionBase) {
        goalRevision_ = kGoalRevisionBase;  // wrapped: stay apart from the command handlers' revisions
    }
    g.revision = goalRevision_;
    if (a != kNoIndex) {
        const Activity& drive = tpn_[active_].activities[a];
        g.count = 1;
        g.goals[0].xM = drive.x;
        g.goals[0].yM = drive.y;
        // `within R`: the deliberative layer claims the goal, and the habitual
        // layer stops, anywhere within R of the point.
        g.goals[0].radiusM = static_cast<float>(drive.radiusMm) / 1000.0F;
        driveRevision_ = goalRevision_;
        // A goal plan's activities are the operator's goals in order.
        goal_.listIndex = goalPlan_ && a < msg::kMaxGoals ? static_cast<std::uint8_t>(a) : 0;
    }
    if (!core::isOk(bus_.publish(goal_))) {
        ++publishFailures_;
        events_.report(events::kPublishFailed, core::Severity::kError, "plan_exec: drive goal refused by the bus");
    }
}

void PlanExecutiveTask::commandInstrument(std::uint16_t a, msg::InstrumentAction action) {
    const Activity& act = tpn_[active_].activities[a];
    msg::InstrumentCommandMsg& c = instrumentCommand_;
    c = msg::InstrumentCommandMsg{};
    c.timeNs = now_;
    c.instrument = act.kind == ActivityKind::kImage ? msg::Instrument::kCamera : msg::Instrument::kGrinder;
    c.action = action;
    c.targetId = act.target;
    if (action == msg::InstrumentAction::kCancel) {
        c.commandId = commandId_[a];
    } else if (action == msg::InstrumentAction::kExtend) {
        // A follow-on: a fresh id continuing the activity's command, the extra work (whole 0.1 s).
        nextCommandId_ = static_cast<std::uint16_t>(nextCommandId_ == 0xFFFF ? 1 : nextCommandId_ + 1);
        c.commandId = nextCommandId_;
        c.extendsCommandId = commandId_[a];
        c.maxDurationS = seconds(pending_.extraMs);
        pending_.commandId = nextCommandId_;
    } else {
        nextCommandId_ = static_cast<std::uint16_t>(nextCommandId_ == 0xFFFF ? 1 : nextCommandId_ + 1);
        commandId_[a] = nextCommandId_;
        c.commandId = nextCommandId_;
        // The activity's ub as the instrument's own limit (0: none; at most 6553.5 s).
        const std::int32_t ub = act.duration.ubMs;
        c.maxDurationS = ub == kInfiniteMs ? 0.0 : (ub > 6553500 ? 6553.5 : static_cast<double>(ub) / 1000.0);
    }
    if (!core::isOk(bus_.publish(c))) {
        ++publishFailures_;
        events_.report(events::kPublishFailed, core::Severity::kError,
                       "plan_exec: instrument command %u refused by the bus", static_cast<unsigned>(c.commandId));
    }
}

bool PlanExecutiveTask::askHolds(const Condition& c) const {
    if (c.planVariable || c.variable >= kComponentCount) {
        return true;  // plan variables are the selector's (causal links)
    }
    const bool equal = static_cast<std::uint8_t>(components_[c.variable]) == c.value;
    return c.negated ? !equal : equal;
}

bool PlanExecutiveTask::checkComponents(std::int32_t nowMs) {
    const Tpn& p = tpn_[active_];
    std::uint16_t affected = 0;
    std::uint16_t first = kNoIndex;
    for (std::uint16_t a = 0; a < p.activityCount; ++a) {
        const ActivityState st = dispatcher_.state(a);
        if (st != ActivityState::kWaiting && st != ActivityState::kRunning) {
            continue;
        }
        const Activity& act = p.activities[a];
        bool holds = true;
        for (std::size_t k = 0; k < act.askCount && k < kMaxAsks; ++k) {
            holds = holds && askHolds(act.asks[k]);
        }
        if (holds) {
            continue;
        }
        ++affected;
        first = first == kNoIndex ? a : first;
        if (st == ActivityState::kRunning) {
            cancelActivity(a);  // the device stops what the plan no longer runs
            deviceFailed(a, "a component it asks has failed");
        } else if (act.guard.guarded() && act.guard.choice < kMaxChoices && act.guard.option < kMaxOptions) {
            deprecated_[act.guard.choice][act.guard.option] = true;
        }
    }
    if (affected == 0) {
        return false;
    }
    events_.report(events::kComponentFailed, core::Severity::kWarning,
                   "plan_exec: %u activit%s ask a component no longer so (first %s): regenerating",
                   static_cast<unsigned>(affected), affected == 1 ? "y" : "ies", p.activities[first].name);
    regenerateForComponent_ = true;
    componentActivity_ = first;
    startRegeneration(nowMs);
    return true;
}

void PlanExecutiveTask::handle(const msg::PlanCommandMsg& m) {
    switch (m.kind) {
        case msg::PlanCommandKind::kChunk: loadChunk(m); break;
        case msg::PlanCommandKind::kStart: startUpload(m); break;
        case msg::PlanCommandKind::kShort:
            if (job_ != Job::kNone) {
                refuse(msg::PlanRefusal::kBusy, events::kUploadRefused, "PLAN_SHORT while a selection is under way");
                return;
            }
            std::memcpy(shortText_, m.data, m.length);
            beginNewPlan(shortText_, m.length, false);
            break;
        case msg::PlanCommandKind::kAbort: abortPlan(false); break;
        case msg::PlanCommandKind::kExtend: extendActivity(m); break;
    }
}

// ---------------------------------------------------------------------------
// Opportunistic science: PLAN_EXTEND.

void PlanExecutiveTask::refuseExtension(msg::PlanExtensionRefusal why, const char* name, std::int32_t extraMs,
                                        const char* detail) {
    ++extensionsRefused_;
    lastExtensionRefusal_ = why;
    changed_ = true;
    events_.report(events::kExtensionRefused, core::Severity::kWarning, "plan_exec: extend %s +%.1f s refused: %s (%s)",
                   name, seconds(extraMs), extensionRefusalName(why), detail);
}

std::int32_t PlanExecutiveTask::expectedOwnEndMs(std::uint16_t a, std::int32_t nowMs) const {
    const Activity& act = tpn_[active_].activities[a];
    const std::int64_t start = dispatcher_.startMs(a);
    const msg::InstrumentStatusMsg& m =
        instruments_[act.kind == ActivityKind::kImage ? static_cast<std::size_t>(msg::Instrument::kCamera)
                                                      : static_cast<std::size_t>(msg::Instrument::kGrinder)];
    // Nothing better known: the plan's least duration.
    std::int64_t total = act.duration.lbMs;
    if (m.commandId == commandId_[a] && m.state == msg::InstrumentState::kBusy && m.progressPct > 0 &&
        m.progressPct < 100 && m.lastReportNs > planStartNs_) {
        // Its progress at its last report: the work is elapsed / progress long.
        const std::int64_t elapsed = (m.lastReportNs - planStartNs_) / core::kNsPerMs - start;
        if (elapsed > 0) {
            total = (elapsed * 100 + m.progressPct - 1) / m.progressPct;
        }
    }
    std::int64_t end = start + total;
    end = end < nowMs ? nowMs : end;
    return static_cast<std::int32_t>(end > kMaxBoundMs ? kMaxBoundMs : end);
}

void PlanExecutiveTask::extendActivity(const msg::PlanCommandMsg& m) {
    // The name as sent: any bytes (shown printable in the events).
    char name[kNameSize] = {};
    const std::size_t shown = m.length < kNameSize ? m.length : kNameSize - 1;
    for (std::size_t i = 0; i < shown; ++i) {
        const char c = m.data[i];
        name[i] = c >= 0x20 && c < 0x7F ? c : '?';
    }
    if (m.extendMs == 0 || m.extendMs > kMaxExtendMs) {
        char detail[64];
        std::snprintf(detail, sizeof detail, "%u ms", static_cast<unsigned>(m.extendMs));
        refuseExtension(msg::PlanExtensionRefusal::kInvalid, name,
                        static_cast<std::int32_t>(m.extendMs > kMaxExtendMs ? kMaxExtendMs : m.extendMs), detail);
        return;
    }
    // Whole 0.1 s, as the instruments take it.
    const auto extraMs = static_cast<std::int32_t>((m.extendMs + 99U) / 100U * 100U);
    std::uint16_t a = kNoIndex;
    const Tpn& p = tpn_[active_];
    for (std::uint16_t i = 0; planLoaded_ && a == kNoIndex && i < p.activityCount; ++i) {
        std::size_t n = 0;
        while (n < kNameSize && p.activities[i].name[n] != '\0') {
            ++n;
        }
        if (m.length == n && n > 0 && std::memcmp(p.activities[i].name, m.data, n) == 0) {
            a = i;
        }
    }
    if (a == kNoIndex) {
        refuseExtension(msg::PlanExtensionRefusal::kUnknownActivity, name, extraMs,
                        planLoaded_ ? "not in the plan" : "no plan");
        return;
    }
    if (job_ != Job::kNone || checking_ || pending_.activity != kNoIndex) {
        refuseExtension(msg::PlanExtensionRefusal::kBusy, name, extraMs,
                        pending_.activity != kNoIndex ? "an extension pending" : "selecting or checking");
        return;
    }
    const Activity& act = p.activities[a];
    const std::int32_t nowMs = planMs();
    const bool commanded = science(act.kind) && commandId_[a] != 0;
    const std::int32_t ownEndMs = commanded ? expectedOwnEndMs(a, nowMs) : nowMs;
    const ExtensionCheck c = dispatcher_.checkExtension(a, nowMs, ownEndMs, extraMs);
    char detail[120];
    switch (c.refusal) {
        case ExtensionRefusal::kNone: break;
        case ExtensionRefusal::kNotRunning:
            std::snprintf(detail, sizeof detail, "%s", toString(dispatcher_.state(a)));
            break;
        case ExtensionRefusal::kNotScience:
            std::snprintf(detail, sizeof detail, "%s", toString(act.kind));
            break;
        case ExtensionRefusal::kBeyondUb:
            std::snprintf(detail, sizeof detail, "end %.1f > start+ub %.1f s", seconds(c.expectedEndMs),
                          seconds(c.ubEndMs));
            break;
        case ExtensionRefusal::kInconsistent:
            std::snprintf(detail, sizeof detail, "end %.1f > latest %.1f s", seconds(c.expectedEndMs),
                          seconds(c.latestMs));
            break;
        case ExtensionRefusal::kBusy:
            std::snprintf(detail, sizeof detail, "holding");
            break;
        case ExtensionRefusal::kInvalid:
            std::snprintf(detail, sizeof detail, "times out of range");
            break;
    }
    if (c.refusal != ExtensionRefusal::kNone) {
        refuseExtension(extensionRefusalOf(c.refusal), name, extraMs, detail);
        return;
    }
    if (!commanded) {
        refuseExtension(msg::PlanExtensionRefusal::kNotRunning, name, extraMs, "no command in hand");
        return;
    }
    pending_ = PendingExtension{};
    pending_.activity = a;
    pending_.extraMs = extraMs;
    pending_.ownEndMs = ownEndMs;
    pending_.requestMs = nowMs;
    commandInstrument(a, msg::InstrumentAction::kExtend);  // sets pending_.commandId
    changed_ = true;
    events_.report(events::kExtensionRequested, core::Severity::kInfo,
                   "plan_exec: extend %s +%.1f s sent: end %.1f->%.1f s (start+ub %.1f, latest %.1f s)", act.name,
                   seconds(extraMs), seconds(ownEndMs), seconds(c.expectedEndMs),
                   c.ubEndMs == kInfiniteMs ? -1.0 : seconds(c.ubEndMs),
                   c.latestMs == kInfiniteMs ? -1.0 : seconds(c.latestMs));
}

void PlanExecutiveTask::answerExtension(std::uint16_t a, const msg::InstrumentStatusMsg& m) {
    const PendingExtension p = pending_;
    const Activity& act = tpn_[active_].activities[a];
    if (m.commandId == p.commandId) {
        // Taken: the instrument's command is the follow-on from now on.
        pending_ = PendingExtension{};
        commandId_[a] = p.commandId;
        const ExtensionCheck c = dispatcher_.extend(a, p.requestMs, p.ownEndMs, p.extraMs);
        if (c.refusal != ExtensionRefusal::kNone) {
            refuseExtension(extensionRefusalOf(c.refusal), act.name, p.extraMs, "taken too late: runs on");
            return;
        }
        if (endBeforeExtensionMs_[a] == 0) {
            endBeforeExtensionMs_[a] = p.ownEndMs;
        }
        ++extensionsAccepted_;
        changed_ = true;
        events_.report(events::kExtensionAccepted, core::Severity::kInfo,
                       "plan_exec: %s extended by %.1f s: the %s took it; end no earlier than %.1f s", act.name,
                       seconds(p.extraMs), act.kind == ActivityKind::kImage ? "camera" : "grinder",
                       seconds(c.floorMs));
        if (dispatcher_.regenerationNeeded() && job_ == Job::kNone) {
            startRegeneration(planMs());  // the network left its range (see PlanDispatcher::extend)
        }
        return;
    }
    if (m.lastRefusedCommandId == p.commandId && m.lastRefusal != msg::InstrumentRefusal::kNone) {
        pending_ = PendingExtension{};
        char detail[32];
        std::snprintf(detail, sizeof detail, "refusal %u", static_cast<unsigned>(m.lastRefusal));
        refuseExtension(msg::PlanExtensionRefusal::kInstrument, act.name, p.extraMs, detail);
    }
}

void PlanExecutiveTask::dropExtension(std::uint16_t a) {
    if (pending_.activity != a) {
        return;
    }
    const std::int32_t extraMs = pending_.extraMs;
    pending_ = PendingExtension{};
    refuseExtension(msg::PlanExtensionRefusal::kNotRunning, tpn_[active_].activities[a].name, extraMs,
                    "ended first");
}

void PlanExecutiveTask::refuse(msg::PlanRefusal why, core::EventId id, const char* detail) {
    ++plansRefused_;
    lastRefusal_ = why;
    changed_ = true;
    const bool running = planLoaded_ && (state_ == msg::PlanExecutiveState::kDispatching ||
                                         state_ == msg::PlanExecutiveState::kRegenerating);
    events_.report(id, core::Severity::kError, "plan_exec: refused (%s): %s; %s", refusalName(why), detail,
                   running ? "the plan running is kept" : "no plan running");
}

void PlanExecutiveTask::loadChunk(const msg::PlanCommandMsg& m) {
    if (m.offset == 0) {
        uploadLength_ = 0;
        uploadOpen_ = true;
        uploadError_ = msg::PlanRefusal::kNone;
    }
    if (uploadError_ != msg::PlanRefusal::kNone) {
        refuse(uploadError_, events::kUploadRefused, "chunk of an upload already spoiled (send offset 0 again)");
        return;
    }
    if (!uploadOpen_ || m.offset > uploadLength_) {
        uploadError_ = msg::PlanRefusal::kGap;
        refuse(uploadError_, events::kUploadRefused, "chunk beyond the text assembled so far");
        return;
    }
    if (static_cast<std::size_t>(m.offset) + m.length > kMaxPlanText) {
        uploadError_ = msg::PlanRefusal::kOverflow;
        refuse(uploadError_, events::kUploadRefused, "chunk past the 16384-byte plan buffer");
        return;
    }
    std::memcpy(text_ + m.offset, m.data, m.length);
    const std::size_t end = static_cast<std::size_t>(m.offset) + m.length;
    uploadLength_ = end > uploadLength_ ? end : uploadLength_;
    changed_ = true;
    events_.report(events::kChunkAccepted, core::Severity::kDebug,
                   "plan_exec: chunk at %u, %u B: %u B of plan text", static_cast<unsigned>(m.offset),
                   static_cast<unsigned>(m.length), static_cast<unsigned>(uploadLength_));
}

void PlanExecutiveTask::refuseStart(msg::PlanRefusal why, const char* what, std::uint32_t said,
                                    std::uint32_t found) {
    char detail[80];
    std::snprintf(detail, sizeof detail, "PLAN_START's %s %u, the text's %u", what, static_cast<unsigned>(said),
                  static_cast<unsigned>(found));
    refuse(why, events::kUploadRefused, detail);
}

void PlanExecutiveTask::startUpload(const msg::PlanCommandMsg& m) {
    if (job_ != Job::kNone) {
        refuse(msg::PlanRefusal::kBusy, events::kUploadRefused, "PLAN_START while a selection is under way");
        return;
    }
    if (!uploadOpen_ || uploadLength_ == 0) {
        refuse(msg::PlanRefusal::kNoUpload, events::kUploadRefused, "no plan text uploaded since the last start");
        return;
    }
    if (uploadError_ != msg::PlanRefusal::kNone) {
        refuse(uploadError_, events::kUploadRefused, "the upload was spoiled by a chunk refused");
        return;
    }
    if (m.textLength != uploadLength_) {
        refuseStart(msg::PlanRefusal::kBadLength, "length", m.textLength,
                    static_cast<std::uint32_t>(uploadLength_));
        return;
    }
    const std::uint32_t crc = core::crc32(text_, uploadLength_);
    if (crc != m.crc32) {
        refuseStart(msg::PlanRefusal::kBadCrc, "CRC-32", m.crc32, crc);
        return;
    }
    uploadOpen_ = false;  // one start per upload
    beginNewPlan(text_, uploadLength_, false);
}

void PlanExecutiveTask::beginNewPlan(const char* text, std::size_t length, bool fromGoals) {
    Tpn& staged = tpn_[1 - active_];
    const ParseResult r = parsePlan(text, length, &staged);
    if (r.error != PlanError::kOk) {
        ++plansRefused_;
        lastRefusal_ = msg::PlanRefusal::kParse;
        lastParse_ = r;
        changed_ = true;
        events_.report(events::kParseRefused, core::Severity::kError,
                       "plan_exec: plan refused: %s at line %u, token '%s'; %s", toString(r.error),
                       static_cast<unsigned>(r.line), r.token,
                       planLoaded_ ? "the plan running is kept" : "no plan running");
        return;
    }
    newInput_ = SelectionInput{};
    for (std::size_t c = 0; c < kComponentCount; ++c) {
        newInput_.components[c] = components_[c];
    }
    for (auto& row : deprecated_) {
        for (bool& d : row) {
            d = false;  // a new plan: the executive has deprecated none of its options
        }
    }
    if (!core::isOk(selector_.start(staged, newInput_, params_))) {
        refuse(msg::PlanRefusal::kBadPlan, events::kSelectionRefused, "method selection refused the plan");
        return;
    }
    stagedLength_ = length;
    stagedGoalPlan_ = fromGoals;
    job_ = Job::kSelectNew;
    selectionRuns_ = 0;
    if (!planLoaded_ || state_ == msg::PlanExecutiveState::kIdle || state_ == msg::PlanExecutiveState::kComplete ||
        state_ == msg::PlanExecutiveState::kFailed) {
        state_ = msg::PlanExecutiveState::kSelecting;
    }
    changed_ = true;
}

void PlanExecutiveTask::abortPlan(bool superseded) {
    if (!superseded) {
        job_ = Job::kNone;
    }
    cancelDispatch();
    if (superseded) {
        events_.report(events::kPlanSuperseded, core::Severity::kInfo,
                       "plan_exec: plan %s replaced by a new plan", tpn_[active_].name);
        return;
    }
    state_ = msg::PlanExecutiveState::kIdle;
    events_.report(events::kPlanAborted, core::Severity::kWarning,
                   "plan_exec: PLAN_ABORT: plan %s stopped, selection dropped",
                   planLoaded_ ? tpn_[active_].name : "(none)");
}

void PlanExecutiveTask::stepSelection() {
    ++selectionRuns_;
    if (!selector_.step(kSelectionUnitsPerRun)) {
        return;
    }
    const SelectionResult& r = selector_.result();
    events_.report(events::kSelectionDone, core::Severity::kInfo,
                   "plan_exec: selection %s, cost %.2f, %llu work units in %u runs", toString(r.status), r.cost,
                   static_cast<unsigned long long>(selector_.work()), static_cast<unsigned>(selectionRuns_));
    const Job job = job_;
    job_ = Job::kNone;
    changed_ = true;
    if (job == Job::kSelectNew) {
        adoptNewPlan(r);
    } else {
        adoptRegeneration(r);
    }
}

void PlanExecutiveTask::adoptNewPlan(const SelectionResult& r) {
    const Tpn& staged = tpn_[1 - active_];
    if (!r.hasSelection) {
        ++plansRefused_;
        lastRefusal_ = msg::PlanRefusal::kNoSelection;
        events_.report(events::kSelectionRefused, core::Severity::kError,
                       "plan_exec: plan %s refused: no valid selection (%s): inconsistent, unschedulable or every "
                       "method unusable; %s",
                       staged.name, toString(r.status), planLoaded_ ? "the plan running is kept" : "no plan running");
        if (!planLoaded_ || state_ == msg::PlanExecutiveState::kSelecting) {
            state_ = planLoaded_ && dispatcher_.phase() != DispatchPhase::kIdle ? msg::PlanExecutiveState::kDispatching
                                                                               : msg::PlanExecutiveState::kIdle;
        }
        return;
    }
    if (planLoaded_ && dispatcher_.phase() != DispatchPhase::kIdle) {
        abortPlan(true);
    }
    active_ = 1 - active_;
    planLoaded_ = true;
    goalPlan_ = stagedGoalPlan_;
    for (std::uint16_t& id : commandId_) {
        id = 0;
    }
    pending_ = PendingExtension{};
    driveActivity_ = kNoIndex;
    selection_ = r.selection;
    selectionStatus_ = r.status;
    cost_ = r.cost;
    costBefore_ = 0.0;
    input_ = newInput_;
    planStartNs_ = now_;
    ++plansAccepted_;
    const Tpn& p = tpn_[active_];
    events_.report(events::kPlanAccepted, core::Severity::kInfo,
                   "plan_exec: plan %s accepted: %u B, %u events, %u activities, %u choices, cost %.2f",
                   p.name, static_cast<unsigned>(stagedLength_), static_cast<unsigned>(p.eventCount),
                   static_cast<unsigned>(p.activityCount), static_cast<unsigned>(p.choiceCount), r.cost);
    state_ = msg::PlanExecutiveState::kDispatching;
    checking_ = core::isOk(dispatcher_.begin(p, selection_, input_, nullptr));
    if (!checking_) {
        events_.report(events::kNetworkRefused, core::Severity::kError,
                       "plan_exec: plan %s: the dispatcher refused the selection", p.name);
        state_ = msg::PlanExecutiveState::kFailed;
    }
}

void PlanExecutiveTask::adoptRegeneration(const SelectionResult& r) {
    const Tpn& p = tpn_[active_];
    if (!r.hasSelection) {
        callOperator(toString(r.status));
        return;
    }
    costBefore_ = cost_;
    cost_ = r.cost;
    selection_ = r.selection;
    selectionStatus_ = r.status;
    input_ = regenInput_;
    carried_ = dispatcher_.activities();  // completions taken while the selection ran included
    events_.report(events::kRegenerated, core::Severity::kWarning,
                   "plan_exec: plan %s regenerated (%s): cost %.2f -> %.2f", p.name, toString(r.status), costBefore_,
                   cost_);
    state_ = msg::PlanExecutiveState::kDispatching;
    checking_ = core::isOk(dispatcher_.begin(p, selection_, input_, &carried_));
    if (!checking_) {
        events_.report(events::kNetworkRefused, core::Severity::kError,
                       "plan_exec: plan %s: the dispatcher refused the regenerated selection", p.name);
        callOperator("the regenerated selection was refused");
    }
}

void PlanExecutiveTask::stepCheck() {
    if (!dispatcher_.stepCheck(kCheckUnitsPerRun)) {
        return;
    }
    checking_ = false;
    changed_ = true;
    if (dispatcher_.phase() != DispatchPhase::kDispatching && !dispatcher_.complete()) {
        events_.report(events::kNetworkRefused, core::Severity::kError,
                       "plan_exec: plan %s: the selected network is not consistent", tpn_[active_].name);
        callOperator("the selected network is not consistent");
    }
}

std::int32_t PlanExecutiveTask::planMs() const {
    const core::TimeNs t = (now_ - planStartNs_) / core::kNsPerMs;
    if (t <= 0) {
        return 0;
    }
    return t > kMaxBoundMs ? kMaxBoundMs : static_cast<std::int32_t>(t);
}

void PlanExecutiveTask::dispatch() {
    const std::int32_t nowMs = planMs();
    if (job_ == Job::kNone && state_ == msg::PlanExecutiveState::kDispatching && checkComponents(nowMs)) {
        return;
    }
    if (core::isOk(dispatcher_.tick(nowMs, &out_))) {
        handleOutput(out_, nowMs);
    }
    completeTimedActivities(nowMs);
    if (dispatcher_.complete() && state_ == msg::PlanExecutiveState::kDispatching) {
        state_ = msg::PlanExecutiveState::kComplete;
        changed_ = true;
        events_.report(events::kPlanComplete, core::Severity::kInfo, "plan_exec: plan %s complete at %.1f s",
                       tpn_[active_].name, static_cast<double>(nowMs) / 1000.0);
        return;
    }
    if (dispatcher_.regenerationNeeded() && job_ == Job::kNone) {
        if (goalPlan_) {
            stopGoalPlan();
        } else {
            startRegeneration(nowMs);
        }
    }
}

void PlanExecutiveTask::cancelDispatch() {
    checking_ = false;
    if (dispatcher_.phase() != DispatchPhase::kIdle) {
        const std::int32_t nowMs = planMs();
        dispatcher_.abort(&out_);
        handleOutput(out_, nowMs);
    }
    changed_ = true;
}

void PlanExecutiveTask::onGoalList(const msg::GoalListMsg& m) {
    riskBound_ = m.riskBound;
    if (goalListSeen_ && m.revision == goalList_.revision) {
        return;
    }
    goalList_ = m;
    goalListSeen_ = true;
    goalsPending_ = true;
}

// GOTO, ADD_TARGET, CLEAR_GOALS and SET_RISK_BOUND (docs/plan_executive.md
// "Goal lists"): the operator's goal list as plan text, one drive activity a
// goal in order, [0, inf) each, no choices; parsed, selected and dispatched as
// any plan. Taken only between selections (a PLAN_START under way first): the
// latest list wins.
void PlanExecutiveTask::beginGoalPlan() {
    goalsPending_ = false;
    const msg::GoalListMsg& g = goalList_;
    if (g.count == 0) {
        const bool running = goalPlan_ && planLoaded_ &&
                             (state_ == msg::PlanExecutiveState::kDispatching ||
                              state_ == msg::PlanExecutiveState::kRegenerating);
        const bool missionPlan = planLoaded_ && !goalPlan_ && !running &&
                                 (state_ == msg::PlanExecutiveState::kDispatching ||
                                  state_ == msg::PlanExecutiveState::kRegenerating);
        // DEBUG when there is nothing to say (the command handlers' first list at boot).
        events_.report(events::kGoalListEmpty,
                       running || missionPlan ? core::Severity::kInfo : core::Severity::kDebug,
                       "plan_exec: goal list rev %u empty: %s", static_cast<unsigned>(g.revision),
                       running ? "goal plan stopped"
                               : (missionPlan ? "the mission plan runs on (PLAN_ABORT stops it)" : "no goal plan to stop"));
        if (running) {
            cancelDispatch();
            state_ = msg::PlanExecutiveState::kIdle;
        }
        return;
    }
    std::size_t n = 0;
    n += static_cast<std::size_t>(std::snprintf(goalText_ + n, sizeof goalText_ - n, "plan goal_list\n"));
    for (std::size_t i = 0; i < g.count && n < sizeof goalText_; ++i) {
        n += static_cast<std::size_t>(std::snprintf(goalText_ + n, sizeof goalText_ - n, "event goal%u\n",
                                                    static_cast<unsigned>(i + 1)));
    }
    for (std::size_t i = 0; i < g.count && n < sizeof goalText_; ++i) {
        char from[16] = "start";
        if (i > 0) {
            std::snprintf(from, sizeof from, "goal%u", static_cast<unsigned>(i));
        }
        // A goal's region goes with it (the command handlers' goals are
        // points: radius 0, no `within`); below the text's 1 mm it is the point.
        char within[24] = "";
        if (g.goals[i].radiusM >= 0.0005F) {
            std::snprintf(within, sizeof within, " within %.3f", static_cast<double>(g.goals[i].radiusM));
        }
        n += static_cast<std::size_t>(std::snprintf(goalText_ + n, sizeof goalText_ - n,
                                                    "activity drive%u drive %s goal%u [0, inf] at %.3f %.3f%s\n",
                                                    static_cast<unsigned>(i + 1), from, static_cast<unsigned>(i + 1),
                                                    g.goals[i].xM, g.goals[i].yM, within));
    }
    if (n < sizeof goalText_) {
        n += static_cast<std::size_t>(std::snprintf(goalText_ + n, sizeof goalText_ - n, "end\n"));
    }
    if (n >= sizeof goalText_) {
        refuse(msg::PlanRefusal::kOverflow, events::kUploadRefused, "goal list longer than its plan text buffer");
        return;
    }
    ++goalPlans_;
    events_.report(events::kGoalPlan, core::Severity::kInfo,
                   "plan_exec: goal list rev %u: %u goal(s), risk bound %.3g: plan goal_list of %u drive(s)",
                   static_cast<unsigned>(g.revision), static_cast<unsigned>(g.count), g.riskBound,
                   static_cast<unsigned>(g.count));
    beginNewPlan(goalText_, n, true);
}

// A goal plan's drive failed: the deliberative layer called home (the goal
// unreachable, replans exhausted: its SafeRequestMsg already sent). A goal
// plan has no other method, and a second call would only overwrite the
// deliberative layer's reason: the plan stops, the call home stands.
void PlanExecutiveTask::stopGoalPlan() {
    const DispatchSnapshot snap = dispatcher_.snapshot(planMs());
    const Tpn& p = tpn_[active_];
    cancelDispatch();
    state_ = msg::PlanExecutiveState::kFailed;
    events_.report(events::kGoalPlanStopped, core::Severity::kWarning,
                   "plan_exec: goal plan stopped at %s: no other method; the deliberative layer's call home stands",
                   snap.reasonActivity < p.activityCount ? p.activities[snap.reasonActivity].name : "-");
}

void PlanExecutiveTask::completeTimedActivities(std::int32_t nowMs) {
    const Tpn& p = tpn_[active_];
    for (std::uint16_t a = 0; a < p.activityCount; ++a) {
        const Activity& act = p.activities[a];
        if (!completesAtLb(act.kind) || dispatcher_.state(a) != ActivityState::kRunning) {
            continue;
        }
        const std::int32_t start = dispatcher_.startMs(a);
        if (static_cast<std::int64_t>(nowMs) - start < act.duration.lbMs) {
            continue;
        }
        deviceCompleted(a);
    }
}

void PlanExecutiveTask::handleOutput(const DispatchOutput& out, std::int32_t nowMs) {
    const Tpn& p = tpn_[active_];
    for (std::uint16_t i = 0; i < out.count && i < DispatchOutput::kCapacity; ++i) {
        const DispatchCommand& c = out.commands[i];
        if (c.activity >= p.activityCount) {
            continue;
        }
        const Activity& a = p.activities[c.activity];
        changed_ = true;
        if (c.kind == DispatchCommandKind::kStart) {
            ++started_;
            events_.report(events::kActivityStarted, core::Severity::kInfo,
                           "plan_exec: %s %s started at %.1f s (bounds [%.1f, %.1f] s)", toString(a.kind), a.name,
                           static_cast<double>(nowMs) / 1000.0, static_cast<double>(a.duration.lbMs) / 1000.0,
                           a.duration.ubMs == kInfiniteMs ? -1.0 : static_cast<double>(a.duration.ubMs) / 1000.0);
            startActivity(c.activity);
            continue;
        }
        cancelActivity(c.activity);
        if (dispatcher_.state(c.activity) == ActivityState::kTimedOut) {
            ++late_;
            events_.report(events::kActivityLate, core::Severity::kWarning,
                           "plan_exec: %s %s timed out at %.1f s: cancelled", toString(a.kind), a.name,
                           static_cast<double>(nowMs) / 1000.0);
        } else {
            events_.report(events::kActivityCancelled, core::Severity::kInfo,
                           "plan_exec: %s %s cancelled at %.1f s", toString(a.kind), a.name,
                           static_cast<double>(nowMs) / 1000.0);
        }
    }
    if (out.regenerate && out.reason == RegenerationReason::kLate && out.activity < p.activityCount &&
        dispatcher_.state(out.activity) == ActivityState::kDone) {
        ++late_;  // completed after its end's latest (a timeout was counted with its Cancel)
        events_.report(events::kActivityLate, core::Severity::kWarning,
                       "plan_exec: %s completed late at %.1f s", p.activities[out.activity].name,
                       static_cast<double>(nowMs) / 1000.0);
    }
}

void PlanExecutiveTask::startRegeneration(std::int32_t nowMs) {
    const Tpn& p = tpn_[active_];
    const RegenerationReason why = dispatcher_.regenerationNeeded() ? dispatcher_.reason() : RegenerationReason::kNone;
    carried_ = dispatcher_.activities();
    regenInput_ = input_;
    for (bool& s : regenInput_.started) {
        s = false;
    }
    for (std::size_t c = 0; c < kComponentCount; ++c) {
        regenInput_.components[c] = components_[c];
    }
    for (std::size_t c = 0; c < kMaxChoices; ++c) {
        for (std::size_t o = 0; o < kMaxOptions; ++o) {
            regenInput_.deprecated[c][o] = regenInput_.deprecated[c][o] || deprecated_[c][o];
        }
    }
    dispatcher_.regenerationInput(nowMs, &regenInput_);
    ++regenerations_;
    lastRegeneration_ = regenerateForComponent_ ? msg::PlanRegeneration::kComponentFailed : regenerationOf(why);
    if (lateByDevice_ && why == RegenerationReason::kActivityFailed) {
        lastRegeneration_ = msg::PlanRegeneration::kLate;  // the instrument's own timeout at the ub
    }
    regenerateForComponent_ = false;
    lateByDevice_ = false;
    changed_ = true;
    const DispatchSnapshot snap = dispatcher_.snapshot(nowMs);
    const bool component = lastRegeneration_ == msg::PlanRegeneration::kComponentFailed;
    const bool late = lastRegeneration_ == msg::PlanRegeneration::kLate;
    const std::uint16_t named = component ? componentActivity_ : snap.reasonActivity;
    events_.report(events::kRegenerating, core::Severity::kWarning,
                   "plan_exec: %s regenerating at %.1f s: %s (%s), cost before %.2f", p.name,
                   static_cast<double>(nowMs) / 1000.0, component ? "component failed" : (late ? "late" : toString(why)),
                   named < p.activityCount ? p.activities[named].name : "-", cost_);
    if (!core::isOk(selector_.start(p, regenInput_, params_))) {
        callOperator("method selection refused the regeneration");
        return;
    }
    job_ = Job::kRegenerate;
    selectionRuns_ = 0;
    state_ = msg::PlanExecutiveState::kRegenerating;
}

void PlanExecutiveTask::callOperator(const char* why) {
    ++operatorCalls_;
    callHomeReason_ = static_cast<std::uint8_t>(msg::CallHomeReason::kPlanNoMethod);
    cancelDispatch();
    state_ = msg::PlanExecutiveState::kFailed;
    events_.report(events::kOperatorCalled, core::Severity::kCritical,
                   "plan_exec: plan %s: no method remains (%s): operator called, rover safed", tpn_[active_].name,
                   why);
    msg::SafeRequestMsg safe{};
    safe.timeNs = now_;
    safe.reason = msg::CallHomeReason::kPlanNoMethod;
    if (!core::isOk(bus_.publish(safe))) {
        ++publishFailures_;
        events_.report(events::kPublishFailed, core::Severity::kError, "plan_exec: safe request refused by the bus");
    }
}

void PlanExecutiveTask::fillStatus() {
    msg::PlanExecutiveStatusMsg& s = status_;
    s = msg::PlanExecutiveStatusMsg{};
    s.timeNs = now_;
    s.state = state_;
    s.selectionStatus = static_cast<std::uint8_t>(selectionStatus_);
    s.lastRefusal = lastRefusal_;
    s.lastParseError = static_cast<std::uint8_t>(lastParse_.error);
    s.lastRegeneration = lastRegeneration_;
    s.callHomeReason = callHomeReason_;
    std::memcpy(s.refusalToken, lastParse_.token, sizeof s.refusalToken);
    s.refusalToken[sizeof s.refusalToken - 1] = '\0';
    s.refusalLine = lastParse_.line;
    s.cost = cost_;
    s.costBefore = costBefore_;
    s.plansAccepted = plansAccepted_;
    s.plansRefused = plansRefused_;
    s.regenerations = regenerations_;
    s.activitiesStarted = started_;
    s.activitiesCompleted = completed_;
    s.activitiesEarly = early_;
    s.activitiesLate = late_;
    s.activitiesFailed = failed_;
    s.operatorCalls = operatorCalls_;
    s.extensionsAccepted = extensionsAccepted_;
    s.extensionsRefused = extensionsRefused_;
    s.lastExtensionRefusal = lastExtensionRefusal_;
    s.slackMs = kInfiniteMs;
    for (std::uint8_t& o : s.options) {
        o = kNoOption;
    }
    if (!planLoaded_) {
        return;
    }
    const Tpn& p = tpn_[active_];
    std::memcpy(s.planName, p.name, sizeof s.planName);
    s.planName[sizeof s.planName - 1] = '\0';
    s.choiceCount = p.choiceCount;
    s.activityCount = p.activityCount;
    for (std::size_t c = 0; c < p.choiceCount && c < msg::kPlanStatusOptions; ++c) {
        s.options[c] = selection_.option[c];
    }
    std::uint32_t deprecated = 0;
    for (std::size_t c = 0; c < p.choiceCount; ++c) {
        for (std::size_t o = 0; o < kMaxOptions; ++o) {
            deprecated += deprecated_[c][o] ? 1U : 0U;
        }
    }
    s.deprecatedCount = static_cast<std::uint8_t>(deprecated);
    const bool dispatched = dispatcher_.phase() != DispatchPhase::kIdle;
    const std::int32_t nowMs = planMs();
    if (dispatched) {
        s.planTimeMs = nowMs;
        s.slackMs = dispatcher_.slackMs(nowMs);
    }
    for (std::uint16_t a = 0; a < p.activityCount; ++a) {
        const ActivityState st = dispatcher_.state(a);
        s.running = static_cast<std::uint16_t>(s.running + (st == ActivityState::kRunning ? 1 : 0));
        if (a < msg::kPlanStatusActivities) {
            const auto v = static_cast<std::uint8_t>(static_cast<std::uint8_t>(st) & 0x0F);
            s.activityStates[a / 2] = static_cast<std::uint8_t>(s.activityStates[a / 2] | (a % 2 == 0 ? v : v << 4));
        }
    }
}

void PlanExecutiveTask::publishStatus() {
    fillStatus();
    if (!core::isOk(bus_.publish(status_))) {
        ++publishFailures_;
        if (core::isReportableOccurrence(publishFailures_)) {
            events_.report(events::kPublishFailed, core::Severity::kError,
                           "plan_exec: status refused by the bus (%u so far)", static_cast<unsigned>(publishFailures_));
        }
    }
}

}  // namespace rse::plan_executive

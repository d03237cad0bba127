#include "fsw/plan_executive/activity_lifecycle.hpp"

#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

namespace {

bool completesAtLb(ActivityKind k) { return k == ActivityKind::kWait || k == ActivityKind::kCommunicate; }

double seconds(std::int32_t ms) { return static_cast<double>(ms) / 1000.0; }

}  // namespace

bool ActivityLifecycle::advance(std::int32_t nowMs) {
    if (core::isOk(ctx_.dispatcher.tick(nowMs, &out_))) {
        handleOutput(out_, nowMs);
    }
    completeTimedActivities(nowMs);
    if (ctx_.dispatcher.complete() && ctx_.state == msg::PlanExecutiveState::kDispatching) {
        ctx_.state = msg::PlanExecutiveState::kComplete;
        ctx_.changed = true;
        ctx_.events.report(events::kPlanComplete, core::Severity::kInfo, "plan_exec: plan %s complete at %.1f s",
                           ctx_.plan().name, seconds(nowMs));
        return true;
    }
    return false;
}

void ActivityLifecycle::takeInstrument(const msg::InstrumentStatusMsg& m) {
    if (!ctx_.planLoaded) {
        return;
    }
    const Tpn& p = ctx_.plan();
    for (std::uint16_t a = 0; a < p.activityCount; ++a) {
        if (!devices_.commandedOn(a, m) || ctx_.dispatcher.state(a) != ActivityState::kRunning) {
            continue;
        }
        if (extension_.pendingFor(a)) {
            extension_.answer(a, m);  // may move the activity's command to the follow-on's id
        }
        switch (devices_.judge(a, m)) {
            case DeviceReport::kDone: completed(a); break;
            case DeviceReport::kTimedOut: failed(a, "timed out at its ub (the instrument's limit)", true); break;
            case DeviceReport::kFailed: failed(a, "the instrument reports it failed"); break;
            case DeviceReport::kRefused: failed(a, "the instrument refused it"); break;
            case DeviceReport::kOffline: failed(a, "the instrument is offline"); break;
            case DeviceReport::kNone:
            case DeviceReport::kCalledHome:
            case DeviceReport::kReplaced: break;
        }
    }
}

void ActivityLifecycle::takePlanStatus(const msg::PlanStatusMsg& m) {
    std::uint16_t a = kNoIndex;
    switch (devices_.takePlanStatus(m, &a)) {
        case DeviceReport::kDone: completed(a); break;
        case DeviceReport::kCalledHome: failed(a, "the deliberative layer called home"); break;
        case DeviceReport::kReplaced: failed(a, "another goal list replaced the drive's"); break;
        case DeviceReport::kNone:
        case DeviceReport::kTimedOut:
        case DeviceReport::kFailed:
        case DeviceReport::kRefused:
        case DeviceReport::kOffline: break;
    }
}

void ActivityLifecycle::completed(std::uint16_t a) {
    const std::int32_t nowMs = ctx_.planMs();
    if (ctx_.dispatcher.state(a) != ActivityState::kRunning) {
        return;
    }
    const std::int32_t start = ctx_.dispatcher.startMs(a);
    if (!core::isOk(ctx_.dispatcher.completed(a, nowMs, &out_))) {
        return;
    }
    devices_.forget(a);
    extension_.drop(a);
    ++counters_.completed;
    ctx_.changed = true;
    reportCompletion(a, start, nowMs);
    handleOutput(out_, nowMs);
}

void ActivityLifecycle::reportCompletion(std::uint16_t a, std::int32_t startMs, std::int32_t nowMs) {
    const Activity& act = ctx_.plan().activities[a];
    ctx_.events.report(events::kActivityCompleted, core::Severity::kInfo, "plan_exec: %s %s completed after %.1f s",
                       toString(act.kind), act.name, seconds(nowMs - startMs));
    const std::int32_t extended = ctx_.dispatcher.activities().extendedMs[a];
    if (extended > 0) {
        ctx_.events.report(events::kExtendedCompleted, core::Severity::kInfo,
                           "plan_exec: %s extended %.1f s: done after %.1f s (expected %.1f s without)", act.name,
                           seconds(extended), seconds(nowMs - startMs),
                           seconds(extension_.endBeforeExtensionMs(a) - startMs));
    }
    if (out_.early) {
        ++counters_.early;
        ctx_.events.report(events::kActivityEarly, core::Severity::kWarning,
                           "plan_exec: %s completed early at %.1f s (lb %.1f s): its end held to %.1f s", act.name,
                           seconds(nowMs), seconds(act.duration.lbMs), seconds(out_.heldToMs));
    }
}

void ActivityLifecycle::failed(std::uint16_t a, const char* why, bool late) {
    const std::int32_t nowMs = ctx_.planMs();
    if (ctx_.dispatcher.state(a) != ActivityState::kRunning || !core::isOk(ctx_.dispatcher.failed(a, nowMs, &out_))) {
        return;
    }
    devices_.forget(a);
    extension_.drop(a);
    devices_.releaseDrive(a);
    ++(late ? counters_.late : counters_.failed);
    lateByDevice_ = lateByDevice_ || late;
    ctx_.changed = true;
    const Activity& act = ctx_.plan().activities[a];
    ctx_.events.report(late ? events::kActivityLate : events::kActivityFailed, core::Severity::kWarning,
                       "plan_exec: %s %s %s at %.1f s: %s", toString(act.kind), act.name, late ? "late" : "failed",
                       seconds(nowMs), why);
    handleOutput(out_, nowMs);
}

void ActivityLifecycle::cancel(std::uint16_t a) {
    if (!devices_.cancel(a)) {
        return;
    }
    if (extension_.pendingFor(a)) {
        // The instrument may have taken the follow-on already: it runs under its id then.
        devices_.cancelFollowOn(a, extension_.pendingCommandId());
        extension_.drop(a);
    }
    devices_.forget(a);
}

void ActivityLifecycle::cancelDispatch() {
    ctx_.checking = false;
    if (ctx_.dispatcher.phase() != DispatchPhase::kIdle) {
        const std::int32_t nowMs = ctx_.planMs();
        ctx_.dispatcher.abort(&out_);
        handleOutput(out_, nowMs);
    }
    ctx_.changed = true;
}

void ActivityLifecycle::newPlan() {
    devices_.forgetAll();
    extension_.clear();
}

bool ActivityLifecycle::takeLateByDevice() {
    const bool late = lateByDevice_;
    lateByDevice_ = false;
    return late;
}

void ActivityLifecycle::completeTimedActivities(std::int32_t nowMs) {
    const Tpn& p = ctx_.plan();
    for (std::uint16_t a = 0; a < p.activityCount; ++a) {
        const Activity& act = p.activities[a];
        if (!completesAtLb(act.kind) || ctx_.dispatcher.state(a) != ActivityState::kRunning) {
            continue;
        }
        const std::int32_t start = ctx_.dispatcher.startMs(a);
        if (static_cast<std::int64_t>(nowMs) - start < act.duration.lbMs) {
            continue;
        }
        completed(a);
    }
}

void ActivityLifecycle::handleOutput(const DispatchOutput& out, std::int32_t nowMs) {
    const Tpn& p = ctx_.plan();
    for (std::uint16_t i = 0; i < out.count && i < DispatchOutput::kCapacity; ++i) {
        const DispatchCommand& c = out.commands[i];
        if (c.activity >= p.activityCount) {
            continue;
        }
        ctx_.changed = true;
        if (c.kind == DispatchCommandKind::kStart) {
            start(c.activity, nowMs);
        } else {
            stop(c.activity, nowMs);
        }
    }
    if (out.regenerate && out.reason == RegenerationReason::kLate && out.activity < p.activityCount &&
        ctx_.dispatcher.state(out.activity) == ActivityState::kDone) {
        ++counters_.late;  // completed after its end's latest (a timeout was counted with its Cancel)
        ctx_.events.report(events::kActivityLate, core::Severity::kWarning, "plan_exec: %s completed late at %.1f s",
                           p.activities[out.activity].name, seconds(nowMs));
    }
}

void ActivityLifecycle::start(std::uint16_t a, std::int32_t nowMs) {
    const Activity& act = ctx_.plan().activities[a];
    ++counters_.started;
    ctx_.events.report(events::kActivityStarted, core::Severity::kInfo,
                       "plan_exec: %s %s started at %.1f s (bounds [%.1f, %.1f] s)", toString(act.kind), act.name,
                       seconds(nowMs), seconds(act.duration.lbMs),
                       act.duration.ubMs == kInfiniteMs ? -1.0 : seconds(act.duration.ubMs));
    extension_.activityStarted(a);
    devices_.start(a);
}

void ActivityLifecycle::stop(std::uint16_t a, std::int32_t nowMs) {
    const Activity& act = ctx_.plan().activities[a];
    cancel(a);
    if (ctx_.dispatcher.state(a) == ActivityState::kTimedOut) {
        ++counters_.late;
        ctx_.events.report(events::kActivityLate, core::Severity::kWarning, "plan_exec: %s %s timed out at %.1f s: cancelled",
                           toString(act.kind), act.name, seconds(nowMs));
    } else {
        ctx_.events.report(events::kActivityCancelled, core::Severity::kInfo, "plan_exec: %s %s cancelled at %.1f s",
                           toString(act.kind), act.name, seconds(nowMs));
    }
}

}  // namespace rse::plan_executive

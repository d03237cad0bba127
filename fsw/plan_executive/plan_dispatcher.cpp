#include "fsw/plan_executive/plan_dispatcher.hpp"

namespace rse::plan_executive {

namespace {

bool executed(std::int32_t timeMs) { return timeMs != kInfiniteMs; }

}  // namespace

const char* toString(ActivityState s) {
    switch (s) {
        case ActivityState::kInactive: return "inactive";
        case ActivityState::kWaiting: return "waiting";
        case ActivityState::kRunning: return "running";
        case ActivityState::kDone: return "done";
        case ActivityState::kTimedOut: return "timed out";
        case ActivityState::kFailed: return "failed";
        case ActivityState::kCancelled: return "cancelled";
    }
    return "?";
}

const char* toString(RegenerationReason r) {
    switch (r) {
        case RegenerationReason::kNone: return "none";
        case RegenerationReason::kLate: return "late";
        case RegenerationReason::kMissedWindow: return "missed window";
        case RegenerationReason::kEarly: return "early";
        case RegenerationReason::kActivityFailed: return "activity failed";
    }
    return "?";
}

const char* toString(ExtensionRefusal r) {
    switch (r) {
        case ExtensionRefusal::kNone: return "accepted";
        case ExtensionRefusal::kNotRunning: return "not running";
        case ExtensionRefusal::kNotScience: return "not a science activity";
        case ExtensionRefusal::kBeyondUb: return "beyond its ub";
        case ExtensionRefusal::kInconsistent: return "would make the plan inconsistent";
        case ExtensionRefusal::kBusy: return "busy";
        case ExtensionRefusal::kInvalid: return "invalid request";
    }
    return "?";
}

const char* toString(DispatchPhase p) {
    switch (p) {
        case DispatchPhase::kIdle: return "idle";
        case DispatchPhase::kChecking: return "checking";
        case DispatchPhase::kDispatching: return "dispatching";
        case DispatchPhase::kHolding: return "holding";
        case DispatchPhase::kComplete: return "complete";
    }
    return "?";
}

void DispatchOutput::clear() {
    count = 0;
    regenerate = false;
    reason = RegenerationReason::kNone;
    activity = kNoIndex;
    event = kNoIndex;
    early = false;
    heldToMs = kInfiniteMs;
}

ActivityRecord::ActivityRecord() {
    for (std::size_t a = 0; a < kMaxActivities; ++a) {
        startMs[a] = kInfiniteMs;
        endMs[a] = kInfiniteMs;
    }
}

// ---------------------------------------------------------------------------
// Start.

core::Status PlanDispatcher::begin(const Tpn& plan, const Selection& selection, const SelectionInput& input,
                                   const ActivityRecord* carried) {
    phase_ = DispatchPhase::kIdle;
    plan_ = &plan;
    selection_ = selection;
    reason_ = RegenerationReason::kNone;
    reasonActivity_ = reasonEvent_ = kNoIndex;
    counts_ = DispatchCounts{};
    lastNowMs_ = 0;
    bool ok = plan.eventCount >= 1 && plan.eventCount <= kMaxEvents && plan.activityCount <= kMaxActivities &&
              plan.constraintCount <= kMaxConstraints && plan.choiceCount <= kMaxChoices;
    // Every choice that exists under the selection has an option.
    for (std::size_t c = 0; c < plan.choiceCount && ok; ++c) {
        ok = !exists(plan.choices[c].guard, selection) || selection.option[c] < plan.choices[c].optionCount;
    }
    for (std::size_t a = 0; a < plan.activityCount && ok; ++a) {
        ok = plan.activities[a].from < plan.eventCount && plan.activities[a].to < plan.eventCount;
    }
    // loadStn() checks the times and the bounds.
    ok = ok && core::isOk(loadStn(plan, selection, input, &stn_));
    if (!ok) {
        return core::Status::kInvalidArgument;
    }
    n_ = plan.eventCount;
    activitiesExisting_ = 0;
    for (std::size_t e = 0; e < n_; ++e) {
        eventExists_[e] = e == 0 || exists(plan.events[e].guard, selection);
        eventTimeMs_[e] = e == 0 ? 0 : (eventExists_[e] ? input.executedAtMs[e] : kInfiniteMs);
        pendingIncoming_[e] = incoming_[e] = 0;
    }
    for (std::size_t k = 0; k < plan.constraintCount; ++k) {
        constraintExists_[k] = exists(plan.constraints[k].guard, selection);
    }
    // Carry-over, in place (carried may be record_ itself: each activity's
    // entry is read before it is written).
    for (std::size_t a = 0; a < kMaxActivities; ++a) {
        const ActivityState was = carried != nullptr ? carried->state[a] : ActivityState::kInactive;
        const std::int32_t wasStart = carried != nullptr ? carried->startMs[a] : kInfiniteMs;
        const std::int32_t wasEnd = carried != nullptr ? carried->endMs[a] : kInfiniteMs;
        const std::int32_t wasExtended = carried != nullptr ? carried->extendedMs[a] : 0;
        const std::int32_t wasFloor = carried != nullptr ? carried->floorMs[a] : 0;
        record_.state[a] = ActivityState::kInactive;
        record_.startMs[a] = record_.endMs[a] = kInfiniteMs;
        record_.extendedMs[a] = record_.floorMs[a] = 0;
        cancelPending_[a] = false;
        if (a >= plan.activityCount) {
            continue;
        }
        const Activity& act = plan.activities[a];
        const bool keep = was == ActivityState::kDone || was == ActivityState::kRunning;
        if (!exists(act.guard, selection)) {
            // Running and dropped by the new selection: cancelled at the first tick.
            cancelPending_[a] = was == ActivityState::kRunning;
            record_.state[a] = cancelPending_[a] ? ActivityState::kCancelled : ActivityState::kInactive;
            record_.startMs[a] = cancelPending_[a] ? wasStart : kInfiniteMs;
            continue;
        }
        ++activitiesExisting_;
        record_.state[a] = keep ? was : ActivityState::kWaiting;
        record_.startMs[a] = keep ? wasStart : kInfiniteMs;
        record_.endMs[a] = was == ActivityState::kDone ? wasEnd : kInfiniteMs;
        record_.extendedMs[a] = keep ? wasExtended : 0;
        record_.floorMs[a] = keep ? wasFloor : 0;
        // A running extended activity's end stays no earlier than its floor
        // (whether or not the input says so: its intersection with it).
        if (was == ActivityState::kRunning && wasFloor > 0 && !executed(eventTimeMs_[act.to])) {
            ok = ok && core::isOk(stn_.addBounds(0, act.to, Bounds{wasFloor, kInfiniteMs}));
        }
        ++incoming_[act.to];
        pendingIncoming_[act.to] =
            static_cast<std::uint16_t>(pendingIncoming_[act.to] + (was == ActivityState::kDone ? 0U : 1U));
        // A started activity's start event happened; an activity not done
        // cannot end at an event already executed.
        ok = ok && (!keep || executed(eventTimeMs_[act.from])) &&
             (was == ActivityState::kDone || !executed(eventTimeMs_[act.to]));
    }
    if (!ok || !core::isOk(stn_.beginCheck())) {
        return core::Status::kInvalidArgument;
    }
    phase_ = DispatchPhase::kChecking;
    return core::Status::kOk;
}

bool PlanDispatcher::stepCheck(std::uint32_t maxUnits) {
    if (phase_ != DispatchPhase::kChecking) {
        return true;
    }
    if (!stn_.step(maxUnits)) {
        return false;
    }
    if (stn_.state() == StnState::kConsistent) {
        finishStart();
    } else {
        phase_ = DispatchPhase::kIdle;
    }
    return true;
}

core::Status PlanDispatcher::start(const Tpn& plan, const Selection& selection, const SelectionInput& input,
                                   const ActivityRecord* carried) {
    if (core::isOk(begin(plan, selection, input, carried))) {
        // n^2 rows at most: one call runs the check to its end.
        (void)stepCheck(static_cast<std::uint32_t>(kMaxEvents * kMaxEvents));
    }
    return phase_ == DispatchPhase::kDispatching || phase_ == DispatchPhase::kComplete
               ? core::Status::kOk
               : core::Status::kInvalidArgument;
}

void PlanDispatcher::finishStart() {
    eventsExisting_ = eventsExecuted_ = 0;
    for (std::size_t e = 0; e < n_; ++e) {
        eventsExisting_ = static_cast<std::uint16_t>(eventsExisting_ + (eventExists_[e] ? 1U : 0U));
        eventsExecuted_ = static_cast<std::uint16_t>(eventsExecuted_ + (eventExists_[e] && executed(eventTimeMs_[e]) ? 1U : 0U));
    }
    phase_ = eventsExecuted_ == eventsExisting_ ? DispatchPhase::kComplete : DispatchPhase::kDispatching;
}

// ---------------------------------------------------------------------------
// Dispatch.

bool PlanDispatcher::push(DispatchOutput* out, DispatchCommandKind kind, std::uint16_t activity) {
    if (out->count >= DispatchOutput::kCapacity) {
        return false;  // cannot happen (see kCapacity); the activity is left for the next call
    }
    out->commands[out->count++] = DispatchCommand{kind, activity};
    return true;
}

void PlanDispatcher::fillOutput(DispatchOutput* out) const {
    out->regenerate = phase_ == DispatchPhase::kHolding;
    out->reason = reason_;
    out->activity = reasonActivity_;
    out->event = reasonEvent_;
}

void PlanDispatcher::needRegeneration(RegenerationReason r, std::uint16_t activity, std::uint16_t event) {
    if (reason_ == RegenerationReason::kNone) {
        reason_ = r;
        reasonActivity_ = activity;
        reasonEvent_ = event;
    }
    phase_ = DispatchPhase::kHolding;
}

bool PlanDispatcher::executeEvent(std::uint16_t e, std::int32_t timeMs) {
    if (stn_.execute(e, timeMs) != StnUpdate::kApplied) {
        return false;  // outside its window (or out of range): the network is as it was
    }
    eventTimeMs_[e] = timeMs;
    ++eventsExecuted_;
    ++counts_.eventsExecuted;
    if (phase_ == DispatchPhase::kDispatching && eventsExecuted_ == eventsExisting_) {
        phase_ = DispatchPhase::kComplete;
    }
    return true;
}

void PlanDispatcher::executeAfterActivities(std::uint16_t e, std::uint16_t activity, std::int32_t nowMs,
                                            RegenerationReason lateReason) {
    // An early end is held to the earliest time the network allows.
    const Window w = stn_.window(e);
    const bool held = nowMs < w.earliestMs;
    const std::int32_t at = held ? w.earliestMs : nowMs;
    if (!executeEvent(e, at)) {
        needRegeneration(held ? RegenerationReason::kEarly : lateReason, activity, e);
    }
}

bool PlanDispatcher::predecessorsExecuted(std::uint16_t e) const {
    // p must precede e when d(e, p) <= 0 (t_p <= t_e); of two events pinned
    // to one time (each <= the other), the lower index goes first, so
    // neither waits for the other forever.
    for (std::uint16_t p = 0; p < n_; ++p) {
        if (p == e || !eventExists_[p] || executed(eventTimeMs_[p]) || stn_.distance(e, p) > 0) {
            continue;
        }
        if (stn_.distance(p, e) > 0 || p < e) {
            return false;
        }
    }
    return true;
}

void PlanDispatcher::cancelLate(std::int32_t nowMs, DispatchOutput* out) {
    for (std::uint16_t a = 0; a < plan_->activityCount; ++a) {
        if (record_.state[a] != ActivityState::kRunning) {
            continue;
        }
        const Activity& act = plan_->activities[a];
        const std::int64_t ran = static_cast<std::int64_t>(nowMs) - record_.startMs[a];
        const bool pastUb = act.duration.ubMs != kInfiniteMs && ran > act.duration.ubMs;
        const std::int32_t latest = stn_.window(act.to).latestMs;
        const bool pastLatest = latest != kInfiniteMs && nowMs > latest;
        if ((pastUb || pastLatest) && push(out, DispatchCommandKind::kCancel, a)) {
            record_.state[a] = ActivityState::kTimedOut;
            record_.endMs[a] = nowMs;
            ++counts_.late;
            needRegeneration(RegenerationReason::kLate, a, act.to);
        }
    }
}

void PlanDispatcher::executeReadyEvents(std::int32_t nowMs) {
    std::size_t executions = 0;
    for (std::uint16_t e = 1; e < n_ && phase_ == DispatchPhase::kDispatching; ++e) {
        if (!eventExists_[e] || executed(eventTimeMs_[e]) || executions >= kMaxExecutionsPerTick) {
            continue;
        }
        if (incoming_[e] > 0) {
            // Its activities' completions execute it; here only when they
            // are all done already (carried over, or a completion refused).
            if (pendingIncoming_[e] == 0) {
                executeAfterActivities(e, kNoIndex, nowMs, RegenerationReason::kMissedWindow);
                ++executions;
            }
            continue;
        }
        const Window w = stn_.window(e);
        if (w.latestMs != kInfiniteMs && nowMs > w.latestMs) {
            needRegeneration(RegenerationReason::kMissedWindow, kNoIndex, e);
        } else if (nowMs >= w.earliestMs && predecessorsExecuted(e)) {
            if (!executeEvent(e, nowMs)) {
                needRegeneration(RegenerationReason::kMissedWindow, kNoIndex, e);
            }
            ++executions;
        }
    }
}

void PlanDispatcher::startReady(std::int32_t nowMs, DispatchOutput* out) {
    for (std::uint16_t a = 0; a < plan_->activityCount; ++a) {
        const std::int32_t fromMs = eventTimeMs_[plan_->activities[a].from];
        // A start event held to a later time (an early end) starts nothing before it.
        if (record_.state[a] == ActivityState::kWaiting && executed(fromMs) && nowMs >= fromMs &&
            push(out, DispatchCommandKind::kStart, a)) {
            record_.state[a] = ActivityState::kRunning;
            record_.startMs[a] = nowMs;
            ++counts_.started;
        }
    }
}

core::Status PlanDispatcher::tick(std::int32_t nowMs, DispatchOutput* out) {
    if (out == nullptr) {
        return core::Status::kInvalidArgument;
    }
    out->clear();
    const bool running = phase_ == DispatchPhase::kDispatching || phase_ == DispatchPhase::kHolding ||
                         phase_ == DispatchPhase::kComplete;
    if (!running) {
        return core::Status::kNotInitialized;
    }
    if (!timeOk(nowMs)) {
        fillOutput(out);
        return core::Status::kInvalidArgument;
    }
    lastNowMs_ = nowMs;
    for (std::uint16_t a = 0; a < plan_->activityCount; ++a) {
        if (cancelPending_[a] && push(out, DispatchCommandKind::kCancel, a)) {
            cancelPending_[a] = false;
            record_.endMs[a] = nowMs;
            ++counts_.cancelled;
        }
    }
    if (phase_ != DispatchPhase::kComplete) {
        cancelLate(nowMs, out);
        executeReadyEvents(nowMs);
        if (phase_ == DispatchPhase::kDispatching) {
            startReady(nowMs, out);
        }
    }
    fillOutput(out);
    return core::Status::kOk;
}

bool PlanDispatcher::runningActivity(std::uint16_t activity, std::int32_t nowMs) const {
    return (phase_ == DispatchPhase::kDispatching || phase_ == DispatchPhase::kHolding) &&
           activity < plan_->activityCount && record_.state[activity] == ActivityState::kRunning && timeOk(nowMs) &&
           nowMs >= record_.startMs[activity];
}

core::Status PlanDispatcher::completed(std::uint16_t activity, std::int32_t nowMs, DispatchOutput* out) {
    if (out == nullptr) {
        return core::Status::kInvalidArgument;
    }
    out->clear();
    if (!runningActivity(activity, nowMs)) {
        fillOutput(out);
        return core::Status::kInvalidArgument;
    }
    lastNowMs_ = nowMs;
    record_.state[activity] = ActivityState::kDone;
    record_.endMs[activity] = nowMs;
    ++counts_.completed;
    const std::uint16_t to = plan_->activities[activity].to;
    --pendingIncoming_[to];
    const Window w = stn_.window(to);
    if (nowMs < w.earliestMs) {
        ++counts_.early;
        out->early = true;
        out->heldToMs = w.earliestMs;
    }
    if (w.latestMs != kInfiniteMs && nowMs > w.latestMs) {
        ++counts_.late;
        needRegeneration(RegenerationReason::kLate, activity, to);
    } else if (pendingIncoming_[to] == 0) {
        executeAfterActivities(to, activity, nowMs, RegenerationReason::kLate);
    }
    fillOutput(out);
    return core::Status::kOk;
}

core::Status PlanDispatcher::failed(std::uint16_t activity, std::int32_t nowMs, DispatchOutput* out) {
    if (out == nullptr) {
        return core::Status::kInvalidArgument;
    }
    out->clear();
    if (!runningActivity(activity, nowMs)) {
        fillOutput(out);
        return core::Status::kInvalidArgument;
    }
    lastNowMs_ = nowMs;
    record_.state[activity] = ActivityState::kFailed;
    record_.endMs[activity] = nowMs;
    ++counts_.failed;
    needRegeneration(RegenerationReason::kActivityFailed, activity, plan_->activities[activity].to);
    fillOutput(out);
    return core::Status::kOk;
}

ExtensionCheck PlanDispatcher::checkExtension(std::uint16_t activity, std::int32_t nowMs, std::int32_t ownEndMs,
                                              std::int32_t extraMs) const {
    ExtensionCheck c;
    const bool timesOk = nowMs >= 0 && nowMs <= kMaxBoundMs && ownEndMs >= 0 && ownEndMs <= kMaxBoundMs &&
                         extraMs > 0 && extraMs <= kMaxBoundMs;
    if (!timesOk) {
        c.refusal = ExtensionRefusal::kInvalid;
        return c;
    }
    if (phase_ == DispatchPhase::kChecking || phase_ == DispatchPhase::kHolding) {
        c.refusal = ExtensionRefusal::kBusy;
        return c;
    }
    if (phase_ != DispatchPhase::kDispatching || plan_ == nullptr || activity >= plan_->activityCount ||
        record_.state[activity] != ActivityState::kRunning) {
        c.refusal = ExtensionRefusal::kNotRunning;
        return c;
    }
    const Activity& act = plan_->activities[activity];
    if (act.kind != ActivityKind::kSample && act.kind != ActivityKind::kImage && act.kind != ActivityKind::kDig) {
        c.refusal = ExtensionRefusal::kNotScience;
        return c;
    }
    const std::int32_t start = record_.startMs[activity];
    if (nowMs < start) {
        c.refusal = ExtensionRefusal::kInvalid;
        return c;
    }
    // Sums in 64 bits: each term is within [0, kMaxBoundMs].
    const std::int64_t expected = static_cast<std::int64_t>(ownEndMs > nowMs ? ownEndMs : nowMs) + extraMs;
    const std::int64_t floor = static_cast<std::int64_t>(nowMs) + extraMs;
    const auto clamp = [](std::int64_t v) {
        return static_cast<std::int32_t>(v >= kInfiniteMs ? kInfiniteMs - 1 : v);
    };
    c.expectedEndMs = clamp(expected);
    c.floorMs = clamp(floor);
    if (floor > kMaxBoundMs) {
        c.refusal = ExtensionRefusal::kInvalid;  // a floor no plan bound could hold
        return c;
    }
    c.latestMs = stn_.window(act.to).latestMs;
    if (act.duration.ubMs != kInfiniteMs) {
        const std::int64_t ubEnd = static_cast<std::int64_t>(start) + act.duration.ubMs;
        c.ubEndMs = clamp(ubEnd);
        if (expected > ubEnd) {
            c.refusal = ExtensionRefusal::kBeyondUb;
            return c;
        }
    }
    if (c.latestMs != kInfiniteMs && expected > c.latestMs) {
        c.refusal = ExtensionRefusal::kInconsistent;
    }
    return c;
}

ExtensionCheck PlanDispatcher::extend(std::uint16_t activity, std::int32_t nowMs, std::int32_t ownEndMs,
                                      std::int32_t extraMs) {
    ExtensionCheck c = checkExtension(activity, nowMs, ownEndMs, extraMs);
    if (c.refusal != ExtensionRefusal::kNone) {
        return c;
    }
    const std::uint16_t to = plan_->activities[activity].to;
    // t_to >= floor: the edge to -> start of weight -floor. floor <=
    // expected end <= latest, so this is consistent (the O(1) test in
    // tighten() is kept as the guard).
    const StnUpdate u = stn_.tighten(to, 0, -c.floorMs);
    if (u == StnUpdate::kInconsistent || u == StnUpdate::kRejected) {
        c.refusal = ExtensionRefusal::kInconsistent;
        return c;
    }
    record_.extendedMs[activity] = static_cast<std::int32_t>(
        static_cast<std::int64_t>(record_.extendedMs[activity]) + extraMs > kMaxBoundMs
            ? kMaxBoundMs
            : record_.extendedMs[activity] + extraMs);
    record_.floorMs[activity] = c.floorMs > record_.floorMs[activity] ? c.floorMs : record_.floorMs[activity];
    ++counts_.extended;
    if (u == StnUpdate::kOutOfRange) {
        // Applied, but a distance left the range (a network beyond the
        // documented range only): regenerated, as a refused execution is.
        needRegeneration(RegenerationReason::kLate, activity, to);
    }
    return c;
}

void PlanDispatcher::abort(DispatchOutput* out) {
    if (out != nullptr) {
        out->clear();
    }
    const std::size_t activities = plan_ != nullptr ? plan_->activityCount : 0;
    for (std::uint16_t a = 0; a < activities; ++a) {
        const bool live = record_.state[a] == ActivityState::kRunning || cancelPending_[a];
        if (live && out != nullptr && push(out, DispatchCommandKind::kCancel, a)) {
            record_.state[a] = ActivityState::kCancelled;
            record_.endMs[a] = lastNowMs_;
            cancelPending_[a] = false;
            ++counts_.cancelled;
        }
    }
    phase_ = DispatchPhase::kIdle;
}

// ---------------------------------------------------------------------------
// Regeneration and queries.

void PlanDispatcher::regenerationInput(std::int32_t nowMs, SelectionInput* input) const {
    if (input == nullptr || plan_ == nullptr) {
        return;
    }
    const Tpn& plan = *plan_;
    // An option under way: its choice's other options deprecated, and its
    // parents' likewise (bounded by the nesting depth, at most kMaxChoices).
    const auto force = [&](Guard g) {
        for (std::size_t up = 0; up < kMaxChoices && g.guarded() && g.choice < plan.choiceCount; ++up) {
            for (std::size_t o = 0; o < plan.choices[g.choice].optionCount; ++o) {
                input->deprecated[g.choice][o] = input->deprecated[g.choice][o] || o != g.option;
            }
            g = plan.choices[g.choice].guard;
        }
    };
    input->notBeforeMs = nowMs;
    for (std::size_t e = 0; e < kMaxEvents; ++e) {
        const bool done = e < n_ && eventExists_[e] && executed(eventTimeMs_[e]);
        input->executedAtMs[e] = done ? eventTimeMs_[e] : kInfiniteMs;
        input->notBeforeEventMs[e] = 0;
        if (done) {
            force(plan.events[e].guard);
        }
    }
    for (std::size_t a = 0; a < kMaxActivities; ++a) {
        const bool started = a < plan.activityCount &&
                             (record_.state[a] == ActivityState::kDone || record_.state[a] == ActivityState::kRunning);
        input->started[a] = started;
        if (started) {
            force(plan.activities[a].guard);
        }
        // An extended activity still running: its end no earlier than its floor.
        const std::uint16_t to = a < plan.activityCount ? plan.activities[a].to : 0;
        if (started && record_.state[a] == ActivityState::kRunning && record_.floorMs[a] > 0 &&
            !executed(eventTimeMs_[to]) && record_.floorMs[a] > input->notBeforeEventMs[to]) {
            input->notBeforeEventMs[to] = record_.floorMs[a];
        }
    }
}

ActivityState PlanDispatcher::state(std::uint16_t activity) const {
    return activity < kMaxActivities ? record_.state[activity] : ActivityState::kInactive;
}

std::int32_t PlanDispatcher::startMs(std::uint16_t activity) const {
    return activity < kMaxActivities ? record_.startMs[activity] : kInfiniteMs;
}

std::int32_t PlanDispatcher::endMs(std::uint16_t activity) const {
    return activity < kMaxActivities ? record_.endMs[activity] : kInfiniteMs;
}

std::int32_t PlanDispatcher::eventTimeMs(std::uint16_t event) const {
    return event < n_ && eventExists_[event] ? eventTimeMs_[event] : kInfiniteMs;
}

bool PlanDispatcher::eventExists(std::uint16_t event) const { return event < n_ && eventExists_[event]; }

bool PlanDispatcher::constraintExists(std::uint16_t constraint) const {
    return plan_ != nullptr && constraint < plan_->constraintCount && constraintExists_[constraint];
}

std::int32_t PlanDispatcher::slackMs(std::int32_t nowMs) const {
    std::int64_t least = kInfiniteMs;
    for (std::uint16_t e = 0; e < n_; ++e) {
        const std::int32_t latest = stn_.window(e).latestMs;
        if (eventExists_[e] && !executed(eventTimeMs_[e]) && latest != kInfiniteMs) {
            const std::int64_t slack = static_cast<std::int64_t>(latest) - nowMs;
            least = slack < least ? slack : least;
        }
    }
    return static_cast<std::int32_t>(least < -kInfiniteMs ? -kInfiniteMs : least);
}

DispatchSnapshot PlanDispatcher::snapshot(std::int32_t nowMs) const {
    DispatchSnapshot s;
    s.phase = phase_;
    s.reason = reason_;
    s.reasonActivity = reasonActivity_;
    s.reasonEvent = reasonEvent_;
    s.events = eventsExisting_;
    s.eventsExecuted = eventsExecuted_;
    s.activities = activitiesExisting_;
    const std::size_t activities = plan_ != nullptr ? plan_->activityCount : 0;
    for (std::size_t a = 0; a < activities; ++a) {
        const ActivityState st = record_.state[a];
        s.waiting = static_cast<std::uint16_t>(s.waiting + (st == ActivityState::kWaiting ? 1U : 0U));
        s.running = static_cast<std::uint16_t>(s.running + (st == ActivityState::kRunning ? 1U : 0U));
        s.done = static_cast<std::uint16_t>(s.done + (st == ActivityState::kDone ? 1U : 0U));
    }
    s.slackMs = slackMs(nowMs);
    s.counts = counts_;
    return s;
}

}  // namespace rse::plan_executive

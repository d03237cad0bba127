// Plan dispatch (plan_dispatcher.hpp) with simulated completions: the
// two-targets plan run to the end; an early completion held to its earliest;
// a late activity cancelled (regeneration, kLate); a failure; the grinder
// failing under sample(target 2): re-selected from where execution stands
// with the done activities carried over, image(target 2) dispatched, the
// costs before and after; a dropped running activity cancelled; events with
// no activity waiting for their windows and their predecessors, and a missed
// window; refusals; abort; the sliced check; bounded output and no heap
// over many ticks.
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/plan_dispatcher.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::plan_executive;
using rse::core::Status;
using rse::test::plan::kTwoTargetsText;
using rse::test::plan::parseText;
using rse::test::plan::PlanBuilder;

namespace {

// Static storage, as in flight.
Tpn plan;
MethodSelector selector;
SelectionResult selected;
PlanDispatcher dispatcher;
PlanDispatcher twin;
DispatchOutput out;
ActivityRecord carried;

constexpr std::int32_t kS = 1000;  // ms a second

// The two-targets plan's events and activities (parse order).
constexpr std::uint16_t kAt1 = 1, kDone1 = 2, kAt2 = 3, kDone2 = 4;
constexpr std::uint16_t kDrive1 = 0, kSample1 = 1, kImage1 = 2, kDrive2 = 3, kSample2 = 4, kImage2 = 5;
constexpr std::uint8_t kSample = 0, kImage = 1;

void parsed(const char* text) {
    const ParseResult r = parseText(text, &plan);
    CHECK_TEXT(r.error == PlanError::kOk, toString(r.error));
}

// Selects and starts dispatching under the input.
void selectAndStart(const SelectionInput& input, const ActivityRecord* previous = nullptr) {
    CHECK(selector.solve(plan, input, SelectionParams{}, &selected) == SelectionStatus::kSelected);
    CHECK(dispatcher.start(plan, selected.selection, input, previous) == Status::kOk);
}

// The output holds exactly this one command.
void onlyCommand(DispatchCommandKind kind, std::uint16_t activity) {
    CHECK_EQUAL(1, out.count);
    CHECK(out.commands[0].kind == kind);
    CHECK_EQUAL(activity, out.commands[0].activity);
}

void tickNothing(std::int32_t nowMs) {
    CHECK(dispatcher.tick(nowMs, &out) == Status::kOk);
    CHECK_EQUAL(0, out.count);
    CHECK_FALSE(out.regenerate);
}

void tickStarts(std::int32_t nowMs, std::uint16_t activity) {
    CHECK(dispatcher.tick(nowMs, &out) == Status::kOk);
    onlyCommand(DispatchCommandKind::kStart, activity);
    CHECK(dispatcher.state(activity) == ActivityState::kRunning);
    CHECK_EQUAL(nowMs, dispatcher.startMs(activity));
}

void completes(std::uint16_t activity, std::int32_t nowMs) {
    CHECK(dispatcher.completed(activity, nowMs, &out) == Status::kOk);
    CHECK_FALSE(out.regenerate);
    CHECK_FALSE(out.early);
    CHECK(dispatcher.state(activity) == ActivityState::kDone);
    CHECK_EQUAL(nowMs, dispatcher.eventTimeMs(plan.activities[activity].to));
}

// The two-targets plan, sampling both, dispatched up to sample(target 2)
// started at 1000 s: drive1 0-100 s, sample1 100-300 s, drive2 300-1000 s.
void runToSecondSample() {
    parsed(kTwoTargetsText);
    selectAndStart(SelectionInput{});
    CHECK_EQUAL(kSample, selected.selection.option[0]);
    CHECK_EQUAL(kSample, selected.selection.option[1]);
    CHECK(dispatcher.state(kImage1) == ActivityState::kInactive);
    CHECK(dispatcher.state(kSample1) == ActivityState::kWaiting);
    CHECK_EQUAL(0, dispatcher.eventTimeMs(0));
    tickStarts(0, kDrive1);
    tickNothing(50 * kS);
    completes(kDrive1, 100 * kS);
    tickStarts(100 * kS, kSample1);
    completes(kSample1, 300 * kS);
    tickStarts(300 * kS, kDrive2);
    completes(kDrive2, 1000 * kS);
    tickStarts(1000 * kS, kSample2);
}

}  // namespace

TEST_GROUP(PlanDispatcher){};

TEST(PlanDispatcher, TheTwoTargetsPlanRunsToTheEnd) {
    runToSecondSample();
    // done2 by min(3600 s deadline, at2 + 300 s): 300 s of slack at 1000 s.
    CHECK_EQUAL(300 * kS, dispatcher.slackMs(1000 * kS));
    CHECK_FALSE(dispatcher.complete());
    completes(kSample2, 1200 * kS);
    CHECK(dispatcher.complete());
    CHECK(dispatcher.phase() == DispatchPhase::kComplete);
    CHECK_EQUAL(kInfiniteMs, dispatcher.slackMs(1200 * kS));
    const DispatchCounts& c = dispatcher.counts();
    CHECK_EQUAL(4U, c.started);
    CHECK_EQUAL(4U, c.completed);
    CHECK_EQUAL(0U, c.early + c.late + c.failed + c.cancelled);
    CHECK_EQUAL(4U, c.eventsExecuted);
    const DispatchSnapshot s = dispatcher.snapshot(1200 * kS);
    CHECK_EQUAL(5, s.events);
    CHECK_EQUAL(5, s.eventsExecuted);
    CHECK_EQUAL(4, s.activities);
    CHECK_EQUAL(4, s.done);
    CHECK(dispatcher.constraintExists(0));
    CHECK_EQUAL(100 * kS, dispatcher.endMs(kDrive1));
    // A complete plan: ticks do nothing.
    tickNothing(1300 * kS);
}

TEST(PlanDispatcher, AnEarlyCompletionIsHeldToItsEarliest) {
    parsed(kTwoTargetsText);
    selectAndStart(SelectionInput{});
    tickStarts(0, kDrive1);
    // drive1 takes at least 60 s; done at 30 s: at1 is held to 60 s.
    CHECK(dispatcher.completed(kDrive1, 30 * kS, &out) == Status::kOk);
    CHECK(out.early);
    CHECK_EQUAL(60 * kS, out.heldToMs);
    CHECK_FALSE(out.regenerate);
    CHECK_EQUAL(60 * kS, dispatcher.eventTimeMs(kAt1));
    CHECK_EQUAL(1U, dispatcher.counts().early);
    // The schedule tightened: done1 now in [60 + 120, 60 + 300] s.
    CHECK_EQUAL(180 * kS, dispatcher.network().window(kDone1).earliestMs);
    CHECK_EQUAL(360 * kS, dispatcher.network().window(kDone1).latestMs);
    // Nothing starts from at1 before 60 s.
    tickNothing(40 * kS);
    tickStarts(60 * kS, kSample1);
    // The sample early too (100 s of its 120): done1 held to 180 s.
    CHECK(dispatcher.completed(kSample1, 160 * kS, &out) == Status::kOk);
    CHECK(out.early);
    CHECK_EQUAL(180 * kS, out.heldToMs);
    CHECK_EQUAL(2U, dispatcher.counts().early);
    tickNothing(170 * kS);
    tickStarts(180 * kS, kDrive2);
}

TEST(PlanDispatcher, AbortCancelsWhatRuns) {
    parsed(kTwoTargetsText);
    selectAndStart(SelectionInput{});
    tickStarts(0, kDrive1);
    dispatcher.abort(&out);
    onlyCommand(DispatchCommandKind::kCancel, kDrive1);
    CHECK(dispatcher.state(kDrive1) == ActivityState::kCancelled);
    CHECK(dispatcher.state(kSample1) == ActivityState::kWaiting);
    CHECK(dispatcher.phase() == DispatchPhase::kIdle);
    CHECK(dispatcher.tick(1, &out) == Status::kNotInitialized);
    CHECK_EQUAL(1U, dispatcher.counts().cancelled);
}

TEST(PlanDispatcher, ALateActivityIsCancelledAndThePlanRegenerated) {
    parsed(kTwoTargetsText);
    selectAndStart(SelectionInput{});
    tickStarts(0, kDrive1);
    tickNothing(900 * kS);  // its ub, not past it
    CHECK(dispatcher.tick(900 * kS + 1, &out) == Status::kOk);
    onlyCommand(DispatchCommandKind::kCancel, kDrive1);
    CHECK(out.regenerate);
    CHECK(out.reason == RegenerationReason::kLate);
    CHECK_EQUAL(kDrive1, out.activity);
    CHECK_EQUAL(kAt1, out.event);
    CHECK(dispatcher.state(kDrive1) == ActivityState::kTimedOut);
    CHECK(dispatcher.regenerationNeeded());
    CHECK_EQUAL(1U, dispatcher.counts().late);
    // Holding: nothing more is started; the timed-out drive cannot complete.
    CHECK(dispatcher.tick(901 * kS, &out) == Status::kOk);
    CHECK_EQUAL(0, out.count);
    CHECK(out.regenerate);
    CHECK(dispatcher.completed(kDrive1, 902 * kS, &out) == Status::kInvalidArgument);
}

TEST(PlanDispatcher, ACompletionAfterTheLatestIsLate) {
    parsed(kTwoTargetsText);
    selectAndStart(SelectionInput{});
    tickStarts(0, kDrive1);
    // No tick saw it late: the completion itself is.
    CHECK(dispatcher.completed(kDrive1, 950 * kS, &out) == Status::kOk);
    CHECK(out.regenerate);
    CHECK(out.reason == RegenerationReason::kLate);
    CHECK_EQUAL(kInfiniteMs, dispatcher.eventTimeMs(kAt1));
    CHECK_EQUAL(1U, dispatcher.counts().late);
}

TEST(PlanDispatcher, AFailureNeedsRegenerationAndCompletionsOfIdleActivitiesAreRefused) {
    parsed(kTwoTargetsText);
    selectAndStart(SelectionInput{});
    CHECK(dispatcher.completed(kDrive1, 0, &out) == Status::kInvalidArgument);  // waiting
    CHECK(dispatcher.completed(kImage1, 0, &out) == Status::kInvalidArgument);  // not selected
    CHECK(dispatcher.completed(999, 0, &out) == Status::kInvalidArgument);
    tickStarts(0, kDrive1);
    CHECK(dispatcher.tick(-1, &out) == Status::kInvalidArgument);
    tickNothing(20 * kS);
    CHECK(dispatcher.tick(10 * kS, &out) == Status::kInvalidArgument);  // time went back
    CHECK(dispatcher.failed(kDrive1, 30 * kS, &out) == Status::kOk);
    CHECK(out.regenerate);
    CHECK(out.reason == RegenerationReason::kActivityFailed);
    CHECK_EQUAL(kDrive1, out.activity);
    CHECK(dispatcher.state(kDrive1) == ActivityState::kFailed);
    CHECK_EQUAL(1U, dispatcher.counts().failed);
    CHECK(dispatcher.failed(kDrive1, 31 * kS, &out) == Status::kInvalidArgument);
}

TEST(PlanDispatcher, TheGrinderFailsAndThePlanGoesOnWithAnImage) {
    runToSecondSample();
    const double before = selectionCost(plan, selected.selection, SelectionInput{}, SelectionParams{});
    DOUBLES_EQUAL(32.5, before, 1e-12);
    // The grinder fails 10 s into sample(target 2).
    CHECK(dispatcher.failed(kSample2, 1010 * kS, &out) == Status::kOk);
    CHECK(out.reason == RegenerationReason::kActivityFailed);
    CHECK_EQUAL(kSample2, out.activity);
    // Re-selected from where execution stands.
    SelectionInput input;
    input.components[static_cast<std::size_t>(Component::kGrinder)] = ComponentState::kFailed;
    dispatcher.regenerationInput(1010 * kS, &input);
    CHECK_EQUAL(1010 * kS, input.notBeforeMs);
    CHECK_EQUAL(100 * kS, input.executedAtMs[kAt1]);
    CHECK_EQUAL(300 * kS, input.executedAtMs[kDone1]);
    CHECK_EQUAL(1000 * kS, input.executedAtMs[kAt2]);
    CHECK_EQUAL(kInfiniteMs, input.executedAtMs[kDone2]);
    CHECK(input.deprecated[0][kImage]);  // sample(target 1) is done: its option is forced
    CHECK_FALSE(input.deprecated[0][kSample]);
    CHECK_FALSE(input.deprecated[1][kSample]);  // the failed sample forces nothing
    // The dispatcher restarted on its own record: done activities carried over.
    selectAndStart(input, &dispatcher.activities());
    CHECK_EQUAL(kSample, selected.selection.option[0]);
    CHECK_EQUAL(kImage, selected.selection.option[1]);
    const double after = selectionCost(plan, selected.selection, input, SelectionParams{});
    DOUBLES_EQUAL(37.5, after, 1e-12);  // the image and its option cost 5 more
    DOUBLES_EQUAL(after, selected.cost, 1e-12);
    CHECK(dispatcher.state(kDrive1) == ActivityState::kDone);
    CHECK(dispatcher.state(kSample1) == ActivityState::kDone);
    CHECK(dispatcher.state(kDrive2) == ActivityState::kDone);
    CHECK_EQUAL(100 * kS, dispatcher.startMs(kSample1));
    CHECK_EQUAL(300 * kS, dispatcher.endMs(kSample1));
    CHECK(dispatcher.state(kSample2) == ActivityState::kInactive);
    CHECK(dispatcher.state(kImage2) == ActivityState::kWaiting);
    // The image's bounds run from at2 (1000 s): done2 in [1030, 1060] s.
    CHECK_EQUAL(1030 * kS, dispatcher.network().window(kDone2).earliestMs);
    CHECK_EQUAL(1060 * kS, dispatcher.network().window(kDone2).latestMs);
    tickStarts(1010 * kS, kImage2);
    completes(kImage2, 1045 * kS);
    CHECK(dispatcher.complete());
    CHECK_EQUAL(1U, dispatcher.counts().started);  // this dispatch's counts
}

TEST(PlanDispatcher, ARunningActivityTheNewSelectionDropsIsCancelled) {
    parsed(kTwoTargetsText);
    selectAndStart(SelectionInput{});
    tickStarts(0, kDrive1);
    completes(kDrive1, 100 * kS);
    tickStarts(100 * kS, kSample1);
    // The executive chose to image target 1 instead (its choice, not the
    // dispatcher's): the running sample is dropped.
    SelectionInput input;
    input.executedAtMs[kAt1] = 100 * kS;
    input.notBeforeMs = 110 * kS;
    input.deprecated[0][kSample] = true;
    carried = dispatcher.activities();
    selectAndStart(input, &carried);
    CHECK(dispatcher.state(kSample1) == ActivityState::kCancelled);
    CHECK(dispatcher.state(kDrive1) == ActivityState::kDone);
    CHECK(dispatcher.tick(110 * kS, &out) == Status::kOk);
    CHECK_EQUAL(2, out.count);
    CHECK(out.commands[0].kind == DispatchCommandKind::kCancel);
    CHECK_EQUAL(kSample1, out.commands[0].activity);
    CHECK(out.commands[1].kind == DispatchCommandKind::kStart);
    CHECK_EQUAL(kImage1, out.commands[1].activity);
    CHECK_EQUAL(1U, dispatcher.counts().cancelled);
    tickNothing(111 * kS);
}

TEST(PlanDispatcher, CarriedActivitiesMustAgreeWithTheExecutedTimes) {
    runToSecondSample();
    carried = dispatcher.activities();
    // drive2 done, but at2 not executed in the input.
    SelectionInput input;
    input.executedAtMs[kAt1] = 100 * kS;
    input.executedAtMs[kDone1] = 300 * kS;
    input.notBeforeMs = 1000 * kS;
    CHECK(selector.solve(plan, input, SelectionParams{}, &selected) == SelectionStatus::kSelected);
    CHECK(dispatcher.start(plan, selected.selection, input, &carried) == Status::kInvalidArgument);
    CHECK(dispatcher.phase() == DispatchPhase::kIdle);
    CHECK(dispatcher.tick(1000 * kS, &out) == Status::kNotInitialized);
    // A selection that leaves a choice without an option.
    Selection none;
    CHECK(dispatcher.start(plan, none, SelectionInput{}) == Status::kInvalidArgument);
    // A network that is not consistent (the selection's drives miss the deadline).
    plan.constraints[0].bounds.ubMs = 100 * kS;
    CHECK(dispatcher.start(plan, selected.selection, SelectionInput{}) == Status::kInvalidArgument);
}

TEST(PlanDispatcher, AnEventWithNoActivityWaitsForItsWindowAndItsPredecessors) {
    // ready: 50-100 s after the start, no activity into it. b: after a
    // (which a drive ends) by at most 30 s, no activity into it.
    parsed("plan w; event ready; event done; event a; event b\n"
           "constraint start ready [50, 100]\n"
           "activity work wait ready done [10, 20]\n"
           "activity go drive start a [10, 20] at 1 1\n"
           "constraint a b [0, 30]\n"
           "end\n");
    constexpr std::uint16_t kReady = 1, kDone = 2, kA = 3, kB = 4, kWork = 0, kGo = 1;
    selectAndStart(SelectionInput{});
    tickStarts(0, kGo);
    CHECK_EQUAL(20 * kS, dispatcher.slackMs(0));  // a by 20 s
    // b's earliest (10 s) is reached, but a must precede it.
    tickNothing(15 * kS);
    CHECK_EQUAL(kInfiniteMs, dispatcher.eventTimeMs(kB));
    completes(kGo, 16 * kS);
    CHECK_EQUAL(16 * kS, dispatcher.eventTimeMs(kA));
    CHECK(dispatcher.tick(17 * kS, &out) == Status::kOk);
    CHECK_EQUAL(0, out.count);
    CHECK_EQUAL(17 * kS, dispatcher.eventTimeMs(kB));
    tickNothing(49 * kS);
    CHECK_EQUAL(kInfiniteMs, dispatcher.eventTimeMs(kReady));
    tickStarts(50 * kS, kWork);  // ready executed, its activity started in the same tick
    CHECK_EQUAL(50 * kS, dispatcher.eventTimeMs(kReady));
    completes(kWork, 65 * kS);
    CHECK_EQUAL(65 * kS, dispatcher.eventTimeMs(kDone));
    CHECK(dispatcher.complete());

    // No tick until 101 s: ready's window has passed.
    CHECK(dispatcher.start(plan, selected.selection, SelectionInput{}) == Status::kOk);
    CHECK(dispatcher.tick(101 * kS, &out) == Status::kOk);
    CHECK(out.regenerate);
    CHECK(out.reason == RegenerationReason::kMissedWindow);
    CHECK_EQUAL(kReady, out.event);
    CHECK_EQUAL(kNoIndex, out.activity);
    CHECK(dispatcher.slackMs(101 * kS) < 0);
}

TEST(PlanDispatcher, ASlicedCheckEqualsTheOneShotStart) {
    parsed(kTwoTargetsText);
    CHECK(selector.solve(plan, SelectionInput{}, SelectionParams{}, &selected) == SelectionStatus::kSelected);
    CHECK(dispatcher.start(plan, selected.selection, SelectionInput{}) == Status::kOk);
    CHECK(twin.begin(plan, selected.selection, SelectionInput{}, nullptr) == Status::kOk);
    CHECK(twin.phase() == DispatchPhase::kChecking);
    std::size_t slices = 0;
    while (!twin.stepCheck(3) && slices < 100) {
        ++slices;
    }
    CHECK_EQUAL(8U, slices);  // 25 rows, 3 a slice
    CHECK(twin.phase() == DispatchPhase::kDispatching);
    for (std::size_t a = 0; a < plan.eventCount; ++a) {
        for (std::size_t b = 0; b < plan.eventCount; ++b) {
            CHECK_EQUAL(dispatcher.network().distance(a, b), twin.network().distance(a, b));
        }
    }
}

TEST(PlanDispatcher, OutputIsBoundedAndEventExecutionsPerTickAreCapped) {
    // 255 events after the start, an activity to each, one more to the last:
    // every activity starts in the first tick, and every one times out in one.
    PlanBuilder b(&plan);
    for (std::size_t e = 1; e < kMaxEvents; ++e) {
        b.event();
        b.activity(ActivityKind::kWait, 0, e, 0, 10 * kS, 1.0);
    }
    b.activity(ActivityKind::kWait, 0, kMaxEvents - 1, 0, 10 * kS, 1.0);
    CHECK_EQUAL(kMaxActivities, plan.activityCount);
    selectAndStart(SelectionInput{});
    CHECK(dispatcher.tick(0, &out) == Status::kOk);
    CHECK_EQUAL(kMaxActivities, out.count);
    CHECK(dispatcher.tick(10 * kS + 1, &out) == Status::kOk);
    CHECK_EQUAL(kMaxActivities, out.count);
    for (std::size_t i = 0; i < out.count; ++i) {
        CHECK(out.commands[i].kind == DispatchCommandKind::kCancel);
    }
    CHECK_EQUAL(kMaxActivities, dispatcher.counts().late);

    // 20 events with windows and no activity: at most kMaxExecutionsPerTick a tick.
    PlanBuilder c(&plan);
    for (std::size_t e = 1; e <= 20; ++e) {
        c.event();
        c.constraint(0, e, 10 * kS, 100 * kS);
    }
    selectAndStart(SelectionInput{});
    CHECK(dispatcher.tick(10 * kS, &out) == Status::kOk);
    CHECK_EQUAL(PlanDispatcher::kMaxExecutionsPerTick, dispatcher.counts().eventsExecuted);
    CHECK(dispatcher.tick(11 * kS, &out) == Status::kOk);
    CHECK(dispatcher.tick(12 * kS, &out) == Status::kOk);
    CHECK(dispatcher.complete());
    CHECK_EQUAL(20U, dispatcher.counts().eventsExecuted);
}

TEST(PlanDispatcher, NoHeapUseAcrossManyTicksAndARegeneration) {
    parsed(kTwoTargetsText);
    rse::test::AllocationWatch watch;
    std::size_t ticks = 0;
    for (int run = 0; run < 5; ++run) {
        selectAndStart(SelectionInput{});
        // 100 ms ticks; an activity completes a quarter of its bounds' width
        // (at most 30 s) after its lb; on odd runs sample2 fails after 5 s.
        for (std::int32_t now = 0; now <= 2000 * kS && !dispatcher.complete(); now += 100) {
            CHECK(dispatcher.tick(now, &out) == Status::kOk);
            CHECK(out.count <= DispatchOutput::kCapacity);
            ++ticks;
            for (std::uint16_t a = 0; a < plan.activityCount; ++a) {
                const Bounds& d = plan.activities[a].duration;
                const std::int64_t width = static_cast<std::int64_t>(d.ubMs) - d.lbMs;
                const std::int64_t takes = d.lbMs + (width / 4 < 30 * kS ? width / 4 : 30 * kS);
                const bool running = dispatcher.state(a) == ActivityState::kRunning;
                const std::int64_t ran = static_cast<std::int64_t>(now) - dispatcher.startMs(a);
                const bool fails = running && a == kSample2 && run % 2 == 1 && ran >= 5 * kS;
                const bool due = running && ran >= takes;
                if (fails) {
                    // Odd runs: the grinder fails; re-selected and carried over.
                    CHECK(dispatcher.failed(a, now, &out) == Status::kOk);
                    SelectionInput input;
                    input.components[static_cast<std::size_t>(Component::kGrinder)] = ComponentState::kFailed;
                    dispatcher.regenerationInput(now, &input);
                    selectAndStart(input, &dispatcher.activities());
                } else if (due) {
                    CHECK(dispatcher.completed(a, now, &out) == Status::kOk);
                }
            }
        }
        CHECK(dispatcher.complete());
        (void)dispatcher.snapshot(0);
    }
    CHECK_EQUAL(0U, watch.count());
    std::printf("\n  dispatch: %zu ticks, no heap; sizeof(PlanDispatcher) %zu B\n", ticks, sizeof(PlanDispatcher));
    CHECK(ticks > 20000);  // about 4 800 a run
}

// ---- Opportunistic science: extension of a running science activity --------

namespace {

// The two-targets plan dispatched up to sample(target 1) started at 100 s:
// done1 in [220, 400] s (sample [120, 300] s from at1; the deadline leaves
// done1 up to 3420 s, the ub binds first).
void runToFirstSample() {
    parsed(kTwoTargetsText);
    selectAndStart(SelectionInput{});
    tickStarts(0, kDrive1);
    completes(kDrive1, 100 * kS);
    tickStarts(100 * kS, kSample1);
    CHECK_EQUAL(220 * kS, dispatcher.network().window(kDone1).earliestMs);
    CHECK_EQUAL(400 * kS, dispatcher.network().window(kDone1).latestMs);
}

// The network as it stands, to show a refusal changed nothing.
Stn before;

void networkUnchanged() {
    const Stn& now = dispatcher.network();
    CHECK_EQUAL(before.size(), now.size());
    for (std::size_t i = 0; i < now.size(); ++i) {
        for (std::size_t j = 0; j < now.size(); ++j) {
            CHECK_EQUAL(before.distance(i, j), now.distance(i, j));
        }
    }
}

void refused(ExtensionRefusal why, std::uint16_t activity, std::int32_t nowMs, std::int32_t ownEndMs,
             std::int32_t extraMs) {
    before = dispatcher.network();
    CHECK_EQUAL(static_cast<int>(why),
                static_cast<int>(dispatcher.checkExtension(activity, nowMs, ownEndMs, extraMs).refusal));
    CHECK_EQUAL(static_cast<int>(why), static_cast<int>(dispatcher.extend(activity, nowMs, ownEndMs, extraMs).refusal));
    networkUnchanged();
    CHECK_EQUAL(0U, dispatcher.counts().extended);
}

}  // namespace

TEST(PlanDispatcher, AnExtensionWithinItsUbAndThePlanRaisesItsEndsFloor) {
    runToFirstSample();
    // At 250 s the sample is expected to end at 260 s; 100 s more: 360 s, within
    // start + ub (400 s) and its end's latest (400 s).
    before = dispatcher.network();
    const ExtensionCheck c = dispatcher.checkExtension(kSample1, 250 * kS, 260 * kS, 100 * kS);
    CHECK(c.refusal == ExtensionRefusal::kNone);
    CHECK_EQUAL(360 * kS, c.expectedEndMs);
    CHECK_EQUAL(400 * kS, c.ubEndMs);
    CHECK_EQUAL(400 * kS, c.latestMs);
    CHECK_EQUAL(350 * kS, c.floorMs);
    networkUnchanged();  // the check changes nothing
    const ExtensionCheck e = dispatcher.extend(kSample1, 250 * kS, 260 * kS, 100 * kS);
    CHECK(e.refusal == ExtensionRefusal::kNone);
    // The extra work cannot be done before 350 s: done1 no earlier, and
    // drive2 (lb 60 s) cannot reach at2 before 410 s; the latest unchanged.
    CHECK_EQUAL(350 * kS, dispatcher.network().window(kDone1).earliestMs);
    CHECK_EQUAL(400 * kS, dispatcher.network().window(kDone1).latestMs);
    CHECK_EQUAL(410 * kS, dispatcher.network().window(kAt2).earliestMs);
    CHECK_EQUAL(1U, dispatcher.counts().extended);
    CHECK_EQUAL(100 * kS, dispatcher.activities().extendedMs[kSample1]);
    CHECK_EQUAL(350 * kS, dispatcher.activities().floorMs[kSample1]);
    // A second extension is judged likewise: at 300 s, the end expected at
    // 360 s, 40 s more fits (400 s), 40.001 s does not.
    CHECK(dispatcher.checkExtension(kSample1, 300 * kS, 360 * kS, 40 * kS).refusal == ExtensionRefusal::kNone);
    CHECK(dispatcher.checkExtension(kSample1, 300 * kS, 360 * kS, 40 * kS + 1).refusal ==
          ExtensionRefusal::kBeyondUb);  // start + ub and the latest are both 400 s: the ub is checked first
    // Completion of the extended work at 340 s is before the floor: early, held to it.
    tickNothing(340 * kS);
    CHECK(dispatcher.completed(kSample1, 340 * kS, &out) == Status::kOk);
    CHECK(out.early);
    CHECK_EQUAL(350 * kS, out.heldToMs);
    CHECK_EQUAL(350 * kS, dispatcher.eventTimeMs(kDone1));
    tickNothing(349 * kS);  // drive2 waits for its start event's time
    tickStarts(350 * kS, kDrive2);
}

TEST(PlanDispatcher, AnExtendedActivityIsStillLateAfterItsUb) {
    runToFirstSample();
    CHECK(dispatcher.extend(kSample1, 250 * kS, 260 * kS, 100 * kS).refusal == ExtensionRefusal::kNone);
    // Never beyond ub: the extended sample is cancelled 1 ms past 400 s.
    tickNothing(400 * kS);
    CHECK(dispatcher.tick(400 * kS + 1, &out) == Status::kOk);
    onlyCommand(DispatchCommandKind::kCancel, kSample1);
    CHECK(out.reason == RegenerationReason::kLate);
    CHECK(dispatcher.state(kSample1) == ActivityState::kTimedOut);
}

TEST(PlanDispatcher, ExtensionsRefusedWithTheirReasonLeaveTheNetworkAsItWas) {
    runToFirstSample();
    refused(ExtensionRefusal::kNotRunning, kDrive1, 150 * kS, 150 * kS, 10 * kS);   // done (and a drive)
    refused(ExtensionRefusal::kNotRunning, kSample2, 150 * kS, 150 * kS, 10 * kS);  // waiting
    refused(ExtensionRefusal::kNotRunning, kImage1, 150 * kS, 150 * kS, 10 * kS);   // not in the selection
    refused(ExtensionRefusal::kNotRunning, 999, 150 * kS, 150 * kS, 10 * kS);
    // 150 s expected, 200 s more: 450 s, past start + ub.
    refused(ExtensionRefusal::kBeyondUb, kSample1, 150 * kS, 250 * kS, 200 * kS);
    refused(ExtensionRefusal::kInvalid, kSample1, 150 * kS, 250 * kS, 0);
    refused(ExtensionRefusal::kInvalid, kSample1, -1, 250 * kS, 10 * kS);
    refused(ExtensionRefusal::kInvalid, kSample1, 50 * kS, 250 * kS, 10 * kS);  // before its start
    refused(ExtensionRefusal::kInvalid, kSample1, 150 * kS, 250 * kS, kMaxBoundMs + 1);
    // A drive running is not science either.
    tickNothing(150 * kS);
    completes(kSample1, 250 * kS);
    tickStarts(250 * kS, kDrive2);
    refused(ExtensionRefusal::kNotScience, kDrive2, 260 * kS, 260 * kS, 10 * kS);
    refused(ExtensionRefusal::kNotRunning, kSample1, 260 * kS, 260 * kS, 10 * kS);  // done
}

TEST(PlanDispatcher, AnExtensionPastALaterDeadlineIsInconsistent) {
    // Sample then a 20 s report, all within 260 s: done1 by 240 s, whatever
    // the sample's own ub (start + 300 s).
    parsed("plan deadline\n"
           "event at1\n"
           "event done1\n"
           "event back\n"
           "activity drive1 drive start at1 [10, 100] cost 1 at 10 0\n"
           "activity sample1 sample at1 done1 [120, 300] cost 1 target 1\n"
           "activity report communicate done1 back [20, 20] cost 1\n"
           "constraint start back [0, 260]\n"
           "end\n");
    selectAndStart(SelectionInput{});
    tickStarts(0, 0);
    completes(0, 20 * kS);
    tickStarts(20 * kS, 1);
    CHECK_EQUAL(240 * kS, dispatcher.network().window(2).latestMs);
    // Expected at 170 s; 80 s more ends at 250 s: within start + ub (320 s),
    // past done1's latest.
    refused(ExtensionRefusal::kInconsistent, 1, 50 * kS, 170 * kS, 80 * kS);
    const ExtensionCheck c = dispatcher.checkExtension(1, 50 * kS, 170 * kS, 80 * kS);
    CHECK_EQUAL(250 * kS, c.expectedEndMs);
    CHECK_EQUAL(320 * kS, c.ubEndMs);
    CHECK_EQUAL(240 * kS, c.latestMs);
    // 70 s fits exactly.
    CHECK(dispatcher.extend(1, 50 * kS, 170 * kS, 70 * kS).refusal == ExtensionRefusal::kNone);
    CHECK_EQUAL(140 * kS, dispatcher.network().window(2).earliestMs);  // 50 + 70 s < 20 + 120 s: no tighter
}

TEST(PlanDispatcher, ExtensionsAreRefusedAsBusyWhileCheckingOrHolding) {
    parsed(kTwoTargetsText);
    CHECK(selector.solve(plan, SelectionInput{}, SelectionParams{}, &selected) == SelectionStatus::kSelected);
    CHECK(dispatcher.begin(plan, selected.selection, SelectionInput{}, nullptr) == Status::kOk);
    CHECK(dispatcher.checkExtension(kSample1, 0, 0, kS).refusal == ExtensionRefusal::kBusy);
    CHECK_TRUE(dispatcher.stepCheck(kMaxEvents * kMaxEvents));
    tickStarts(0, kDrive1);
    CHECK(dispatcher.failed(kDrive1, 10 * kS, &out) == Status::kOk);
    CHECK(dispatcher.checkExtension(kDrive1, 20 * kS, 20 * kS, kS).refusal == ExtensionRefusal::kBusy);
    CHECK(dispatcher.extend(kSample1, 20 * kS, 20 * kS, kS).refusal == ExtensionRefusal::kBusy);
}

TEST(PlanDispatcher, ARegenerationKeepsARunningActivitysExtension) {
    runToFirstSample();
    CHECK(dispatcher.extend(kSample1, 250 * kS, 260 * kS, 100 * kS).refusal == ExtensionRefusal::kNone);
    // The re-selection is told the end's floor ...
    SelectionInput input;
    input.notBeforeEventMs[kDone2] = 7;  // stale: overwritten
    dispatcher.regenerationInput(260 * kS, &input);
    CHECK_EQUAL(350 * kS, input.notBeforeEventMs[kDone1]);
    CHECK_EQUAL(0, input.notBeforeEventMs[kDone2]);
    CHECK(input.started[kSample1]);
    carried = dispatcher.activities();
    selectAndStart(input, &carried);
    CHECK(dispatcher.state(kSample1) == ActivityState::kRunning);
    CHECK_EQUAL(100 * kS, dispatcher.activities().extendedMs[kSample1]);
    CHECK_EQUAL(350 * kS, dispatcher.network().window(kDone1).earliestMs);
    // ... and the restarted dispatcher keeps it from its record even when the input does not.
    input.notBeforeEventMs[kDone1] = 0;
    carried = dispatcher.activities();
    selectAndStart(input, &carried);
    CHECK_EQUAL(350 * kS, dispatcher.network().window(kDone1).earliestMs);
    // A floor past the range is refused with the other times.
    input.notBeforeEventMs[kDone1] = kMaxBoundMs + 1;
    CHECK(selector.start(plan, input, SelectionParams{}) == Status::kInvalidArgument);
}

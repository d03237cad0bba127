// The executive's status (plan_status.hpp): PlanExecutiveStatusMsg assembled
// from the parts' figures, without a plan (no name, no options, slack
// unbounded) and with the two-targets plan dispatching (its name, choices and
// chosen options, the deprecated options, the activities' states a nibble
// each, how many run, the plan time and the least slack); published.
#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/plan_executive/plan_status.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::plan_executive;

namespace {

// Static storage, as in flight.
Tpn statusPlan;
MethodSelector statusSelector;
PlanDispatcher statusDispatcher;
DispatchOutput statusOut;
msg::PlanExecutiveStatusMsg status;

StatusFigures someFigures() {
    StatusFigures f;
    f.timeNs = 1234 * core::kNsPerMs;
    f.state = msg::PlanExecutiveState::kDispatching;
    f.selectionStatus = SelectionStatus::kSelected;
    f.cost = 32.5;
    f.costBefore = 30.0;
    f.plans.accepted = 2;
    f.plans.refused = 3;
    f.plans.lastRefusal = msg::PlanRefusal::kParse;
    f.plans.lastParse.error = PlanError::kUnknownActivityKind;
    f.plans.lastParse.line = 7;
    std::memcpy(f.plans.lastParse.token, "fly", 4);
    f.plans.operatorCalls = 1;
    f.plans.callHomeReason = 7;
    f.activities = ActivityCounters{5, 4, 1, 2, 3};
    f.regeneration.regenerations = 6;
    f.regeneration.last = msg::PlanRegeneration::kComponentFailed;
    f.extensions.accepted = 8;
    f.extensions.refused = 9;
    f.extensions.lastRefusal = msg::PlanExtensionRefusal::kBusy;
    return f;
}

}  // namespace

TEST_GROUP(PlanStatus){};

TEST(PlanStatus, WithoutAPlanTheFiguresAreAllItSays) {
    std::memset(&status, 0x5A, sizeof status);  // afresh: nothing of before stays
    assembleStatus(someFigures(), StatusPlanView{}, &status);
    LONGS_EQUAL(1234 * core::kNsPerMs, status.timeNs);
    CHECK(status.state == msg::PlanExecutiveState::kDispatching);
    LONGS_EQUAL(static_cast<long>(SelectionStatus::kSelected), status.selectionStatus);
    CHECK(status.lastRefusal == msg::PlanRefusal::kParse);
    LONGS_EQUAL(static_cast<long>(PlanError::kUnknownActivityKind), status.lastParseError);
    LONGS_EQUAL(7, status.refusalLine);
    STRCMP_EQUAL("fly", status.refusalToken);
    CHECK(status.lastRegeneration == msg::PlanRegeneration::kComponentFailed);
    LONGS_EQUAL(7, status.callHomeReason);
    DOUBLES_EQUAL(32.5, status.cost, 0.0);
    DOUBLES_EQUAL(30.0, status.costBefore, 0.0);
    LONGS_EQUAL(2, status.plansAccepted);
    LONGS_EQUAL(3, status.plansRefused);
    LONGS_EQUAL(6, status.regenerations);
    LONGS_EQUAL(5, status.activitiesStarted);
    LONGS_EQUAL(4, status.activitiesCompleted);
    LONGS_EQUAL(1, status.activitiesEarly);
    LONGS_EQUAL(2, status.activitiesLate);
    LONGS_EQUAL(3, status.activitiesFailed);
    LONGS_EQUAL(1, status.operatorCalls);
    LONGS_EQUAL(8, status.extensionsAccepted);
    LONGS_EQUAL(9, status.extensionsRefused);
    CHECK(status.lastExtensionRefusal == msg::PlanExtensionRefusal::kBusy);
    // No plan: no name, no choices, no activities, no plan time, slack unbounded.
    STRCMP_EQUAL("", status.planName);
    LONGS_EQUAL(0, status.choiceCount);
    LONGS_EQUAL(0, status.activityCount);
    LONGS_EQUAL(0, status.deprecatedCount);
    LONGS_EQUAL(0, status.planTimeMs);
    LONGS_EQUAL(kInfiniteMs, status.slackMs);
    for (std::uint8_t o : status.options) {
        LONGS_EQUAL(kNoOption, o);
    }
    for (std::uint8_t s : status.activityStates) {
        LONGS_EQUAL(0, s);
    }
}

TEST(PlanStatus, WithAPlanItsNameOptionsAndActivitiesAreShown) {
    CHECK(test::plan::parseText(test::plan::kTwoTargetsText, &statusPlan).error == PlanError::kOk);
    SelectionResult r;
    CHECK(statusSelector.solve(statusPlan, SelectionInput{}, SelectionParams{}, &r) == SelectionStatus::kSelected);
    CHECK(core::isOk(statusDispatcher.start(statusPlan, r.selection, SelectionInput{})));
    CHECK(core::isOk(statusDispatcher.tick(0, &statusOut)));  // drive1 starts
    StatusPlanView v;
    v.plan = &statusPlan;
    v.selection = &r.selection;
    v.dispatcher = &statusDispatcher;
    v.planMs = 5000;
    v.deprecatedCount = 1;
    assembleStatus(someFigures(), v, &status);
    STRCMP_EQUAL("two_targets", status.planName);
    LONGS_EQUAL(2, status.choiceCount);
    LONGS_EQUAL(6, status.activityCount);
    LONGS_EQUAL(0, status.options[0]);  // sample, sample: the cheapest
    LONGS_EQUAL(0, status.options[1]);
    LONGS_EQUAL(kNoOption, status.options[2]);
    LONGS_EQUAL(1, status.deprecatedCount);
    LONGS_EQUAL(5000, status.planTimeMs);
    LONGS_EQUAL(statusDispatcher.slackMs(5000), status.slackMs);
    LONGS_EQUAL(1, status.running);
    // drive1 (0) running, sample1 (1) waiting; image1 (2) inactive, drive2 (3) waiting.
    LONGS_EQUAL(static_cast<long>(ActivityState::kRunning) | static_cast<long>(ActivityState::kWaiting) << 4,
                status.activityStates[0]);
    LONGS_EQUAL(static_cast<long>(ActivityState::kInactive) | static_cast<long>(ActivityState::kWaiting) << 4,
                status.activityStates[1]);
}

TEST(PlanStatus, PublishedOnTheBus) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    ExecutiveContext* ctx = new ExecutiveContext(bus, events);  // two plans: not on the stack
    PlanStatusReport report;
    core::PipeId probe = 0;
    CHECK(core::isOk(bus.createPipe("probe", 2, &probe)));
    CHECK(core::isOk(bus.subscribe(probe, msg::ids::kPlanExecutiveStatus)));
    report.publish(*ctx, someFigures(), StatusPlanView{});
    LONGS_EQUAL(0, ctx->publishFailures);
    LONGS_EQUAL(2, report.message().plansAccepted);
    core::Message m{};
    msg::PlanExecutiveStatusMsg taken{};
    CHECK(core::isOk(bus.receive(probe, &m)));
    CHECK(core::isOk(m.decode(&taken)));
    LONGS_EQUAL(3, taken.plansRefused);
    LONGS_EQUAL(kInfiniteMs, taken.slackMs);
    delete ctx;
}

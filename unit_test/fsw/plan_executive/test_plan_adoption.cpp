// Selection and adoption (plan_adoption.hpp), on the executive's parts
// without the task: a plan text parsed, selected and adopted (950) and its
// check run to dispatching; a parse error refused with its reason, line and
// token and the plan running kept (953); a plan with no valid selection
// refused (954); a new plan superseding the running one (967); PLAN_ABORT
// (965); a regeneration adopted with the cost before and after (963); no
// method left calling the operator (966, SafeRequestMsg).
#include <cstdint>
#include <cstring>

#include "fsw/plan_executive/plan_executive_events.hpp"
#include "unit_test/fsw/plan_executive/executive_parts.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using msg::PlanExecutiveState;
using plan_executive::ActivityState;
namespace ev = plan_executive::events;

namespace {

constexpr const char* kWait = "plan waiting;event e;activity w wait start e [100, 200] cost 1;end";
constexpr const char* kBadKind = "plan bad\nevent a\nactivity x fly start a [1, 2] cost 1\nend\n";
// Parses, but 10 s of waiting cannot fit in 5 s.
constexpr const char* kTight = "plan tight;event a;activity w wait start a [10, 20] cost 1;constraint start a [0, 5];end";

test::ExecutiveParts* parts = nullptr;

}  // namespace

TEST_GROUP(PlanAdoption) {
    void setup() override {
        parts = new test::ExecutiveParts();
        CHECK_TRUE(parts->init());
    }
    void teardown() override {
        delete parts;
        parts = nullptr;
    }
};

TEST(PlanAdoption, APlanIsSelectedAdoptedAndChecked) {
    parts->adoption.beginNewPlan(kWait, std::strlen(kWait), false);
    CHECK(parts->ctx.state == PlanExecutiveState::kSelecting);
    CHECK(parts->ctx.job == plan_executive::SelectionJob::kSelectNew);
    CHECK_TRUE(parts->adopt(kWait));
    LONGS_EQUAL(1, parts->count(ev::kSelectionDone));
    LONGS_EQUAL(1, parts->count(ev::kPlanAccepted));
    LONGS_EQUAL(1, parts->adoption.counters().accepted);
    STRCMP_EQUAL("waiting", parts->ctx.plan().name);
    CHECK_FALSE(parts->ctx.goalPlan);
    DOUBLES_EQUAL(1.0, parts->adoption.cost(), 1e-12);
    LONGS_EQUAL(parts->ctx.now, parts->ctx.planStartNs);  // its time starts now
}

TEST(PlanAdoption, AParseErrorIsRefusedWithItsReasonAndThePlanRunningKept) {
    CHECK_TRUE(parts->adopt(kWait));
    parts->adoption.beginNewPlan(kBadKind, std::strlen(kBadKind), false);
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kParseRefused));
    const plan_executive::PlanCounters& c = parts->adoption.counters();
    LONGS_EQUAL(1, c.refused);
    CHECK(c.lastRefusal == msg::PlanRefusal::kParse);
    CHECK(c.lastParse.error == plan_executive::PlanError::kUnknownActivityKind);
    LONGS_EQUAL(3, c.lastParse.line);
    STRCMP_EQUAL("fly", c.lastParse.token);
    STRCMP_EQUAL("waiting", parts->ctx.plan().name);
    CHECK(parts->ctx.state == PlanExecutiveState::kDispatching);
    CHECK(parts->ctx.job == plan_executive::SelectionJob::kNone);
}

TEST(PlanAdoption, APlanWithNoValidSelectionIsRefused) {
    CHECK_TRUE(parts->adopt(kWait));
    parts->adopt(kTight);
    LONGS_EQUAL(1, parts->count(ev::kSelectionRefused));
    CHECK(parts->adoption.counters().lastRefusal == msg::PlanRefusal::kNoSelection);
    STRCMP_EQUAL("waiting", parts->ctx.plan().name);
    CHECK(parts->ctx.state == PlanExecutiveState::kDispatching);
    // Refusals the others find (the upload's, busy) are counted here too.
    parts->adoption.refuse(msg::PlanRefusal::kBusy, ev::kUploadRefused, "busy");
    parts->drain();
    LONGS_EQUAL(2, parts->adoption.counters().refused);
    LONGS_EQUAL(1, parts->count(ev::kUploadRefused));
}

TEST(PlanAdoption, ANewPlanSupersedesTheRunningOneAndAbortStopsIt) {
    CHECK_TRUE(parts->adopt(kWait));
    parts->advance();
    CHECK(parts->state(0) == ActivityState::kRunning);
    CHECK_TRUE(parts->adopt(test::plan::kTwoTargetsText));
    LONGS_EQUAL(1, parts->count(ev::kPlanSuperseded));
    LONGS_EQUAL(1, parts->count(ev::kActivityCancelled));  // the wait
    STRCMP_EQUAL("two_targets", parts->ctx.plan().name);
    parts->advance();
    parts->adoption.abort(false);
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kPlanAborted));
    CHECK(parts->ctx.state == PlanExecutiveState::kIdle);
    LONGS_EQUAL(0, parts->lastGoal.goals.count);  // drive1's goal cleared
}

TEST(PlanAdoption, ARegenerationIsAdoptedWithTheCostBeforeAndAfter) {
    CHECK_TRUE(parts->adopt(test::plan::kTwoTargetsText));
    parts->advance();
    msg::InstrumentStatusMsg grinder{};
    grinder.instrument = msg::Instrument::kGrinder;
    grinder.state = msg::InstrumentState::kOffline;
    parts->components.takeInstrument(grinder);
    CHECK_TRUE(parts->regeneration.checkComponents());
    parts->adoption.startRegeneration(parts->ctx.planMs());
    CHECK(parts->ctx.state == PlanExecutiveState::kRegenerating);
    for (int i = 0; i < 50 && parts->ctx.job != plan_executive::SelectionJob::kNone; ++i) {
        parts->adoption.stepSelection();
    }
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kRegenerated));
    DOUBLES_EQUAL(32.5, parts->adoption.costBefore(), 1e-9);
    DOUBLES_EQUAL(42.5, parts->adoption.cost(), 1e-9);  // both targets imaged: 2 x (8 + 2) for 2 x 5
    LONGS_EQUAL(1, parts->adoption.selection().option[0]);
    CHECK(parts->ctx.state == PlanExecutiveState::kDispatching);
    CHECK(parts->state(0) == ActivityState::kRunning);  // drive1 carried over
}

TEST(PlanAdoption, NoMethodLeftCallsTheOperator) {
    CHECK_TRUE(parts->adopt(kWait));
    parts->adoption.callOperator("test");
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kOperatorCalled));
    LONGS_EQUAL(1, parts->safeRequests);
    LONGS_EQUAL(1, parts->adoption.counters().operatorCalls);
    LONGS_EQUAL(static_cast<long>(msg::CallHomeReason::kPlanNoMethod), parts->adoption.counters().callHomeReason);
    CHECK(parts->ctx.state == PlanExecutiveState::kFailed);
}

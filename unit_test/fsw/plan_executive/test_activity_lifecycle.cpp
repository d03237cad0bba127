// Dispatch and the activities' lifecycle (activity_lifecycle.hpp), on the
// executive's parts without the task: waits and a communicate completed at
// their lb to the plan's end (956, 957, 964); a drive started as a goal and
// completed on the deliberative layer's complete, then a sample commanded; an
// early completion held (958); a timeout past the ub cancelled and late (959);
// an instrument giving up at the ub late, the regeneration's reason late; a
// refusal failing the activity (960); the dispatch stopped cancelling what
// runs (961).
#include <cstdint>

#include "fsw/plan_executive/plan_executive_events.hpp"
#include "unit_test/fsw/plan_executive/executive_parts.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using plan_executive::ActivityState;
namespace ev = plan_executive::events;

namespace {

constexpr const char* kWaits =
    "plan waits\n"
    "event a\n"
    "event b\n"
    "event c\n"
    "activity w1 wait start a [1, 5] cost 1\n"
    "activity w2 wait a b [2, 5] cost 1\n"
    "activity talk communicate b c [1, 2] cost 1\n"
    "end\n";

// One sample at the start, [lb, ub] given.
constexpr const char* kLoneSample = "plan lone;event e;activity s sample start e [10, 20] cost 1 target 1;end";

test::ExecutiveParts* parts = nullptr;

}  // namespace

TEST_GROUP(ActivityLifecycle) {
    void setup() override {
        parts = new test::ExecutiveParts();
        CHECK_TRUE(parts->init());
    }
    void teardown() override {
        delete parts;
        parts = nullptr;
    }
    // The lone sample running on the grinder: its command id.
    std::uint16_t sampleRunning() {
        CHECK_TRUE(parts->adopt(kLoneSample));
        parts->advance();
        CHECK(parts->state(0) == ActivityState::kRunning);
        CHECK(parts->lastInstrument.action == msg::InstrumentAction::kSample);
        return parts->lastInstrument.commandId;
    }
};

TEST(ActivityLifecycle, WaitsCompleteAtTheirLbAndThePlanCompletes) {
    CHECK_TRUE(parts->adopt(kWaits));
    bool complete = false;
    for (int i = 0; i < 100 && !complete; ++i) {
        complete = parts->advance();
    }
    CHECK_TRUE(complete);
    CHECK(parts->ctx.state == msg::PlanExecutiveState::kComplete);
    LONGS_EQUAL(3, parts->count(ev::kActivityStarted));
    LONGS_EQUAL(3, parts->count(ev::kActivityCompleted));
    LONGS_EQUAL(1, parts->count(ev::kPlanComplete));
    LONGS_EQUAL(3, parts->lifecycle.counters().started);
    LONGS_EQUAL(3, parts->lifecycle.counters().completed);
    LONGS_EQUAL(0, parts->goalsSent + parts->instrumentCommands);  // waits and talks need no device
}

TEST(ActivityLifecycle, ADriveIsAGoalCompletedByTheDeliberativeLayerThenTheSampleIsCommanded) {
    CHECK_TRUE(parts->adopt(test::plan::kTwoTargetsText));
    parts->advance();
    CHECK(parts->state(0) == ActivityState::kRunning);
    LONGS_EQUAL(1, parts->goalsSent);
    const std::uint32_t revision = parts->lastGoal.goals.revision;
    CHECK(revision >= plan_executive::ActivityDevices::kGoalRevisionBase);
    parts->tick(600);  // drive1's lb: 60 s
    msg::PlanStatusMsg status{};
    status.goalRevision = revision;
    status.state = msg::DeliberativeState::kComplete;
    parts->lifecycle.takePlanStatus(status);
    parts->drain();
    CHECK(parts->state(0) == ActivityState::kDone);
    LONGS_EQUAL(1, parts->count(ev::kActivityCompleted));
    parts->advance();
    CHECK(parts->state(1) == ActivityState::kRunning);  // sample1
    CHECK(parts->lastInstrument.action == msg::InstrumentAction::kSample);
    LONGS_EQUAL(1, parts->lastInstrument.targetId);
    DOUBLES_EQUAL(300.0, parts->lastInstrument.maxDurationS, 1e-9);  // its ub, the instrument's own limit
}

TEST(ActivityLifecycle, ACompletionBeforeTheLbIsEarlyAndHeld) {
    const std::uint16_t id = sampleRunning();
    parts->tick(20);  // 2 s of a 10 s lb
    parts->reportInstrument(parts->instrumentStatus(msg::Instrument::kGrinder, msg::InstrumentState::kDone, id));
    CHECK(parts->state(0) == ActivityState::kDone);
    LONGS_EQUAL(1, parts->count(ev::kActivityEarly));
    LONGS_EQUAL(1, parts->lifecycle.counters().early);
    LONGS_EQUAL(1, parts->lifecycle.counters().completed);
    LONGS_EQUAL(0, parts->devices.commandId(0));  // its command is over
}

TEST(ActivityLifecycle, PastItsUbAnActivityIsTimedOutCancelledAndLate) {
    const std::uint16_t id = sampleRunning();
    for (int i = 0; i < 300 && parts->state(0) == ActivityState::kRunning; ++i) {
        parts->advance();
    }
    CHECK(parts->state(0) == ActivityState::kTimedOut);
    LONGS_EQUAL(1, parts->count(ev::kActivityLate));
    LONGS_EQUAL(1, parts->lifecycle.counters().late);
    CHECK(parts->lastInstrument.action == msg::InstrumentAction::kCancel);
    LONGS_EQUAL(id, parts->lastInstrument.commandId);
    CHECK_TRUE(parts->ctx.dispatcher.regenerationNeeded());
}

TEST(ActivityLifecycle, AnInstrumentGivingUpAtTheUbIsLateAndSoIsTheRegeneration) {
    const std::uint16_t id = sampleRunning();
    parts->tick(150);
    msg::InstrumentStatusMsg m = parts->instrumentStatus(msg::Instrument::kGrinder, msg::InstrumentState::kFailed, id);
    m.result = msg::InstrumentResult::kTimedOut;
    parts->reportInstrument(m);
    CHECK(parts->state(0) == ActivityState::kFailed);
    LONGS_EQUAL(1, parts->count(ev::kActivityLate));
    LONGS_EQUAL(1, parts->lifecycle.counters().late);
    LONGS_EQUAL(0, parts->lifecycle.counters().failed);
    CHECK_TRUE(parts->lifecycle.takeLateByDevice());
    CHECK_FALSE(parts->lifecycle.takeLateByDevice());  // taken once
}

TEST(ActivityLifecycle, ARefusalOrAnOfflineInstrumentFailsTheActivity) {
    const std::uint16_t id = sampleRunning();
    // A refusal of another command is not about it.
    msg::InstrumentStatusMsg other = parts->instrumentStatus(msg::Instrument::kGrinder, msg::InstrumentState::kIdle, 0);
    other.lastRefusal = msg::InstrumentRefusal::kBusy;
    other.lastRefusedCommandId = static_cast<std::uint16_t>(id + 1);
    parts->reportInstrument(other);
    CHECK(parts->state(0) == ActivityState::kRunning);
    // The camera's status is not about a grinder's activity.
    parts->reportInstrument(parts->instrumentStatus(msg::Instrument::kCamera, msg::InstrumentState::kDone, id));
    CHECK(parts->state(0) == ActivityState::kRunning);
    other.lastRefusedCommandId = id;
    parts->reportInstrument(other);
    CHECK(parts->state(0) == ActivityState::kFailed);
    LONGS_EQUAL(1, parts->count(ev::kActivityFailed));
    LONGS_EQUAL(1, parts->lifecycle.counters().failed);
    CHECK_FALSE(parts->lifecycle.takeLateByDevice());
}

TEST(ActivityLifecycle, StoppingTheDispatchCancelsWhatRuns) {
    const std::uint16_t id = sampleRunning();
    parts->lifecycle.cancelDispatch();
    parts->drain();
    CHECK(parts->ctx.dispatcher.phase() == plan_executive::DispatchPhase::kIdle);
    CHECK(parts->lastInstrument.action == msg::InstrumentAction::kCancel);
    LONGS_EQUAL(id, parts->lastInstrument.commandId);
    LONGS_EQUAL(1, parts->count(ev::kActivityCancelled));
    LONGS_EQUAL(0, parts->devices.commandId(0));
    CHECK_FALSE(parts->ctx.checking);
}

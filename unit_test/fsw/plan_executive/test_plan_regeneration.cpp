// Regeneration's triggers and input (plan_regeneration.hpp), on the
// executive's parts without the task, the two-targets plan dispatching: the
// grinder offline deprecates the waiting samples' options (973) while the
// running drive is untouched; a failed drive mode fails the running drive it
// asks (its goal cleared, 960); the input of the re-selection keeps the
// executive's deprecations and the components as now, counted with its
// reason (component failed, late, a device's late failure), evented (962);
// a new plan forgets the deprecations.
#include <cstdint>

#include "fsw/plan_executive/plan_executive_events.hpp"
#include "unit_test/fsw/plan_executive/executive_parts.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using plan_executive::ActivityState;
using plan_executive::Component;
using plan_executive::ComponentState;
namespace ev = plan_executive::events;

namespace {

test::ExecutiveParts* parts = nullptr;
const plan_executive::SelectionInput* inForce = nullptr;  // the selection in force's input (2.6 KB: not on the stack)

}  // namespace

TEST_GROUP(PlanRegeneration) {
    void setup() override {
        parts = new test::ExecutiveParts();
        inForce = new plan_executive::SelectionInput();
        CHECK_TRUE(parts->init());
        CHECK_TRUE(parts->adopt(test::plan::kTwoTargetsText));
        parts->advance();
        CHECK(parts->state(0) == ActivityState::kRunning);  // drive1
    }
    void teardown() override {
        delete inForce;
        delete parts;
        parts = nullptr;
    }
};

TEST(PlanRegeneration, NothingAskedOfAFailedComponentTriggersNothing) {
    CHECK_FALSE(parts->regeneration.checkComponents());
    LONGS_EQUAL(0, parts->count(ev::kComponentFailed));
    LONGS_EQUAL(0, parts->regeneration.deprecatedCount(2));
}

TEST(PlanRegeneration, TheGrinderOfflineDeprecatesTheWaitingSamplesOptions) {
    msg::InstrumentStatusMsg grinder{};
    grinder.instrument = msg::Instrument::kGrinder;
    grinder.state = msg::InstrumentState::kOffline;
    CHECK_TRUE(parts->components.takeInstrument(grinder));
    CHECK_TRUE(parts->regeneration.checkComponents());
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kComponentFailed));
    LONGS_EQUAL(2, parts->regeneration.deprecatedCount(2));  // science1.sample, science2.sample
    CHECK(parts->state(0) == ActivityState::kRunning);       // the drive asks no grinder
    const plan_executive::SelectionInput& input = parts->regeneration.prepare(parts->ctx.planMs(), *inForce, 32.5);
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kRegenerating));
    LONGS_EQUAL(1, parts->regeneration.counters().regenerations);
    CHECK(parts->regeneration.counters().last == msg::PlanRegeneration::kComponentFailed);
    CHECK_TRUE(input.deprecated[0][0]);
    CHECK_TRUE(input.deprecated[1][0]);
    CHECK_FALSE(input.deprecated[0][1]);
    CHECK(input.components[static_cast<std::size_t>(Component::kGrinder)] == ComponentState::kFailed);
    CHECK_TRUE(input.started[0]);  // drive1 runs: where execution stands
    // A new plan: none of its options deprecated.
    parts->regeneration.clearDeprecations();
    LONGS_EQUAL(0, parts->regeneration.deprecatedCount(2));
}

TEST(PlanRegeneration, AFailedDriveModeFailsTheRunningDriveThatAsksIt) {
    msg::DriveModesMsg modes{};
    modes.drives[1].declared = msg::DriveMode::kFailed;  // drive_ML: drive1 asks drive_ML != failed
    CHECK_TRUE(parts->components.takeDriveModes(modes));
    CHECK_TRUE(parts->regeneration.checkComponents());
    parts->drain();
    CHECK(parts->state(0) == ActivityState::kFailed);
    LONGS_EQUAL(1, parts->count(ev::kActivityFailed));
    LONGS_EQUAL(0, parts->lastGoal.goals.count);  // its goal cleared first
    LONGS_EQUAL(0, parts->regeneration.deprecatedCount(2));
}

TEST(PlanRegeneration, TheDispatchersReasonOrTheInstrumentsLateFailureNamesTheRegeneration) {
    // drive1 fails on its own (the deliberative layer called home): activity failed.
    msg::PlanStatusMsg status{};
    status.goalRevision = parts->lastGoal.goals.revision;
    status.state = msg::DeliberativeState::kCalledHome;
    parts->lifecycle.takePlanStatus(status);
    CHECK_TRUE(parts->ctx.dispatcher.regenerationNeeded());
    parts->regeneration.prepare(parts->ctx.planMs(), *inForce, 32.5);
    CHECK(parts->regeneration.counters().last == msg::PlanRegeneration::kActivityFailed);
}

TEST(PlanRegeneration, AnInstrumentGivingUpAtTheUbMakesTheRegenerationLate) {
    parts->tick(600);
    msg::PlanStatusMsg status{};
    status.goalRevision = parts->lastGoal.goals.revision;
    status.state = msg::DeliberativeState::kComplete;
    parts->lifecycle.takePlanStatus(status);
    parts->advance();
    CHECK(parts->state(1) == ActivityState::kRunning);  // sample1
    msg::InstrumentStatusMsg m =
        parts->instrumentStatus(msg::Instrument::kGrinder, msg::InstrumentState::kFailed, parts->lastInstrument.commandId);
    m.result = msg::InstrumentResult::kTimedOut;
    parts->reportInstrument(m);
    parts->regeneration.prepare(parts->ctx.planMs(), *inForce, 32.5);
    CHECK(parts->regeneration.counters().last == msg::PlanRegeneration::kLate);
}

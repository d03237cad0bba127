// The devices' side of the activities (activity_devices.hpp) and the
// component states (component_states.hpp), on the executive's parts: a
// drive's goal (its point, region, the risk bound, a revision of the
// executive's own) and its cancel; a science command with a fresh id and the
// ub as its limit, the follow-on and the cancels; what an instrument's or the
// deliberative layer's status says of an activity; drive modes and
// instrument states as components (972 on each change), and whether an Ask
// holds.
#include <cstdint>

#include "fsw/plan_executive/plan_executive_events.hpp"
#include "unit_test/fsw/plan_executive/executive_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::plan_executive;
namespace ev = plan_executive::events;

namespace {

constexpr const char* kDriveAndImage =
    "plan dev;event a;event b;"
    "activity d drive start a [0, 900] at 10 -3 within 2;"
    "activity i image a b [1, inf] target 4;end";

test::ExecutiveParts* parts = nullptr;

}  // namespace

TEST_GROUP(ActivityDevices) {
    void setup() override {
        parts = new test::ExecutiveParts();
        CHECK_TRUE(parts->init());
        CHECK_TRUE(parts->adopt(kDriveAndImage));
    }
    void teardown() override {
        delete parts;
        parts = nullptr;
    }
};

TEST(ActivityDevices, ADriveIsAGoalOfOneRegionAtTheRiskBoundAndItsCancelAnEmptyList) {
    parts->devices.setRiskBound(4e-3);
    parts->devices.start(0);
    parts->drain();
    LONGS_EQUAL(1, parts->goalsSent);
    const msg::GoalListMsg& g = parts->lastGoal.goals;
    LONGS_EQUAL(1, g.count);
    DOUBLES_EQUAL(10.0, g.goals[0].xM, 0.0);
    DOUBLES_EQUAL(-3.0, g.goals[0].yM, 0.0);
    DOUBLES_EQUAL(2.0, g.goals[0].radiusM, 1e-6);
    DOUBLES_EQUAL(4e-3, g.riskBound, 0.0);
    CHECK(g.revision > ActivityDevices::kGoalRevisionBase);
    const std::uint32_t revision = g.revision;
    // The deliberative layer on another list before it took this one: not news.
    msg::PlanStatusMsg status{};
    status.goalRevision = 12;
    status.state = msg::DeliberativeState::kExecuting;
    std::uint16_t a = kNoIndex;
    CHECK(parts->devices.takePlanStatus(status, &a) == DeviceReport::kNone);
    status.goalRevision = revision;
    CHECK(parts->devices.takePlanStatus(status, &a) == DeviceReport::kNone);  // taken: working on it
    status.goalRevision = 13;
    CHECK(parts->devices.takePlanStatus(status, &a) == DeviceReport::kReplaced);
    LONGS_EQUAL(0, a);
    // Let go: no drive is followed any more, and its cancel sends nothing.
    CHECK(parts->devices.takePlanStatus(status, &a) == DeviceReport::kNone);
    CHECK_FALSE(parts->devices.cancel(0));
    parts->drain();
    LONGS_EQUAL(1, parts->goalsSent);
    parts->devices.start(0);
    CHECK_FALSE(parts->devices.cancel(0));
    parts->drain();
    LONGS_EQUAL(3, parts->goalsSent);
    LONGS_EQUAL(0, parts->lastGoal.goals.count);
}

TEST(ActivityDevices, AScienceActivityIsACommandWithAFreshIdJudgedByTheInstrumentsStatus) {
    parts->devices.start(1);
    parts->drain();
    const msg::InstrumentCommandMsg first = parts->lastInstrument;
    CHECK(first.instrument == msg::Instrument::kCamera);
    CHECK(first.action == msg::InstrumentAction::kImage);
    LONGS_EQUAL(4, first.targetId);
    DOUBLES_EQUAL(0.0, first.maxDurationS, 0.0);  // ub inf: no limit
    LONGS_EQUAL(first.commandId, parts->devices.commandId(1));
    msg::InstrumentStatusMsg m = parts->instrumentStatus(msg::Instrument::kCamera, msg::InstrumentState::kBusy, first.commandId);
    CHECK_TRUE(parts->devices.commandedOn(1, m));
    CHECK(parts->devices.judge(1, m) == DeviceReport::kNone);
    m.state = msg::InstrumentState::kDone;
    CHECK(parts->devices.judge(1, m) == DeviceReport::kDone);
    m.state = msg::InstrumentState::kFailed;
    CHECK(parts->devices.judge(1, m) == DeviceReport::kFailed);
    m.result = msg::InstrumentResult::kTimedOut;
    CHECK(parts->devices.judge(1, m) == DeviceReport::kTimedOut);
    m = parts->instrumentStatus(msg::Instrument::kCamera, msg::InstrumentState::kOffline, 0);
    CHECK(parts->devices.judge(1, m) == DeviceReport::kOffline);
    m.state = msg::InstrumentState::kIdle;
    m.lastRefusal = msg::InstrumentRefusal::kBusy;
    m.lastRefusedCommandId = first.commandId;
    CHECK(parts->devices.judge(1, m) == DeviceReport::kRefused);
    // The grinder's status is not about a camera activity.
    m.instrument = msg::Instrument::kGrinder;
    CHECK_FALSE(parts->devices.commandedOn(1, m));
    // A follow-on: a fresh id continuing the command; its cancel and the command's.
    const std::uint16_t followOn = parts->devices.sendFollowOn(1, 12300);
    parts->drain();
    CHECK(parts->lastInstrument.action == msg::InstrumentAction::kExtend);
    LONGS_EQUAL(followOn, parts->lastInstrument.commandId);
    LONGS_EQUAL(first.commandId, parts->lastInstrument.extendsCommandId);
    DOUBLES_EQUAL(12.3, parts->lastInstrument.maxDurationS, 1e-9);
    CHECK_TRUE(parts->devices.cancel(1));
    parts->drain();
    CHECK(parts->lastInstrument.action == msg::InstrumentAction::kCancel);
    LONGS_EQUAL(first.commandId, parts->lastInstrument.commandId);
    parts->devices.cancelFollowOn(1, followOn);
    parts->drain();
    LONGS_EQUAL(followOn, parts->lastInstrument.commandId);
    parts->devices.forgetAll();
    LONGS_EQUAL(0, parts->devices.commandId(1));
}

TEST_GROUP(ComponentStates) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    ComponentStates components{events};

    unsigned changes() {
        unsigned n = 0;
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            n += e.id == ev::kComponentState ? 1U : 0U;
        }
        return n;
    }
};

TEST(ComponentStates, DriveModesAndInstrumentsAreComponentsEachChangeEvented) {
    msg::DriveModesMsg modes{};  // all nominal
    CHECK_FALSE(components.takeDriveModes(modes));
    modes.drives[2].declared = msg::DriveMode::kDegraded;
    modes.drives[4].declared = msg::DriveMode::kFailed;
    modes.drives[5].declared = msg::DriveMode::kUnknown;  // not known to be ok
    CHECK_TRUE(components.takeDriveModes(modes));
    LONGS_EQUAL(3, changes());
    CHECK(components.state(Component::kDriveRL) == ComponentState::kDegraded);
    CHECK(components.state(Component::kDriveMR) == ComponentState::kFailed);
    CHECK(components.state(Component::kDriveRR) == ComponentState::kDegraded);
    msg::InstrumentStatusMsg camera{};
    camera.instrument = msg::Instrument::kCamera;
    camera.state = msg::InstrumentState::kFailed;  // a command failed, no fault: still usable
    CHECK_FALSE(components.takeInstrument(camera));
    camera.faultCode = 9;
    CHECK_TRUE(components.takeInstrument(camera));
    CHECK(components.state(Component::kCamera) == ComponentState::kFailed);
    CHECK(components.state(Component::kGrinder) == ComponentState::kOk);
    LONGS_EQUAL(1, changes());
    Condition ask;
    ask.variable = static_cast<std::uint8_t>(Component::kCamera);
    ask.value = static_cast<std::uint8_t>(ComponentState::kOk);
    CHECK_FALSE(components.holds(ask));
    ask.negated = true;
    CHECK_TRUE(components.holds(ask));
    ask.planVariable = true;  // the selector's to judge
    ask.negated = false;
    CHECK_TRUE(components.holds(ask));
    SelectionInput* input = new SelectionInput();
    components.fill(input);
    CHECK(input->components[static_cast<std::size_t>(Component::kCamera)] == ComponentState::kFailed);
    delete input;
}

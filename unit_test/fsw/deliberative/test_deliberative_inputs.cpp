// The deliberative task's inputs (deliberative_inputs.hpp): the two pipes with
// their names, depths and ids, each usable message handed on in order, and the
// unusable ones counted, evented (916) and dropped.
#include <cmath>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/deliberative_inputs.hpp"
#include "unit_test/fsw/deliberative/event_record.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::DeliberativeInputs;
namespace ev = rse::deliberative::events;

namespace {

// Records what it is handed, in order (message ids).
class Recorder final : public DeliberativeInputs::Receiver {
public:
    void takePose(const msg::PoseEstimateMsg& m) override { add(m); lastPose = m; }
    void takeDriveStatus(const msg::DriveStatusMsg& m) override { add(m); }
    void takeGoals(const msg::PlanGoalMsg& m) override { add(m); }
    void takeLegReport(const msg::LegReportMsg& m) override { add(m); }
    void takeDriveModes(const msg::DriveModesMsg& m) override { add(m); }
    void takeMode(const msg::ModeMsg& m) override { add(m); }
    void takeHazards(const msg::KnownHazardsMsg& m) override { add(m); }
    void takeHold(const msg::MissionHoldMsg& m) override { add(m); }
    void takeFaults(const msg::FaultStatusMsg& m) override { add(m); }
    void takeReplanRequest(const msg::ReplanRequestMsg& m) override { add(m); }

    core::MsgId ids[64] = {};
    unsigned count = 0;
    msg::PoseEstimateMsg lastPose{};

private:
    template <typename M>
    void add(const M&) {
        if (count < 64) {
            ids[count++] = M::kMsgId;
        }
    }
};

msg::PlanGoalMsg goodGoal() {
    msg::PlanGoalMsg g{};
    g.goals.riskBound = 1e-3;
    g.goals.count = 1;
    g.goals.goals[0].xM = 10.0;
    return g;
}

msg::KnownHazardsMsg oneHazard(float radius) {
    msg::KnownHazardsMsg h{};
    h.count = 1;
    h.hazards[0].xM = 3.0F;
    h.hazards[0].radiusM = radius;
    h.hazards[0].obstacleId = 1;
    return h;
}

}  // namespace

TEST_GROUP(DeliberativeInputs) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    test::EventRecord seen{events};
    Recorder recorder;
    DeliberativeInputs inputs{bus, events, recorder};

    void setup() override { CHECK(core::isOk(inputs.init())); }
};

TEST(DeliberativeInputs, TwoPipesWithTheirNamesAndDepths) {
    LONGS_EQUAL(2, bus.pipeCount());
    STRCMP_EQUAL("delib_fast", bus.pipeName(0));
    STRCMP_EQUAL("deliberative", bus.pipeName(1));
    LONGS_EQUAL(deliberative::kFastPipeDepth, bus.pipeStats(0)->depth);
    LONGS_EQUAL(deliberative::kInputPipeDepth, bus.pipeStats(1)->depth);
    // Init twice: the pipe exists.
    CHECK(core::Status::kAlreadyExists == inputs.init());
}

TEST(DeliberativeInputs, EveryUsableInputIsHandedOnInTheOrderPublishedFastPipeFirst) {
    msg::ModeMsg mode{};
    mode.mode = msg::mode::kAutonomous;
    CHECK(core::isOk(bus.publish(mode)));
    CHECK(core::isOk(bus.publish(goodGoal())));
    CHECK(core::isOk(bus.publish(msg::LegReportMsg{})));
    CHECK(core::isOk(bus.publish(msg::DriveModesMsg{})));
    CHECK(core::isOk(bus.publish(oneHazard(0.5F))));
    CHECK(core::isOk(bus.publish(msg::MissionHoldMsg{})));
    CHECK(core::isOk(bus.publish(msg::FaultStatusMsg{})));
    msg::ReplanRequestMsg rr{};
    rr.faultId = msg::fault::kOffMap;
    rr.attempt = 1;
    CHECK(core::isOk(bus.publish(rr)));
    msg::PoseEstimateMsg pose{};
    pose.xM = 4.0;
    CHECK(core::isOk(bus.publish(pose)));
    CHECK(core::isOk(bus.publish(msg::DriveStatusMsg{})));
    inputs.drainFast();
    LONGS_EQUAL(2, recorder.count);
    inputs.drainInputs();
    const core::MsgId expected[] = {msg::ids::kPoseEstimate,  msg::ids::kDriveStatus, msg::ids::kMode,
                                    msg::ids::kPlanGoal,      msg::ids::kLegReport,   msg::ids::kDriveModes,
                                    msg::ids::kKnownHazards,  msg::ids::kMissionHold, msg::ids::kFaultStatus,
                                    msg::ids::kReplanRequest};
    LONGS_EQUAL(10, recorder.count);
    for (unsigned i = 0; i < 10; ++i) {
        LONGS_EQUAL(expected[i], recorder.ids[i]);
    }
    DOUBLES_EQUAL(4.0, recorder.lastPose.xM, 0.0);
    LONGS_EQUAL(0, inputs.malformed());
}

TEST(DeliberativeInputs, UnusableInputsAreCountedEventedAndNotHandedOn) {
    msg::PoseEstimateMsg pose{};
    pose.covariance[8] = NAN;
    CHECK(core::isOk(bus.publish(pose)));
    msg::ModeMsg mode{};
    mode.mode = msg::mode::kCount;
    CHECK(core::isOk(bus.publish(mode)));
    msg::PlanGoalMsg goal = goodGoal();
    goal.listIndex = msg::kMaxGoals;
    CHECK(core::isOk(bus.publish(goal)));
    msg::LegReportMsg report{};
    report.violated = static_cast<msg::LegConstraint>(99);
    CHECK(core::isOk(bus.publish(report)));
    CHECK(core::isOk(bus.publish(oneHazard(11.0F))));
    msg::MissionHoldMsg hold{};
    hold.estop = 2;
    CHECK(core::isOk(bus.publish(hold)));
    msg::ReplanRequestMsg rr{};
    rr.faultId = msg::fault::kOffMap;  // try 0
    CHECK(core::isOk(bus.publish(rr)));
    inputs.drainFast();
    inputs.drainInputs();
    LONGS_EQUAL(0, recorder.count);
    LONGS_EQUAL(7, inputs.malformed());
    // Throttled per pipe: the fast pipe's 1st; the other's 1st, 2nd, 4th.
    LONGS_EQUAL(4, seen.count(ev::kMalformedInput));
    CHECK_TRUE(seen.textHas(ev::kMalformedInput, "deliberative: bus message 0x"));
}

TEST(DeliberativeInputs, TheChecksRefuseWhatTheTaskCannotUse) {
    msg::PoseEstimateMsg pose{};
    CHECK(core::isOk(deliberative::checkPose(pose)));
    pose.headingRad = INFINITY;
    CHECK_FALSE(core::isOk(deliberative::checkPose(pose)));
    CHECK(core::isOk(deliberative::checkGoals(goodGoal())));
    msg::PlanGoalMsg goal = goodGoal();
    goal.goals.riskBound = 0.7;
    CHECK_FALSE(core::isOk(deliberative::checkGoals(goal)));
    msg::LegReportMsg report{};
    report.state = msg::HabitualState::kAchieved;
    report.violated = msg::LegConstraint::kPower;
    CHECK(core::isOk(deliberative::checkLegReport(report)));
    report.state = static_cast<msg::HabitualState>(static_cast<std::uint8_t>(msg::HabitualState::kAchieved) + 1);
    CHECK_FALSE(core::isOk(deliberative::checkLegReport(report)));
    CHECK(core::isOk(deliberative::checkHazards(oneHazard(deliberative::kMaxHazardRadiusM))));
    CHECK_FALSE(core::isOk(deliberative::checkHazards(oneHazard(0.0F))));
    CHECK_FALSE(core::isOk(deliberative::checkHazards(oneHazard(NAN))));
    msg::KnownHazardsMsg contact = oneHazard(1.0F);
    contact.hazards[0].obstacleId = 0;  // a contact the follower felt (habitual map_builder.hpp)
    CHECK(core::isOk(deliberative::checkHazards(contact)));
    msg::KnownHazardsMsg nowhere = oneHazard(1.0F);
    nowhere.hazards[0].xM = NAN;
    CHECK_FALSE(core::isOk(deliberative::checkHazards(nowhere)));
    msg::KnownHazardsMsg tooMany = oneHazard(1.0F);
    tooMany.count = static_cast<std::uint8_t>(msg::kMaxKnownHazards + 1);
    CHECK_FALSE(core::isOk(deliberative::checkHazards(tooMany)));
    msg::ReplanRequestMsg rr{};
    rr.faultId = msg::fault::kOffMap;
    rr.attempt = 2;
    CHECK(core::isOk(deliberative::checkReplanRequest(rr)));
    rr.faultId = static_cast<std::uint8_t>(msg::fault::kOffMap + 1);
    CHECK_FALSE(core::isOk(deliberative::checkReplanRequest(rr)));
    msg::MissionHoldMsg hold{};
    hold.reasons = 1U << 31;
    CHECK_FALSE(core::isOk(deliberative::checkHold(hold)));
}

// PLAN_EXEC, packed from what the plan executive publishes: in slot 40 and in
// the run after a status whose state, counters, selection or activities
// changed; its slack and plan time alone are not news.
#include <cstring>

#include "fsw/plan_executive/plan_exec_telemetry.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::RecordingSink;

TEST_GROUP(PlanExecTelemetry) {
    plan_executive::PlanExecTelemetry packer;
    test::PackerRig rig{packer};
    msg::PlanExecutiveStatusMsg status{};
};

TEST(PlanExecTelemetry, GoesInItsSlotAndAfterAChangeThatMatters) {
    rig.runFrames(0, plan_executive::kPlanExecSlot);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::PLAN_EXEC_Tlm>());
    status.timeNs = 5;
    status.slackMs = 900;
    status.planTimeMs = 1200;
    rig.publish(status);
    rig.run(41);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::PLAN_EXEC_Tlm>());  // time, slack, plan time: not news
    status.activitiesStarted = 1;
    std::memcpy(status.planName, "survey", 6);
    rig.publish(status);
    rig.run(42);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::PLAN_EXEC_Tlm>());
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::PLAN_EXEC_Tlm>();
    DOUBLES_EQUAL(1, RecordingSink::field(p, "started"), 0.0);
    DOUBLES_EQUAL(900, RecordingSink::field(p, "slack"), 0.0);
    DOUBLES_EQUAL(1200, RecordingSink::field(p, "plan_time"), 0.0);
    DOUBLES_EQUAL('s', RecordingSink::field(p, "plan_name", 0), 0.0);
    rig.runFrames(43, 139);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::PLAN_EXEC_Tlm>());
    rig.run(140);
    LONGS_EQUAL(3, rig.sink.count<cmdtlm::PLAN_EXEC_Tlm>());  // the 1 Hz slot
}

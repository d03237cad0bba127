// FAULT_PROTECTION, packed from what fault protection publishes: in slot 80
// and in the run after every status; the hold's e-stop from MissionHoldMsg.
#include "fsw/fault_protection/fault_protection_telemetry.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::RecordingSink;

TEST_GROUP(FaultProtectionTelemetry) {
    fault_protection::FaultProtectionTelemetry packer;
    test::PackerRig rig{packer};
};

TEST(FaultProtectionTelemetry, GoesInItsSlotAndAfterEachStatusWithItsResponses) {
    rig.runFrames(0, fault_protection::kFaultProtectionSlot);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::FAULT_PROTECTION_Tlm>());
    msg::MissionHoldMsg hold{};
    hold.estop = 1;
    hold.resumeCount = 2;
    rig.publish(hold);
    rig.run(81);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::FAULT_PROTECTION_Tlm>());  // the hold alone is not news
    msg::FaultProtectionStatusMsg status{};
    status.responsesStarted = 3;
    status.activeCount = 1;
    status.responses[0].faultId = 4;
    status.responses[0].attemptsUsed = 2;
    status.responses[0].sinceNs = 1500 * core::kNsPerMs;
    rig.publish(status);
    rig.run(82);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::FAULT_PROTECTION_Tlm>());
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::FAULT_PROTECTION_Tlm>();
    DOUBLES_EQUAL(1, RecordingSink::field(p, "hold_estop"), 0.0);
    DOUBLES_EQUAL(2, RecordingSink::field(p, "resume_count"), 0.0);
    DOUBLES_EQUAL(3, RecordingSink::field(p, "responses_started"), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(p, "response_count"), 0.0);
    DOUBLES_EQUAL(4, RecordingSink::field(p, "fault_id", 0), 0.0);
    DOUBLES_EQUAL(2, RecordingSink::field(p, "attempts_used", 0), 0.0);
    DOUBLES_EQUAL(1.5, RecordingSink::field(p, "state_since", 0), 1e-6);
    rig.publish(status);  // the same status again: still news (each one is)
    rig.run(83);
    LONGS_EQUAL(3, rig.sink.count<cmdtlm::FAULT_PROTECTION_Tlm>());
}

TEST(FaultProtectionTelemetry, NoMoreResponsesThanThePacketHolds) {
    msg::FaultProtectionStatusMsg status{};
    status.activeCount = 200;
    rig.publish(status);
    rig.run(1);
    DOUBLES_EQUAL(msg::kResponseSlots,
                  RecordingSink::field(rig.sink.last<cmdtlm::FAULT_PROTECTION_Tlm>(), "response_count"), 0.0);
}

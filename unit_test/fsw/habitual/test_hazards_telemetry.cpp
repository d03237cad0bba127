// HAZARDS, packed from the habitual layer's hazard map: in slot 45 of every
// fifth second, and in slot 45 of a second in which the map's revision changed.
#include "fsw/habitual/hazards_telemetry.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::RecordingSink;

TEST_GROUP(HazardsTelemetry) {
    habitual::HazardsTelemetry packer;
    test::PackerRig rig{packer};
    msg::KnownHazardsMsg hazards{};
};

TEST(HazardsTelemetry, EveryFifthSecondAndInTheSecondOfANewRevision) {
    rig.runFrames(0, 499);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::HAZARDS_Tlm>());  // frame 45
    hazards.revision = 1;
    hazards.count = 1;
    hazards.hazards[0].xM = 3.5F;
    hazards.hazards[0].radiusM = 0.4F;
    hazards.hazards[0].obstacleId = 7;
    rig.publish(hazards);
    rig.runFrames(500, 544);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::HAZARDS_Tlm>());  // not before the slot
    rig.run(545);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::HAZARDS_Tlm>());
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::HAZARDS_Tlm>();
    DOUBLES_EQUAL(1, RecordingSink::field(p, "revision"), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(p, "count"), 0.0);
    DOUBLES_EQUAL(3.5, RecordingSink::field(p, "x", 0), 1e-6);
    DOUBLES_EQUAL(7, RecordingSink::field(p, "obstacle_id", 0), 0.0);
    rig.publish(hazards);  // the same revision again: not news
    rig.runFrames(546, 999);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::HAZARDS_Tlm>());
    rig.runFrames(1000, 1045);
    LONGS_EQUAL(3, rig.sink.count<cmdtlm::HAZARDS_Tlm>());  // the 5 s repeat
    LONGS_EQUAL(3, packer.hazardsSent());
}

TEST(HazardsTelemetry, AMapWithMoreHazardsThanTheMessageHoldsIsRefused) {
    hazards.revision = 4;
    hazards.count = static_cast<std::uint8_t>(msg::kMaxKnownHazards + 1);
    rig.publish(hazards);
    rig.runFrames(0, 45);
    LONGS_EQUAL(1, rig.pipe.malformed());
    DOUBLES_EQUAL(0, RecordingSink::field(rig.sink.last<cmdtlm::HAZARDS_Tlm>(), "revision"), 0.0);
}

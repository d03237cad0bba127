// ROVER_STATE and HEALTH, packed from what the estimator tasks publish:
// ROVER_STATE in slot 60, HEALTH in slot 70 and in the run after the active
// faults or a declared drive mode changed.
#include "fsw/estimator/estimator_telemetry.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::RecordingSink;

TEST_GROUP(EstimatorTelemetry) {
    estimator::EstimatorTelemetry packer;
    test::PackerRig rig{packer};
};

TEST(EstimatorTelemetry, RoverStateGoesInItsSlotWithThePoseEstimate) {
    msg::PoseEstimateMsg pose{};
    pose.initialised = 1;
    pose.xM = 12.5;
    pose.headingRad = 0.25;
    pose.covariance[4] = 0.04;
    pose.fixesAccepted = 9;
    rig.publish(pose);
    rig.runFrames(0, estimator::kRoverStateSlot - 1);
    LONGS_EQUAL(0, rig.sink.count<cmdtlm::ROVER_STATE_Tlm>());
    rig.run(estimator::kRoverStateSlot);
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::ROVER_STATE_Tlm>();
    DOUBLES_EQUAL(1, RecordingSink::field(p, "estimate_valid"), 0.0);
    DOUBLES_EQUAL(12.5, RecordingSink::field(p, "x"), 0.0);
    DOUBLES_EQUAL(0.25, RecordingSink::field(p, "heading"), 0.0);
    DOUBLES_EQUAL(0.04, RecordingSink::field(p, "covariance", 4), 1e-7);
    DOUBLES_EQUAL(9, RecordingSink::field(p, "fixes_accepted"), 0.0);
}

TEST(EstimatorTelemetry, HealthGoesInItsSlotAndWhenTheFaultsOrADeclaredModeChange) {
    rig.runFrames(0, estimator::kHealthSlot);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::HEALTH_Tlm>());
    msg::FaultStatusMsg faults{};
    faults.activeMask = 1U << 3;
    faults.raisedTotal = 1;
    rig.publish(faults);
    rig.run(71);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::HEALTH_Tlm>());
    DOUBLES_EQUAL(8, RecordingSink::field(rig.sink.last<cmdtlm::HEALTH_Tlm>(), "active_faults"), 0.0);
    faults.raisedTotal = 2;  // the same faults: not news
    rig.publish(faults);
    rig.run(72);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::HEALTH_Tlm>());
    msg::DriveModesMsg modes{};
    modes.drives[3].probability[static_cast<std::size_t>(msg::DriveMode::kNominal)] = 0.6F;  // beliefs alone: not news
    rig.publish(modes);
    rig.run(73);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::HEALTH_Tlm>());
    modes.drives[3].declared = msg::DriveMode::kDegraded;
    modes.drives[3].powerFactor = 1.4F;
    rig.publish(modes);
    rig.run(74);
    LONGS_EQUAL(3, rig.sink.count<cmdtlm::HEALTH_Tlm>());
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::HEALTH_Tlm>();
    DOUBLES_EQUAL(static_cast<double>(msg::DriveMode::kDegraded), RecordingSink::field(p, "drive_mode", 3), 0.0);
    DOUBLES_EQUAL(1.4, RecordingSink::field(p, "power_factor", 3), 1e-6);
    DOUBLES_EQUAL(0.6, RecordingSink::field(p, "p_nominal", 3), 1e-6);
}

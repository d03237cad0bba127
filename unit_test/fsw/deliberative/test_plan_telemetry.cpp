// PLAN and PLAN_PATH, packed from the goal list and the deliberative layer's
// plan status and paths: PLAN on change (and not for what it does not show)
// and every 5 s; PLAN_PATH on receipt, one per plan.
#include "fsw/deliberative/plan_telemetry.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::RecordingSink;

TEST_GROUP(PlanTelemetry) {
    RecordingSink receipts;  // where PLAN_PATH goes, on receipt
    deliberative::PlanTelemetry packer{receipts};
    test::PackerRig rig{packer};
};

TEST(PlanTelemetry, PlanGoesFirstThenOnAChangeThenEveryFiveSeconds) {
    rig.run(1);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::PLAN_Tlm>());
    rig.runFrames(2, 499);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::PLAN_Tlm>());
    msg::GoalListMsg goals{};
    goals.count = 1;
    goals.riskBound = 0.01;
    goals.goals[0].xM = 20.0;
    rig.publish(goals);
    rig.run(500);  // a change and the 5 s mark: one packet
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::PLAN_Tlm>());
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::PLAN_Tlm>();
    DOUBLES_EQUAL(1, RecordingSink::field(p, "goal_count"), 0.0);
    DOUBLES_EQUAL(20.0, RecordingSink::field(p, "goal_x", 0), 1e-6);
    DOUBLES_EQUAL(0.01, RecordingSink::field(p, "risk_bound"), 0.0);
}

TEST(PlanTelemetry, APlanStatusIsNewsOnlyWhenWhatPlanShowsChanged) {
    rig.run(1);
    msg::PlanStatusMsg status{};
    status.legIndex = 2;
    status.shownLegs = 1;
    status.legs[0].xM = 4.0;
    rig.publish(status);
    rig.run(2);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::PLAN_Tlm>());
    DOUBLES_EQUAL(4.0, RecordingSink::field(rig.sink.last<cmdtlm::PLAN_Tlm>(), "waypoint_x", 0), 1e-6);
    status.timeNs = 123;  // the time, the risk used ... alone are not news
    status.riskUsed = 1e-4;
    rig.publish(status);
    rig.run(3);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::PLAN_Tlm>());
    status.plansMade = 1;
    rig.publish(status);
    rig.run(4);
    LONGS_EQUAL(3, rig.sink.count<cmdtlm::PLAN_Tlm>());
}

TEST(PlanTelemetry, SiteModesCountsGoDownAndAHorizonEndIsNews) {
    rig.run(1);
    msg::PlanStatusMsg status{};
    status.siteMode = 1;
    status.routesFound = 1;
    status.horizonsReached = 4;
    status.horizonsDrivenThrough = 3;
    status.horizonStops = 1;
    status.lookAheadsStarted = 9;
    status.lookAheadsDropped = 5;
    rig.publish(status);
    rig.run(2);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::PLAN_Tlm>());
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::PLAN_Tlm>();
    DOUBLES_EQUAL(1, RecordingSink::field(p, "site_mode"), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(p, "routes_found"), 0.0);
    DOUBLES_EQUAL(4, RecordingSink::field(p, "horizons_reached"), 0.0);
    DOUBLES_EQUAL(3, RecordingSink::field(p, "horizons_driven_through"), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(p, "horizon_stops"), 0.0);
    DOUBLES_EQUAL(9, RecordingSink::field(p, "look_aheads_started"), 0.0);
    DOUBLES_EQUAL(5, RecordingSink::field(p, "look_aheads_dropped"), 0.0);
    // A look-ahead restarted is not news; a horizon's end is.
    status.lookAheadsStarted = 10;
    rig.publish(status);
    rig.run(3);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::PLAN_Tlm>());
    status.horizonsReached = 5;
    status.horizonsDrivenThrough = 4;
    rig.publish(status);
    rig.run(4);
    LONGS_EQUAL(3, rig.sink.count<cmdtlm::PLAN_Tlm>());
}

TEST(PlanTelemetry, EachPlanPathGoesDownOnReceiptWithItsMeans) {
    msg::PlanPathMsg path{};
    path.planNumber = 3;
    path.timeNs = 2 * core::kNsPerSec;
    path.steps = 2;
    path.meanX[2] = 7.5;
    path.goalX = 7.5;
    rig.publish(path);
    (void)rig.pipe.drain();
    LONGS_EQUAL(1, receipts.count<cmdtlm::PLAN_PATH_Tlm>());  // before any pack()
    LONGS_EQUAL(0, rig.sink.packets.size());
    const RecordingSink::Packet& p = receipts.last<cmdtlm::PLAN_PATH_Tlm>();
    DOUBLES_EQUAL(3, RecordingSink::field(p, "plan_number"), 0.0);
    DOUBLES_EQUAL(2.0, RecordingSink::field(p, "plan_time"), 0.0);
    DOUBLES_EQUAL(2, RecordingSink::field(p, "steps"), 0.0);
    DOUBLES_EQUAL(7.5, RecordingSink::field(p, "mean_x", 2), 1e-6);
    LONGS_EQUAL(1, packer.planPathsSent());
}

TEST(PlanTelemetry, APathWithMoreMeansThanTheMessageHoldsIsRefused) {
    msg::PlanPathMsg path{};
    path.steps = static_cast<std::uint8_t>(msg::kPlanPathMeans);
    rig.publish(path);
    (void)rig.pipe.drain();
    LONGS_EQUAL(1, rig.pipe.malformed());
    LONGS_EQUAL(0, receipts.packets.size());
    LONGS_EQUAL(0, packer.planPathsSent());
}

TEST(PlanTelemetry, EachRouteChunkGoesDownOnReceiptAndABadOneIsRefused) {
    msg::RouteChunkMsg chunk{};
    chunk.routeNumber = 2;
    chunk.timeNs = 3 * core::kNsPerSec;
    chunk.pointCount = 40;
    chunk.chunkIndex = 1;
    chunk.chunkCount = 2;
    chunk.count = 8;
    chunk.lengthM = 512.5;
    chunk.x[7] = 700.0F;
    chunk.y[7] = 80.0F;
    rig.publish(chunk);
    (void)rig.pipe.drain();
    LONGS_EQUAL(1, receipts.count<cmdtlm::ROUTE_Tlm>());
    const RecordingSink::Packet& p = receipts.last<cmdtlm::ROUTE_Tlm>();
    DOUBLES_EQUAL(2, RecordingSink::field(p, "route_number"), 0.0);
    DOUBLES_EQUAL(3.0, RecordingSink::field(p, "route_time"), 0.0);
    DOUBLES_EQUAL(40, RecordingSink::field(p, "point_count"), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(p, "chunk_index"), 0.0);
    DOUBLES_EQUAL(8, RecordingSink::field(p, "count"), 0.0);
    DOUBLES_EQUAL(512.5, RecordingSink::field(p, "length"), 1e-3);
    DOUBLES_EQUAL(700.0, RecordingSink::field(p, "x", 7), 1e-3);
    DOUBLES_EQUAL(0.0, RecordingSink::field(p, "x", 8), 0.0);
    LONGS_EQUAL(1, packer.routeChunksSent());
    chunk.count = static_cast<std::uint8_t>(msg::kRouteChunkPoints + 1);   // more than it holds
    rig.publish(chunk);
    chunk.count = 1;
    chunk.chunkIndex = 2;                                                  // past the last chunk
    rig.publish(chunk);
    (void)rig.pipe.drain();
    LONGS_EQUAL(1, packer.routeChunksSent());
}

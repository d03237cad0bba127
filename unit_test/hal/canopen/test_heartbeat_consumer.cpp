#include "hal/canopen/canopen_events.hpp"
#include "hal/canopen/heartbeat_consumer.hpp"
#include "unit_test/hal/canopen/canopen_test_rig.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal::canopen;
using core::kNsPerMs;

TEST_GROUP(HeartbeatConsumer) {
    test::CanRig rig;
    HeartbeatConsumer hb{rig.events};
    void setup() override { CHECK(core::Status::kOk == hb.monitor(3, 250 * kNsPerMs)); }
    void beat(std::uint8_t node, std::uint8_t state, core::TimeNs at) {
        hb.onFrame(test::CanRig::make(0x700 + node, {state}), at);
    }
};

TEST(HeartbeatConsumer, BootUpThenStatesAreTracked) {
    beat(3, 0x00, 0);
    LONGS_EQUAL(1, hb.node(3)->bootUps);
    CHECK(NmtState::kPreOperational == hb.node(3)->state);
    beat(3, 0x05, 100 * kNsPerMs);
    CHECK(NmtState::kOperational == hb.node(3)->state);
    LONGS_EQUAL(1, test::drainEventsWithId(rig.events, hal::events::kNodeStateChanged));
}

TEST(HeartbeatConsumer, SilenceBeyondTheTimeoutIsALossAndABeatRecovers) {
    beat(3, 0x7F, 0);
    hb.check(250 * kNsPerMs);
    CHECK_FALSE(hb.node(3)->lost);
    hb.check(251 * kNsPerMs);
    CHECK_TRUE(hb.node(3)->lost);
    LONGS_EQUAL(1, hb.node(3)->losses);
    hb.check(400 * kNsPerMs);  // evented once, not every cycle
    LONGS_EQUAL(1, test::drainEventsWithId(rig.events, hal::events::kNodeLost));
    beat(3, 0x7F, 500 * kNsPerMs);
    CHECK_FALSE(hb.node(3)->lost);
    LONGS_EQUAL(1, test::drainEventsWithId(rig.events, hal::events::kNodeRecovered));
}

TEST(HeartbeatConsumer, NeverHeardNodesAreNotDeclaredLost) {
    hb.check(10 * core::kNsPerSec);
    CHECK_FALSE(hb.node(3)->lost);
}

TEST(HeartbeatConsumer, HostileHeartbeatsAreCountedAndIgnored) {
    beat(3, 0x05, 0);
    hb.onFrame(test::CanRig::make(0x703, {0x05, 0x00}), 1);  // DLC 2
    hb.onFrame(test::CanRig::make(0x703, {0x42}), 2);        // no such state
    hb.onFrame(test::CanRig::make(0x703, {}), 3);            // DLC 0
    LONGS_EQUAL(3, hb.badFrames());
    CHECK(NmtState::kOperational == hb.node(3)->state);
    CHECK(rse::test::drainEventsWithId(rig.events, hal::events::kBadHeartbeat) >= 1);
    beat(9, 0x05, 4);  // not monitored
    LONGS_EQUAL(1, hb.unmonitored());
}

TEST(HeartbeatConsumer, MonitorArgumentsAreChecked) {
    CHECK(core::Status::kInvalidArgument == hb.monitor(0, 100));
    CHECK(core::Status::kInvalidArgument == hb.monitor(128, 100));
    CHECK(core::Status::kAlreadyExists == hb.monitor(3, 100));
    for (std::uint8_t id = 10; id < 10 + kMaxMonitoredNodes - 1; ++id) {
        CHECK(core::Status::kOk == hb.monitor(id, 100));
    }
    CHECK(core::Status::kNoCapacity == hb.monitor(100, 100));
}

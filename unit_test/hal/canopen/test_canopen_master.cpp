#include "hal/canopen/canopen_events.hpp"
#include "hal/canopen/canopen_master.hpp"
#include "unit_test/hal/canopen/canopen_test_rig.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal;
using namespace rse::hal::canopen;

namespace {
class CountingSink final : public CanFrameSink {
public:
    void onFrame(const CanFrame& frame, core::TimeNs) override {
        ++frames;
        lastId = frame.id;
    }
    unsigned frames = 0;
    std::uint32_t lastId = 0;
};
}  // namespace

TEST_GROUP(CanOpenMaster) {
    test::CanRig rig;
    CanOpenMaster master{*rig.flight, rig.events};
};

TEST(CanOpenMaster, FirstCycleResetsCommunicationThenSyncEveryCycle) {
    master.cycle(0);
    master.cycle(10 * core::kNsPerMs);
    auto frames = rig.sent();
    LONGS_EQUAL(3, frames.size());
    LONGS_EQUAL(0x000, frames.at(0)->id);
    LONGS_EQUAL(0x82, frames.at(0)->data[0]);  // reset communication
    LONGS_EQUAL(0, frames.at(0)->data[1]);     // all nodes
    LONGS_EQUAL(0x080, frames.at(1)->id);
    LONGS_EQUAL(0, frames.at(1)->dlc);
    LONGS_EQUAL(0x080, frames.at(2)->id);
    LONGS_EQUAL(2, master.stats().syncSent);
}

TEST(CanOpenMaster, FramesGoToTheirSinkOrAreCountedAsUnknown) {
    CountingSink imu;
    CHECK(core::Status::kOk == master.addSink(0x6A0, &imu));
    CHECK(core::Status::kAlreadyExists == master.addSink(0x6A0, &imu));
    CHECK(core::Status::kOk == master.monitor(0x20, 250 * core::kNsPerMs));
    rig.peerSends(0x6A0, {1, 2, 3, 4, 5, 6, 7, 8});
    rig.peerSends(0x720, {0x05});
    rig.peerSends(0x3FF, {1});   // nobody's
    rig.peerSends(0x185, {1});   // a TPDO of an unregistered node
    master.cycle(0);
    LONGS_EQUAL(1, imu.frames);
    CHECK(NmtState::kOperational == master.heartbeats().node(0x20)->state);
    LONGS_EQUAL(2, master.stats().unknownCobId);
    LONGS_EQUAL(2, test::drainEventsWithId(rig.events, events::kUnknownCobId));
}

TEST(CanOpenMaster, ABabblingNodeCannotStallTheCycle) {
    for (int i = 0; i < 200; ++i) {
        rig.peerSends(0x001, {0xFF});
    }
    master.cycle(0);
    LONGS_EQUAL(kMaxFramesPerCycle, master.stats().framesIn);
    LONGS_EQUAL(1, master.stats().backlogCycles);
    LONGS_EQUAL(1, master.stats().syncSent);  // the cycle still completed
    master.cycle(10 * core::kNsPerMs);
    LONGS_EQUAL(200, master.stats().framesIn);
}

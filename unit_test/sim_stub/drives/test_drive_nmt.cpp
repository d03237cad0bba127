// CiA 402 drive emulator: NMT slave, boot-up and heartbeat producer (docs/icd.md §1.3).
#include "unit_test/sim_stub/drives/drive_test_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using rse::sim::NmtState;
using rse::test::kCycle;
using rse::test::kNode;

namespace {

// Heartbeats (not boot-ups) from node 5 among the frames waiting; their state bytes.
unsigned countHeartbeats(test::DriveRig& rig, std::uint8_t* lastState = nullptr,
                         core::TimeNs* firstAt = nullptr, core::TimeNs* lastAt = nullptr) {
    unsigned n = 0;
    hal::CanFrame f;
    while (rig.receive(&f)) {
        if (f.id == 0x700 + kNode && f.dlc == 1 && f.data[0] != 0x00) {
            if (n == 0 && firstAt != nullptr) {
                *firstAt = f.timestamp;
            }
            if (lastAt != nullptr) {
                *lastAt = f.timestamp;
            }
            if (lastState != nullptr) {
                *lastState = f.data[0];
            }
            ++n;
        }
    }
    return n;
}

}  // namespace

TEST_GROUP(DriveNmt) {
    test::DriveRig rig;
};

TEST(DriveNmt, SilentUntilPoweredThenBootUpAndPreOperational) {
    rig.idle(100 * core::kNsPerMs);
    hal::CanFrame f;
    CHECK_FALSE(rig.receive(&f));
    CHECK(sim::NodeLife::kOff == rig.drive.life());

    rig.drive.powerOn();
    rig.advance(kCycle);
    CHECK(rig.receive(&f));
    LONGS_EQUAL(0x705, f.id);
    LONGS_EQUAL(1, f.dlc);
    LONGS_EQUAL(0x00, f.data[0]);
    CHECK_FALSE(rig.receive(&f));
    CHECK(NmtState::kPreOperational == rig.drive.nmtState());
    CHECK(sim::NodeLife::kRunning == rig.drive.life());
    LONGS_EQUAL(1, rig.drive.stats().bootUps);
    CHECK(rig.drive.filtersInstalled());

    // Default 0x1017 is 0: no heartbeat until the master sets one.
    rig.idle(core::kNsPerSec);
    LONGS_EQUAL(0, countHeartbeats(rig));
    LONGS_EQUAL(0, rig.drive.heartbeatPeriodMs());
}

TEST(DriveNmt, TenHeartbeatsPerSecondAfter1017Is100) {
    rig.boot();
    hal::CanFrame r;
    CHECK(rig.sdoDownload(0x1017, 0, 100, 2, &r));
    const core::TimeNs written = rig.clock.now();
    rig.drain();
    rig.idle(core::kNsPerSec);
    std::uint8_t state = 0;
    core::TimeNs first = 0;
    core::TimeNs last = 0;
    LONGS_EQUAL(10, countHeartbeats(rig, &state, &first, &last));
    LONGS_EQUAL(0x7F, state);
    CHECK_EQUAL(written + 100 * core::kNsPerMs, first);
    CHECK_EQUAL(written + 1000 * core::kNsPerMs, last);
    LONGS_EQUAL(10, rig.drive.stats().heartbeatsSent);

    // A coarser step cadence keeps the 100 ms grid and never bursts.
    for (int i = 0; i < 10; ++i) {
        rig.advance(35 * core::kNsPerMs);
    }
    const unsigned n = countHeartbeats(rig);
    CHECK(n >= 3 && n <= 4);
}

TEST(DriveNmt, HeartbeatByteFollowsTheNmtState) {
    rig.boot();
    hal::CanFrame r;
    CHECK(rig.sdoDownload(0x1017, 0, 100, 2, &r));
    rig.drain();
    std::uint8_t state = 0;

    rig.nmt(0x01, kNode);  // start
    rig.idle(200 * core::kNsPerMs);
    CHECK(NmtState::kOperational == rig.drive.nmtState());
    CHECK(countHeartbeats(rig, &state) >= 1);
    LONGS_EQUAL(0x05, state);

    rig.nmt(0x02, kNode);  // stop
    rig.idle(200 * core::kNsPerMs);
    CHECK(NmtState::kStopped == rig.drive.nmtState());
    CHECK(countHeartbeats(rig, &state) >= 1);
    LONGS_EQUAL(0x04, state);

    rig.nmt(0x80, kNode);  // enter pre-operational
    rig.idle(200 * core::kNsPerMs);
    CHECK(NmtState::kPreOperational == rig.drive.nmtState());
    CHECK(countHeartbeats(rig, &state) >= 1);
    LONGS_EQUAL(0x7F, state);
}

TEST(DriveNmt, CommandsToAllNodesAreObeyedAndOthersIgnored) {
    rig.boot();
    rig.nmt(0x01, 6);  // start node 6: not us
    rig.advance(kCycle);
    CHECK(NmtState::kPreOperational == rig.drive.nmtState());
    LONGS_EQUAL(1, rig.drive.stats().nmtOtherNode);

    rig.nmt(0x01, 0);  // start all
    rig.advance(kCycle);
    CHECK(NmtState::kOperational == rig.drive.nmtState());
    rig.nmt(0x02, 0x25);  // stop another node
    rig.nmt(0x81, 4);     // reset another node
    rig.advance(kCycle);
    CHECK(NmtState::kOperational == rig.drive.nmtState());
    LONGS_EQUAL(3, rig.drive.stats().nmtOtherNode);
    hal::CanFrame f;
    CHECK_FALSE(rig.receive(&f));  // no boot-up: the reset was not ours

    rig.nmt(0x02, 0);  // stop all
    rig.advance(kCycle);
    CHECK(NmtState::kStopped == rig.drive.nmtState());
    rig.nmt(0x80, 0);
    rig.advance(kCycle);
    CHECK(NmtState::kPreOperational == rig.drive.nmtState());
    LONGS_EQUAL(3, rig.drive.stats().nmtCommands);
}

TEST(DriveNmt, ResetCommunicationKeepsTheApplicationResetNodeDoesNot) {
    rig.configureAndStart();
    CHECK(NmtState::kOperational == rig.drive.nmtState());
    LONGS_EQUAL(100, rig.drive.heartbeatPeriodMs());
    LONGS_EQUAL(3, rig.drive.modeOfOperation());

    rig.nmt(0x82, kNode);  // reset communication
    rig.step();
    hal::CanFrame f;
    CHECK(rig.receive(&f));
    LONGS_EQUAL(0x705, f.id);
    LONGS_EQUAL(0x00, f.data[0]);
    CHECK(NmtState::kPreOperational == rig.drive.nmtState());
    LONGS_EQUAL(0, rig.drive.heartbeatPeriodMs());   // 0x1017 is a communication object
    LONGS_EQUAL(3, rig.uploadValue(0x6061, 0));       // 0x6060 is not
    LONGS_EQUAL(0, rig.uploadValue(0x1017, 0));

    rig.nmt(0x81, 0);  // reset node, to all
    rig.step();
    CHECK(rig.receive(&f));
    LONGS_EQUAL(0x705, f.id);
    LONGS_EQUAL(0x00, f.data[0]);
    LONGS_EQUAL(0, rig.uploadValue(0x6061, 0));
    CHECK(sim::PowerState::kNotReadyToSwitchOn == rig.drive.powerState());
    rig.advance(kCycle);
    CHECK(sim::PowerState::kSwitchOnDisabled == rig.drive.powerState());
    LONGS_EQUAL(3, rig.drive.stats().bootUps);
}

TEST(DriveNmt, StoppedNodeAnswersNoSdoButObeysNmt) {
    rig.boot();
    rig.nmt(0x02, kNode);
    rig.step();
    hal::CanFrame r;
    CHECK_FALSE(rig.sdoUpload(0x1000, 0, &r));
    LONGS_EQUAL(1, rig.drive.stats().sdoNotAllowed);
    rig.nmt(0x80, kNode);
    rig.step();
    CHECK(rig.sdoUpload(0x1000, 0, &r));
    LONGS_EQUAL(0x43, r.data[0]);
}

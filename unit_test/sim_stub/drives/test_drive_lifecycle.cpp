// CiA 402 drive emulator: crash and restart, heartbeat suppression, hostile
// frames, frame budget, determinism and the no-allocation rule.
#include "unit_test/sim_stub/drives/drive_test_rig.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using rse::sim::NmtState;
using rse::sim::PowerState;
using rse::test::Captured;
using rse::test::DriveRig;
using rse::test::kCycle;
using rse::test::kNode;
using rse::test::Tpdo;

namespace {

unsigned heartbeatsIn(DriveRig& rig) {
    unsigned n = 0;
    hal::CanFrame f;
    while (rig.receive(&f)) {
        n += (f.id == 0x700 + kNode && f.dlc == 1 && f.data[0] != 0) ? 1U : 0U;
    }
    return n;
}

}  // namespace

TEST_GROUP(DriveLifecycle) {
    DriveRig rig;
};

TEST(DriveLifecycle, CrashSilencesTheNodeAndRestartIsAPowerCycle) {
    rig.enable();
    for (int i = 0; i < 50; ++i) {
        (void)rig.cycle(0x000F, 1000);
    }
    rig.idle(300 * core::kNsPerMs);
    CHECK(heartbeatsIn(rig) >= 2);

    rig.drive.crash();
    CHECK(sim::NodeLife::kCrashed == rig.drive.life());
    for (int i = 0; i < 100; ++i) {
        Tpdo t = rig.cycle(0x000F, 1000);
        CHECK_FALSE(t.present);
    }
    hal::CanFrame r;
    CHECK_FALSE(rig.sdoUpload(0x1000, 0, &r));
    rig.idle(core::kNsPerSec);
    CHECK_FALSE(rig.receive(&r));  // nothing at all: no heartbeat, no EMCY, no SDO
    DOUBLES_EQUAL(0.0, rig.drive.wheelSpeedRadS(), 0.001);  // power stage off: the wheel coasted down
    CHECK(rig.drive.stats().framesDiscarded >= 201);

    rig.drive.restart();
    rig.advance(kCycle);
    CHECK(rig.receive(&r));
    LONGS_EQUAL(0x705, r.id);
    LONGS_EQUAL(0x00, r.data[0]);
    CHECK(NmtState::kPreOperational == rig.drive.nmtState());
    // Every object back to its default.
    LONGS_EQUAL(0, rig.uploadValue(0x1017, 0));
    LONGS_EQUAL(0, rig.uploadValue(0x6061, 0));
    LONGS_EQUAL(0, rig.uploadValue(0x60FF, 0));
    LONGS_EQUAL(0, rig.uploadValue(0x6040, 0));
    LONGS_EQUAL(1, rig.uploadValue(0x1800, 2));
    rig.idle(core::kNsPerSec);
    LONGS_EQUAL(0, heartbeatsIn(rig));
    CHECK(PowerState::kSwitchOnDisabled == rig.drive.powerState());

    // The master configures it again and it drives.
    rig.drain();
    hal::CanFrame a;
    CHECK(rig.sdoDownload(0x1017, 0, 100, 2, &a));
    CHECK(rig.sdoDownload(0x6060, 0, 3, 1, &a));
    rig.nmt(0x01, kNode);
    rig.step();
    (void)rig.cycle(0x0006, 0);
    (void)rig.cycle(0x0007, 0);
    Tpdo t;
    for (int i = 0; i < 100; ++i) {
        t = rig.cycle(0x000F, 1000);
    }
    CHECK(t.velocity >= 990);
}

TEST(DriveLifecycle, FramesSentWhileBootingAreNotSeen) {
    rig.drive.powerOn();
    rig.nmt(0x01, 0);  // before the node listens
    rig.step();
    CHECK(NmtState::kPreOperational == rig.drive.nmtState());
    LONGS_EQUAL(1, rig.drive.stats().framesDiscarded);
}

TEST(DriveLifecycle, SuppressedHeartbeatsButOtherwiseAlive) {
    rig.configureAndStart();
    rig.drive.setHeartbeatSuppressed(true);
    rig.idle(core::kNsPerSec);
    LONGS_EQUAL(0, heartbeatsIn(rig));
    LONGS_EQUAL(10, rig.drive.stats().heartbeatsSuppressed);
    LONGS_EQUAL(0x00020192, rig.uploadValue(0x1000, 0));
    CHECK(rig.cycle(0x0000, 0).present);
    rig.drive.setHeartbeatSuppressed(false);
    rig.idle(core::kNsPerSec);
    LONGS_EQUAL(10, heartbeatsIn(rig));
}

TEST(DriveLifecycle, HostileFramesAreCountedAndTheDriveKeepsWorking) {
    rig.boot();
    const std::uint8_t junk[8] = {0x0F, 0x00, 0xE8, 0x03, 0x00, 0x00, 0x00, 0x00};
    // Pre-operational: an RPDO1 and a SYNC do nothing.
    rig.send(0x205, 6, junk);
    rig.sync();
    rig.advance(kCycle);
    hal::CanFrame f;
    CHECK_FALSE(rig.receive(&f));
    LONGS_EQUAL(1, rig.drive.stats().rpdoNotOperational);
    // NMT with the wrong DLC, and an unknown command.
    const std::uint8_t start[3] = {0x01, kNode, 0x00};
    rig.send(0x000, 1, start);
    rig.send(0x000, 3, start);
    const std::uint8_t bogus[2] = {0x55, kNode};
    rig.send(0x000, 2, bogus);
    rig.step();
    CHECK(NmtState::kPreOperational == rig.drive.nmtState());
    LONGS_EQUAL(2, rig.drive.stats().nmtMalformed);
    LONGS_EQUAL(1, rig.drive.stats().nmtUnknownCommand);
    // SDO with the wrong DLC; an unknown command specifier.
    const std::uint8_t upload[8] = {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0};
    rig.send(0x605, 7, upload);
    rig.step();
    CHECK_FALSE(rig.receive(&f));
    LONGS_EQUAL(1, rig.drive.sdoStats().malformed);
    const std::uint8_t ccs6[8] = {0xC0, 0x00, 0x10, 0x00, 0, 0, 0, 0};
    CHECK(rig.sdo(ccs6, &f));
    LONGS_EQUAL(0x05040001, DriveRig::abortCode(f));
    // A remote frame on the RPDO id is not a PDO.
    hal::CanFrame rtr = test::makeFrame(0x205, 6, junk);
    rtr.flags = hal::CanFrame::kRemote;
    rig.send(rtr);
    rig.step();
    LONGS_EQUAL(1, rig.drive.stats().framesIgnored);

    // Operational: RPDO1 with DLC 5 and 8 -> ignored, one EMCY 0x8210 (communication bit).
    hal::CanFrame a;
    CHECK(rig.sdoDownload(0x6060, 0, 3, 1, &a));
    rig.nmt(0x01, kNode);
    rig.step();
    (void)rig.cycle(0x0006, 0);
    (void)rig.cycle(0x0007, 0);
    (void)rig.cycle(0x000F, 0);
    rig.drain();
    rig.clock.advance(kCycle);
    rig.send(0x205, 5, junk);
    rig.send(0x205, 8, junk);
    rig.sync();
    rig.step();
    Captured c = rig.capture();
    LONGS_EQUAL(1, c.countId(0x085));
    CHECK(c.find(0x085, &f));
    LONGS_EQUAL(0x10, f.data[0]);
    LONGS_EQUAL(0x82, f.data[1]);
    LONGS_EQUAL(0x11, f.data[2]);  // generic + communication
    CHECK(c.find(0x185, &f));
    Tpdo t = DriveRig::decodeTpdo(f);
    LONGS_EQUAL(0x0027, t.statusword & 0x006F);  // still enabled: a length error is not a drive fault
    LONGS_EQUAL(2, rig.drive.stats().rpdoMalformed);
    // SYNC with a counter byte (none configured): ignored.
    const std::uint8_t counter[1] = {7};
    rig.send(0x080, 1, counter);
    rig.step();
    CHECK_FALSE(rig.receive(&f));
    LONGS_EQUAL(1, rig.drive.stats().syncMalformed);

    // The next good RPDO1 clears the communication error: EMCY 0x0000, register 0.
    c = rig.cycleAll(0x000F, 500);
    CHECK(c.find(0x085, &f));
    LONGS_EQUAL(0, f.data[0] | f.data[1] | f.data[2]);
    for (int i = 0; i < 100; ++i) {
        t = rig.cycle(0x000F, 500);
    }
    CHECK(t.velocity >= 495 && t.velocity <= 505);
    LONGS_EQUAL(0, rig.drive.stats().faults);
}

TEST(DriveLifecycle, AtMost64FramesPerStep) {
    rig.boot();
    const std::uint8_t other[2] = {0x01, 9};
    for (int i = 0; i < 100; ++i) {
        rig.send(0x000, 2, other);
    }
    rig.step();
    LONGS_EQUAL(64, rig.drive.stats().nmtOtherNode);
    LONGS_EQUAL(1, rig.drive.stats().frameBudgetHits);
    rig.step();
    LONGS_EQUAL(100, rig.drive.stats().nmtOtherNode);
}

TEST(DriveLifecycle, TimeNeverRunsBackwards) {
    rig.boot();
    rig.advance(50 * core::kNsPerMs);
    rig.drive.step(10 * core::kNsPerMs);
    LONGS_EQUAL(1, rig.drive.stats().timeWentBack);
}

// ---------------------------------------------------------------------------

namespace {

// A scripted mission for one rig: every frame the drive sends is recorded.
struct Recording {
    static constexpr std::size_t kMax = 4096;
    hal::CanFrame frames[kMax];
    std::size_t count = 0;
    void take(DriveRig& rig) {
        hal::CanFrame f;
        while (rig.receive(&f)) {
            if (count < kMax) {
                frames[count++] = f;
            }
        }
    }
};

void script(DriveRig& rig, Recording& rec) {
    rig.drive.powerOn();
    rig.step();
    rec.take(rig);
    hal::CanFrame r;
    (void)rig.sdoDownload(0x1017, 0, 100, 2, &r);
    (void)rig.sdoDownload(0x6060, 0, 3, 1, &r);
    const std::uint8_t name[8] = {0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0};
    (void)rig.sdo(name, &r);
    const std::uint8_t seg0[8] = {0x60, 0, 0, 0, 0, 0, 0, 0};
    (void)rig.sdo(seg0, &r);
    rec.take(rig);
    rig.nmt(0x01, 0);
    const std::uint16_t walk[] = {0x0006, 0x0007, 0x000F};
    for (std::uint16_t cw : walk) {
        rig.clock.advance(kCycle);
        rig.rpdo(cw, 0);
        rig.sync();
        rig.step();
        rec.take(rig);
    }
    for (int i = 0; i < 300; ++i) {
        if (i == 100) {
            rig.drive.setDegradation(1.3);
            rig.drive.setLoadTorque(0.8);
        }
        if (i == 200) {
            rig.drive.failMotor();
        }
        rig.clock.advance(kCycle);
        rig.rpdo(i > 200 && (i % 10) == 5 ? 0x0080 : 0x000F, 300 + 7 * i);
        rig.sync();
        rig.step();
        rec.take(rig);
    }
    rig.drive.restart();
    rig.idle(200 * core::kNsPerMs);
    rec.take(rig);
}

}  // namespace

TEST_GROUP(DriveDeterminism) {
    DriveRig a;
    DriveRig b;
    Recording ra;
    Recording rb;
};

TEST(DriveDeterminism, SameFramesAndTimesGiveTheSameFrames) {
    script(a, ra);
    script(b, rb);
    CHECK(ra.count > 300);
    LONGS_EQUAL(ra.count, rb.count);
    for (std::size_t i = 0; i < ra.count; ++i) {
        LONGS_EQUAL(ra.frames[i].id, rb.frames[i].id);
        LONGS_EQUAL(ra.frames[i].dlc, rb.frames[i].dlc);
        CHECK_EQUAL(ra.frames[i].timestamp, rb.frames[i].timestamp);
        for (int k = 0; k < 8; ++k) {
            LONGS_EQUAL(ra.frames[i].data[k], rb.frames[i].data[k]);
        }
    }
    DOUBLES_EQUAL(a.drive.wheelSpeedRadS(), b.drive.wheelSpeedRadS(), 0.0);
}

TEST(DriveDeterminism, NothingIsAllocatedAfterConstruction) {
    Recording* rec = &ra;
    std::uint64_t allocations = 0;
    {
        test::AllocationWatch watch;
        script(a, *rec);
        a.drive.crash();
        a.idle(100 * core::kNsPerMs);
        a.drive.restart();
        a.nmt(0x82, 0);
        a.idle(100 * core::kNsPerMs);
        allocations = watch.count();
    }
    LONGS_EQUAL(0, allocations);
    CHECK(rec->count > 300);
}

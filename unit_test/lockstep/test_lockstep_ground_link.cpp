// Lockstep: a ground station on the CAN bus talks ISO-TP to the flight software.
#include <cstring>

#include "hal/can/isotp.hpp"
#include "unit_test/lockstep/lockstep_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

struct Ground {
    hal::MemoryCanEndpoint* can = nullptr;
    hal::IsoTpChannel* channel = nullptr;
};
Ground g_ground;

// Every frame: the ground side reads its endpoint and advances its ISO-TP channel.
void serviceGround(test::LockstepRig&) {
    hal::CanFrame f;
    while (core::isOk(g_ground.can->receive(&f))) {
        if (f.id == app::kGroundDownlinkCobId) {
            g_ground.channel->onFrame(f);
        }
    }
    g_ground.channel->poll();
}

hal::IsoTpConfig groundConfig() {
    hal::IsoTpConfig c;
    c.txId = app::kGroundUplinkCobId;
    c.rxId = app::kGroundDownlinkCobId;
    return c;
}

}  // namespace

TEST_GROUP(LockstepGroundLink) {
    test::LockstepRig* rig = nullptr;
    core::EventLog* groundEvents = nullptr;
    void setup() override {
        rig = new test::LockstepRig("sim_stub/scenarios/straight_10m.toml");
        CHECK(core::Status::kOk == rig->init());
        groundEvents = new core::EventLog(rig->clock());
        g_ground.can = rig->wire().attach("ground");
        g_ground.channel = new hal::IsoTpChannel(*g_ground.can, rig->clock(), *groundEvents, groundConfig());
        rig->setOnFrame(serviceGround);
    }
    void teardown() override {
        delete g_ground.channel;
        delete groundEvents;
        delete rig;
    }
};

TEST(LockstepGroundLink, FourThousandBytePacketComesBackIntactWhileTheRoverDrives) {
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * core::kNsPerSec));
    rig->commandAllWheels(1.0);
    static std::uint8_t sent[4000];
    for (std::size_t i = 0; i < sizeof sent; ++i) {
        sent[i] = static_cast<std::uint8_t>((i * 7 + 3) & 0xFF);
    }
    CHECK(core::Status::kOk == g_ground.channel->send(sent, sizeof sent));
    static std::uint8_t got[hal::kIsoTpMaxMessage];
    std::size_t length = 0;
    const core::TimeNs sentAt = rig->clock().now();
    CHECK_TRUE(rig->runUntil([&] { return core::isOk(g_ground.channel->receive(got, sizeof got, &length)); },
                             5 * core::kNsPerSec));
    char diag[256];
    const hal::IsoTpStats& fs = rig->fsw().canIo().groundLink().channel().stats();
    const hal::IsoTpStats& gs = g_ground.channel->stats();
    std::snprintf(diag, sizeof diag, "ground link: 4000 bytes there and back in %.2f s (%u + %u CAN frames)",
                  static_cast<double>(rig->clock().now() - sentAt) * 1e-9, gs.txFrames + fs.txFrames,
                  gs.rxFrames + fs.rxFrames);
    UT_PRINT(diag);
    LONGS_EQUAL(sizeof sent, length);
    MEMCMP_EQUAL(sent, got, sizeof sent);
    LONGS_EQUAL(1, rig->fsw().canIo().groundLink().echoed());
    // Driving went on undisturbed: every drive still operational, no CAN drops.
    CHECK_TRUE(rig->allDrivesOperational());
    LONGS_EQUAL(0, rig->fsw().executive().stats().frameOverruns);
}

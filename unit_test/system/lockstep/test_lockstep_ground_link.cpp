// Lockstep: a ground station on the CAN bus talks ISO-TP to the flight software,
// whose CanGroundLink carries commands to command ingest and telemetry from
// telemetry output, while the rover drives.
#include <cstdio>
#include <cstring>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_packet.hpp"
#include "hal/can/isotp.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

struct Ground {
    hal::MemoryCanEndpoint* can = nullptr;
    hal::IsoTpChannel* channel = nullptr;
    std::uint32_t packets = 0;       // complete downlink messages
    std::uint32_t malformed = 0;     // ... that are not a whole CCSDS telemetry packet
    std::uint8_t buffer[hal::kIsoTpMaxMessage] = {};
};
Ground g_ground;

// A whole CCSDS telemetry packet: version 0, type telemetry, and the header's
// length field matches the message (docs/icd.md, ground link).
bool isTelemetryPacket(const std::uint8_t* data, std::size_t length) {
    if (length < cmdtlm::kTelemetryHeaderSize || length > cmdtlm::kMaxTelemetryPacket) {
        return false;
    }
    const cmdtlm::PrimaryHeader h = cmdtlm::decodePrimaryHeader(data);
    return h.version == 0 && h.type == cmdtlm::PacketType::kTelemetry && h.dataLength + 7U == length;
}

// Every frame: the ground side reads its endpoint, advances its ISO-TP channel
// and takes every completed downlink message.
void serviceGround(sim::LockstepRig&) {
    hal::CanFrame f;
    while (core::isOk(g_ground.can->receive(&f))) {
        if (f.id == io::kGroundDownlinkCobId) {
            g_ground.channel->onFrame(f);
        }
    }
    g_ground.channel->poll();
    std::size_t length = 0;
    while (core::isOk(g_ground.channel->receive(g_ground.buffer, sizeof g_ground.buffer, &length))) {
        ++g_ground.packets;
        g_ground.malformed += isTelemetryPacket(g_ground.buffer, length) ? 0U : 1U;
    }
}

hal::IsoTpConfig groundConfig() {
    hal::IsoTpConfig c;
    c.txId = io::kGroundUplinkCobId;
    c.rxId = io::kGroundDownlinkCobId;
    c.blockSize = 8;  // as the rover asks of the ground: one block of 8 CFs per flow control
    return c;
}

}  // namespace

TEST_GROUP(LockstepGroundLink) {
    sim::LockstepRig* rig = nullptr;
    core::EventLog* groundEvents = nullptr;
    void setup() override {
        rig = new sim::LockstepRig("sim_stub/scenarios/straight_10m.toml");
        CHECK(core::Status::kOk == rig->init());
        groundEvents = new core::EventLog(rig->clock());
        g_ground = Ground{};
        g_ground.can = rig->wire().attach("ground");
        g_ground.channel = new hal::IsoTpChannel(*g_ground.can, rig->clock(), *groundEvents, groundConfig());
        rig->setOnFrame(serviceGround);
    }
    void teardown() override {
        delete g_ground.channel;
        delete groundEvents;
        delete rig;
    }
    const io::CanGroundLink& link() { return rig->fsw().canIo().groundLink(); }
};

TEST(LockstepGroundLink, TelemetryComesDownAsWholeCcsdsPacketsWhileTheRoverDrives) {
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * core::kNsPerSec));
    rig->runFor(core::kNsPerSec);
    LONGS_EQUAL(0, g_ground.packets);  // nobody heard on 0x6C0 yet: the downlink holds back
    LONGS_EQUAL(0, link().stats().txDropped);

    // The ground says NOOP; from then on telemetry comes down.
    cmdtlm::HmacSha256 hmac;
    CHECK(core::isOk(hmac.init()));
    cmdtlm::CommandFields noop;
    noop.apid = 0x180;
    noop.keyId = cmdtlm::kLabKeyId;
    noop.authSequence = 1;
    std::uint8_t packet[cmdtlm::kMaxCommandPacket];
    const std::size_t n = cmdtlm::encodeCommandPacket(noop, nullptr, 0, cmdtlm::kLabKey, hmac, packet, sizeof packet);
    CHECK(core::Status::kOk == g_ground.channel->send(packet, n));
    CHECK_TRUE(rig->runUntil([&] { return rig->fsw().commands().counters().accepted == 1; }, core::kNsPerSec));
    rig->commandAllWheels(1.0);
    const std::uint32_t before = g_ground.packets;
    rig->runFor(3 * core::kNsPerSec);

    char diag[200];
    const hal::PacketLinkStats& s = link().stats();
    std::snprintf(diag, sizeof diag,
                  "CAN ground link, 3 s driving: %u packets down, %u queued, %u refused (queue full), %u aborted",
                  static_cast<unsigned>(g_ground.packets - before), static_cast<unsigned>(s.txPackets),
                  static_cast<unsigned>(s.txDropped), static_cast<unsigned>(link().txAborted()));
    UT_PRINT(diag);
    CHECK(g_ground.packets - before >= 3);  // at least the 1 Hz housekeeping
    LONGS_EQUAL(0, g_ground.malformed);
    LONGS_EQUAL(0, link().txAborted());
    // What the ground got is what the link completed (give or take the one in flight).
    CHECK(link().txCompleted() >= g_ground.packets && link().txCompleted() <= g_ground.packets + 1);
    // Driving went on undisturbed: every drive still operational, no frame overran.
    CHECK_TRUE(rig->allDrivesOperational());
    LONGS_EQUAL(0, rig->fsw().executive().stats().frameOverruns);
}

TEST(LockstepGroundLink, AnUplinkMessageIsReadByCommandIngest) {
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * core::kNsPerSec));
    static std::uint8_t sent[200];
    for (std::size_t i = 0; i < sizeof sent; ++i) {
        sent[i] = static_cast<std::uint8_t>((i * 7 + 3) & 0xFF);
    }
    const std::uint32_t before = link().stats().rxPackets;
    CHECK(core::Status::kOk == g_ground.channel->send(sent, sizeof sent));
    CHECK_TRUE(rig->runUntil([&] { return link().stats().rxPackets == before + 1; }, 2 * core::kNsPerSec));
    CHECK(g_ground.channel->txResult() == hal::IsoTpTxResult::kDone);
    LONGS_EQUAL(0, link().stats().rxDropped);
    LONGS_EQUAL(0, link().channel().pendingMessages());  // taken, nothing left waiting
}

TEST(LockstepGroundLink, AnUploadLongerThanACommandIsRefusedByTheRoverOnTheWire) {
    static std::uint8_t sent[4000];
    CHECK(core::Status::kOk == g_ground.channel->send(sent, sizeof sent));
    CHECK_TRUE(rig->runUntil([&] { return !g_ground.channel->txBusy(); }, 2 * core::kNsPerSec));
    CHECK(g_ground.channel->txResult() == hal::IsoTpTxResult::kPeerOverflow);
    LONGS_EQUAL(1, link().channel().stats().rxTooLong);
    LONGS_EQUAL(1, link().stats().rxDropped);
}

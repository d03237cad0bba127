// The master's wheel drive client against the independent CiA 402 drive
// emulator (and, where a server must misbehave on cue, a scripted SDO server):
// the FAULT_RESPONSE limits it is given (DriveConfig) and the boot timeout
// change what it does, and a fault taken before the node is operational clears.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "hal/canopen/canopen_events.hpp"
#include "hal/canopen/canopen_master.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/devices/wheel_drive.hpp"
#include "sim_stub/drives/cia402_drive_emulator.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal;
using core::kNsPerMs;
using core::kNsPerSec;

namespace {

constexpr core::TimeNs kCycle = 10 * kNsPerMs;
constexpr core::TimeNs kHeartbeatTimeout = 250 * kNsPerMs;

// The flight side (master + one drive client) and the devices on one bus.
struct Rig {
    core::VirtualClock clock;
    core::EventLog events{clock};
    MemoryCanBus wire{clock};
    MemoryCanEndpoint* flightEnd = wire.attach("flight");
    MemoryCanEndpoint* driveEnd = wire.attach("drive");
    MemoryCanEndpoint* peer = wire.attach("peer");  // scripted servers
    canopen::CanOpenMaster master{*flightEnd, events};
    WheelDrive drive{*flightEnd, events, master.heartbeats(), 1, "FL"};
    sim::Cia402DriveEmulator emulator;
    bool emulatorOn = true;
    unsigned eventCount[1000] = {};
    char lastText[1000][core::kEventTextSize] = {};

    explicit Rig(std::uint8_t emulatorNode = 1) : emulator(*driveEnd, emulatorNode) {}

    void start(const DriveConfig& config, std::uint8_t node = 1, core::TimeNs bootTimeout = 0) {
        CHECK(core::Status::kOk == drive.configure(node, config));
        CHECK(core::Status::kOk == master.addNode(&drive, kHeartbeatTimeout, bootTimeout));
    }
    void collectEvents() {
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            if (e.id < 1000) {
                ++eventCount[e.id];
                std::memcpy(lastText[e.id], e.text, sizeof e.text);
            }
        }
    }
    // One minor frame: the devices answer what they got, then the master cycles.
    void cycle() {
        clock.advance(kCycle);
        if (emulatorOn) {
            emulator.step(clock.now());
        }
        master.cycle(clock.now());
        collectEvents();
    }
    template <typename Pred>
    bool runUntil(Pred done, core::TimeNs limit) {
        for (core::TimeNs t = 0; t < limit; t += kCycle) {
            cycle();
            if (done()) {
                return true;
            }
        }
        return false;
    }
    bool runUntilState(DriveState s, core::TimeNs limit) {
        return runUntil([&] { return drive.state() == s; }, limit);
    }
};

CanFrame sdoAnswer(std::uint8_t node, std::uint8_t cmd, const CanFrame& request, std::uint32_t value) {
    CanFrame f;
    f.id = 0x580U + node;
    f.dlc = 8;
    f.data[0] = cmd;
    f.data[1] = request.data[1];
    f.data[2] = request.data[2];
    f.data[3] = request.data[3];
    for (int i = 0; i < 4; ++i) {
        f.data[4 + i] = static_cast<std::uint8_t>((value >> (8 * i)) & 0xFF);
    }
    return f;
}

// A node-1 SDO server on the peer endpoint that aborts the first `aborts`
// requests for 0x1000 (device type) with `abortCode`, then answers properly;
// step 2 (0x1017) is aborted with `laterAbort` when it is non-zero.
struct ScriptedServer {
    unsigned aborts = 0;
    std::uint32_t abortCode = 0x08000020;  // data cannot be transferred
    std::uint32_t laterAbort = 0;
    unsigned deviceTypeRequests = 0;
    unsigned heartbeatRequests = 0;

    void serve(MemoryCanEndpoint& peer) {
        CanFrame r;
        while (core::isOk(peer.receive(&r))) {
            if (r.id != 0x601) {
                continue;
            }
            const std::uint16_t index = static_cast<std::uint16_t>(r.data[1] | (r.data[2] << 8));
            if (index == 0x1000) {
                ++deviceTypeRequests;
                const bool abort = deviceTypeRequests <= aborts;
                (void)peer.send(abort ? sdoAnswer(1, 0x80, r, abortCode) : sdoAnswer(1, 0x43, r, 0x00020192));
            } else if (index == 0x1017) {
                ++heartbeatRequests;
                (void)peer.send(laterAbort != 0 ? sdoAnswer(1, 0x80, r, laterAbort) : sdoAnswer(1, 0x60, r, 0));
            }
        }
    }
};

// Runs the scripted server against a drive given `retries`; true when the
// configuration got past the device-type check.
bool deviceTypeCheckPasses(unsigned retries, ScriptedServer& server, Rig& rig) {
    DriveConfig config;
    config.sdoRetries = retries;
    rig.emulatorOn = false;
    rig.start(config);
    rig.cycle();  // reset communication
    const CanFrame bootUp = [] {
        CanFrame f;
        f.id = 0x701;
        f.dlc = 1;
        return f;
    }();
    (void)rig.peer->send(bootUp);
    for (int i = 0; i < 100 && server.heartbeatRequests == 0 && rig.drive.state() != DriveState::kFailed; ++i) {
        rig.cycle();
        server.serve(*rig.peer);
    }
    return server.heartbeatRequests > 0;
}

}  // namespace

TEST_GROUP(WheelDrive) {};

TEST(WheelDrive, SdoRetriesAreTriesAfterTheFirstFailure) {
    // Two refusals: passes only when at least two retries follow the first try.
    const struct {
        unsigned retries;
        bool passes;
        unsigned requests;
    } cases[] = {{0, false, 1}, {1, false, 2}, {2, true, 3}, {3, true, 3}};
    for (const auto& c : cases) {
        Rig rig;
        ScriptedServer server;
        server.aborts = 2;
        CHECK_EQUAL(c.passes, deviceTypeCheckPasses(c.retries, server, rig));
        LONGS_EQUAL(c.requests, server.deviceTypeRequests);
        LONGS_EQUAL(c.passes ? 0 : 1, rig.eventCount[events::kDriveConfigFailed]);
        LONGS_EQUAL(c.passes ? 0 : 1, rig.drive.stats().configFailures);
    }
}

TEST(WheelDrive, ConfigFailedEventShowsTheWholeAbortCodeAndNoStaleValue) {
    Rig rig;
    ScriptedServer server;
    server.aborts = 100;
    CHECK_FALSE(deviceTypeCheckPasses(0, server, rig));
    const char* text = rig.lastText[events::kDriveConfigFailed];
    UT_PRINT(text);
    CHECK(std::strstr(text, "abort code 0x08000020") != nullptr);
    CHECK(std::strstr(text, "0x1000:0") != nullptr);

    // The device type read fine (value 0x00020192), then the heartbeat write
    // was refused: the text names that abort, never the earlier read's value.
    Rig later;
    ScriptedServer refusing;
    refusing.laterAbort = 0x06010002;  // read-only object
    CHECK_TRUE(deviceTypeCheckPasses(0, refusing, later));
    CHECK_TRUE(later.runUntilState(DriveState::kFailed, 200 * kNsPerMs));
    const char* laterText = later.lastText[events::kDriveConfigFailed];
    UT_PRINT(laterText);
    CHECK(std::strstr(laterText, "abort code 0x06010002") != nullptr);
    CHECK(std::strstr(laterText, "0x1017:0") != nullptr);
    CHECK(std::strstr(laterText, "00020192") == nullptr);
    // The longest wheel name and node id still leave the code whole.
    CHECK(std::strlen(laterText) + 4 < core::kEventTextSize);
}

TEST(WheelDrive, SdoTimeoutIsHowLongTheServerHasToAnswer) {
    // Both below the 250 ms heartbeat timeout: the scripted node sends no heartbeat.
    for (const core::TimeNs timeout : {40 * kNsPerMs, 200 * kNsPerMs}) {
        Rig rig;
        ScriptedServer silent;  // never answers 0x1000: boot-up only
        DriveConfig config;
        config.sdoRetries = 0;
        config.sdoTimeout = timeout;
        rig.emulatorOn = false;
        rig.start(config);
        rig.cycle();
        CanFrame bootUp;
        bootUp.id = 0x701;
        bootUp.dlc = 1;
        (void)rig.peer->send(bootUp);
        rig.cycle();  // boot-up seen, device type requested
        const core::TimeNs asked = rig.clock.now();
        CHECK_TRUE(rig.runUntilState(DriveState::kFailed, 2 * kNsPerSec));
        const core::TimeNs took = rig.clock.now() - asked;
        CHECK(took > timeout);
        CHECK(took <= timeout + 3 * kCycle);
        CHECK(std::strstr(rig.lastText[events::kDriveConfigFailed], "timeout") != nullptr);
    }
}

TEST(WheelDrive, RestartAttemptsAndResetWaitSetHowLongAFaultedDriveIsTried) {
    const struct {
        unsigned resets;
        core::TimeNs wait;
    } cases[] = {{1, 50 * kNsPerMs}, {3, 50 * kNsPerMs}, {3, 300 * kNsPerMs}};
    for (const auto& c : cases) {
        Rig rig;
        DriveConfig config;
        config.faultResets = c.resets;
        config.faultResetWait = c.wait;
        rig.start(config);
        rig.emulator.powerOn();
        CHECK_TRUE(rig.runUntilState(DriveState::kOperational, 2 * kNsPerSec));
        rig.emulator.failMotor();  // refuses every reset
        CHECK_TRUE(rig.runUntilState(DriveState::kFaulted, 200 * kNsPerMs));
        const core::TimeNs faultedAt = rig.clock.now();
        CHECK_TRUE(rig.runUntilState(DriveState::kFailed, 5 * kNsPerSec));
        const core::TimeNs took = rig.clock.now() - faultedAt;
        LONGS_EQUAL(c.resets, rig.drive.stats().faultResets);
        LONGS_EQUAL(c.resets, rig.emulator.stats().faultResetsRefused);
        // The last reset is given its wait before the drive is declared failed.
        CHECK(took >= static_cast<core::TimeNs>(c.resets) * c.wait);
        CHECK(took <= static_cast<core::TimeNs>(c.resets) * c.wait + 3 * kCycle);
    }
}

TEST(WheelDrive, AFaultTakenBeforeTheNodeIsOperationalIsResetBySdoAndConfigurationCompletes) {
    // When: as the boot-up is seen, and while configuring (pre-operational).
    for (const DriveState when : {DriveState::kWaitingBootUp, DriveState::kConfiguring}) {
        Rig rig;
        rig.start(DriveConfig{});
        rig.emulator.powerOn();
        if (when == DriveState::kWaitingBootUp) {
            rig.emulator.injectFault(0x4310);  // raised at its first step, EMCY right after the boot-up
        } else {
            CHECK_TRUE(rig.runUntilState(DriveState::kConfiguring, 1 * kNsPerSec));
            rig.emulator.injectFault(0x4310);
        }
        CHECK_TRUE(rig.runUntil([&] { return rig.emulator.stats().faults > 0; }, 100 * kNsPerMs));
        CHECK_TRUE(rig.runUntilState(DriveState::kOperational, 3 * kNsPerSec));
        CHECK(rig.drive.stats().sdoFaultResets >= 1);
        LONGS_EQUAL(1, rig.emulator.stats().faultResets);
        CHECK(rig.emulator.nmtState() == sim::NmtState::kOperational);
        CHECK(rig.emulator.powerState() == sim::PowerState::kOperationEnabled);
    }
}

TEST(WheelDrive, AFaultResetRequestGivesAFailedDriveAFreshRound) {
    Rig rig;
    DriveConfig config;
    config.faultResets = 1;
    rig.start(config);
    rig.emulator.powerOn();
    CHECK_TRUE(rig.runUntilState(DriveState::kOperational, 2 * kNsPerSec));
    LONGS_EQUAL(static_cast<long>(core::Status::kUnavailable),
                static_cast<long>(rig.drive.requestFaultReset(rig.clock.now())));
    // Its one reset is lost on the bus, so the drive is declared failed.
    CanFaultRule drop;
    drop.id = 0x201;
    drop.mask = 0x7FF;
    drop.count = 0;
    CHECK(core::Status::kOk == rig.wire.addFault(drop));
    rig.emulator.injectFault(0x4310);
    CHECK_TRUE(rig.runUntilState(DriveState::kFailed, 2 * kNsPerSec));
    rig.wire.clearFaults();
    rig.runUntil([] { return false; }, 200 * kNsPerMs);
    CHECK(rig.drive.state() == DriveState::kFailed);  // failed stays failed on its own
    CHECK(core::Status::kOk == rig.drive.requestFaultReset(rig.clock.now()));
    CHECK_TRUE(rig.runUntilState(DriveState::kOperational, 2 * kNsPerSec));
    LONGS_EQUAL(1, rig.eventCount[events::kDriveResetRequested]);
    LONGS_EQUAL(1, rig.drive.stats().resetRequests);
}

TEST(WheelDrive, ADriveThatNeverBootsIsDeclaredLostAfterTheBootTimeout) {
    for (const core::TimeNs bootTimeout : {1 * kNsPerSec, 3 * kNsPerSec}) {
        Rig rig;
        rig.start(DriveConfig{}, 1, bootTimeout);
        rig.runUntil([] { return false; }, bootTimeout - 2 * kCycle);
        const canopen::NodeHealth* health = rig.master.heartbeats().node(1);
        CHECK_FALSE(health->lost);
        CHECK(rig.drive.state() == DriveState::kWaitingBootUp);
        rig.runUntil([] { return false; }, 4 * kCycle);
        CHECK_TRUE(health->lost);
        LONGS_EQUAL(1, health->losses);
        LONGS_EQUAL(1, rig.eventCount[events::kNodeNeverBooted]);
        CHECK(rig.drive.state() == DriveState::kLost);
        rig.runUntil([] { return false; }, 1 * kNsPerSec);
        LONGS_EQUAL(1, rig.eventCount[events::kNodeNeverBooted]);  // once, not every cycle
        // It boots late: configured and enabled as at any start.
        rig.emulator.powerOn();
        CHECK_TRUE(rig.runUntilState(DriveState::kOperational, 2 * kNsPerSec));
        CHECK_FALSE(health->lost);
    }
}

TEST(WheelDrive, NoBootTimeoutMeansANeverHeardNodeIsNotJudged) {
    Rig rig;
    rig.start(DriveConfig{}, 1, 0);
    rig.runUntil([] { return false; }, 10 * kNsPerSec);
    CHECK_FALSE(rig.master.heartbeats().node(1)->lost);
    CHECK(rig.drive.state() == DriveState::kWaitingBootUp);
}

TEST(WheelDrive, TheNodeIdGivenAtStartUpIsTheOneDriven) {
    Rig rig(7);
    rig.start(DriveConfig{}, 7);
    rig.emulator.powerOn();
    CHECK_TRUE(rig.runUntilState(DriveState::kOperational, 2 * kNsPerSec));
    LONGS_EQUAL(7, rig.drive.nodeId());
    LONGS_EQUAL(7, rig.drive.sdo().nodeId());
    WheelDrive spare{*rig.flightEnd, rig.events, rig.master.heartbeats(), 2, "ML"};
    LONGS_EQUAL(static_cast<long>(core::Status::kInvalidArgument),
                static_cast<long>(spare.configure(0, DriveConfig{})));
    LONGS_EQUAL(static_cast<long>(core::Status::kInvalidArgument),
                static_cast<long>(spare.configure(128, DriveConfig{})));
    LONGS_EQUAL(2, spare.nodeId());
}

TEST(WheelDrive, MotorTemperatureIsDecodedFromTpdo2) {
    Rig rig;
    rig.emulator.setAmbientTemperature(-12.3);
    rig.start(DriveConfig{});
    rig.emulator.powerOn();
    CHECK_TRUE(rig.runUntilState(DriveState::kStarting, 2 * kNsPerSec));
    LONGS_EQUAL(0, rig.drive.feedback().temperatureCount);  // unknown until the first TPDO2
    CHECK_TRUE(rig.runUntilState(DriveState::kOperational, 2 * kNsPerSec));
    rig.runUntil([] { return false; }, 1 * kNsPerSec);
    CHECK(rig.drive.feedback().temperatureCount >= 9);
    // Holding zero speed still draws current, so it warms a little between reports.
    const std::int16_t reported = rig.drive.feedback().temperatureDeciC;
    CHECK(reported > -123);
    CHECK(std::abs(static_cast<double>(reported) - 10.0 * rig.emulator.temperatureC()) < 2.0);
    // A TPDO2 of the wrong length is counted, the last good value kept.
    CanFrame bad;
    bad.id = 0x281;
    bad.dlc = 4;
    (void)rig.peer->send(bad);
    const std::uint32_t badBefore = rig.drive.stats().badPdo;
    rig.emulatorOn = false;
    rig.cycle();
    LONGS_EQUAL(badBefore + 1, rig.drive.stats().badPdo);
    LONGS_EQUAL(reported, rig.drive.feedback().temperatureDeciC);
}

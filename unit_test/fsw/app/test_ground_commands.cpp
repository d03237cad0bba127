// The whole flight application commanded from a ground station over an
// in-memory link (ground_station_rig.hpp): each command reaches its owner and
// is acknowledged; what it changes shows in housekeeping and on the bus. The
// packets' schedule and content: test_ground_telemetry.cpp.
#include "unit_test/fsw/app/ground_station_rig.hpp"

using namespace rse;
using namespace rse::cmdtlm;
using namespace rse::test::ground;

TEST_GROUP_BASE(GroundCommands, GroundStation){};

TEST(GroundCommands, SetModeIsAcknowledgedAndShownInHousekeeping) {
    runFrames(1);
    LONGS_EQUAL(0, static_cast<long>(field(last("HK"), "mode")));  // boots in SAFE
    send("SET_MODE", {1});
    send("REQUEST_HK");
    runFrames(2);
    expectAccepted("REQUEST_HK");
    const Packet& hk = last("HK");
    LONGS_EQUAL(1, static_cast<long>(field(hk, "mode")));
    LONGS_EQUAL(2, static_cast<long>(field(hk, "cmd_accepted")));
    LONGS_EQUAL(1, static_cast<long>(field(hk, "auth_required")));
    LONGS_EQUAL(16, static_cast<long>(field(hk, "task_count")));
    LONGS_EQUAL(0, countOf("TASK_TIMING"));
    runFrames(30);
    LONGS_EQUAL(16, countOf("TASK_TIMING"));  // one per task, in minor frames 10..25
    CHECK(countOf("EVENT") > 5);             // the start-up events came down
}

TEST(GroundCommands, RejectionsAreCountedByReasonInHousekeeping) {
    send("DRIVE", f32s({0.1F, 0.0F, 1.0F}));  // SAFE mode: wrong mode
    send("SET_MODE", {9});                     // out of range
    send("REQUEST_HK");
    runFrames(3);
    const Packet& hk = last("HK");
    LONGS_EQUAL(2, static_cast<long>(field(hk, "cmd_rejected")));
    LONGS_EQUAL(1, static_cast<long>(field(hk, "cmd_rejected_by_reason", 13)));
    LONGS_EQUAL(1, static_cast<long>(field(hk, "cmd_rejected_by_reason", 12)));
}

TEST(GroundCommands, PlanExtendReachesThePlanExecutiveWhichSaysWhyItRefusesIt) {
    CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kPlanCommand)));
    std::vector<std::uint8_t> args = f32s({12.34F});
    const char* name = "sample1";
    args.insert(args.end(), name, name + std::strlen(name));
    send("PLAN_EXTEND", args);  // SAFE at start
    runFrames(3);
    CHECK(static_cast<long>(field(last("CMD_ACK"), "reason")) != 0);
    send("SET_MODE", {1});
    send("PLAN_EXTEND", args);
    runFrames(2);
    expectAccepted("PLAN_EXTEND");
    core::Message m;
    msg::PlanCommandMsg plan{};
    bool seen = false;
    while (core::isOk(fsw.bus().receive(probe, &m))) {
        if (m.header.id == msg::ids::kPlanCommand) {
            CHECK(core::isOk(m.decode(&plan)));
            seen = true;
        }
    }
    CHECK_TRUE(seen);
    CHECK(plan.kind == msg::PlanCommandKind::kExtend);
    LONGS_EQUAL(12340, plan.extendMs);
    LONGS_EQUAL(7, plan.length);
    MEMCMP_EQUAL(name, plan.data, 7);
    runFrames(150);
    LONGS_EQUAL(1, eventCount(976));
    const Packet& exec = last("PLAN_EXEC");
    LONGS_EQUAL(1, static_cast<long>(field(exec, "extensions_refused")));
    LONGS_EQUAL(1, static_cast<long>(field(exec, "last_extension_refusal")));  // unknown activity: no plan
    LONGS_EQUAL(0, static_cast<long>(field(exec, "extensions")));
}

TEST(GroundCommands, ManualDriveTurnsIntoSkidSteerWheelSpeedsAndStops) {
    send("SET_MODE", {3});
    send("DRIVE", f32s({0.25F, 0.0F, 0.5F}));
    runFrames(3);
    expectAccepted("DRIVE");
    core::Message m;
    msg::WheelCommandMsg cmd{};
    CHECK(core::isOk(fsw.bus().receive(probe, &m)));
    CHECK(core::isOk(m.decode(&cmd)));
    const double radius = static_cast<double>(fsw.tables().roverGeometry().wheel_radius_m);
    for (double v : cmd.velocityRadS) {
        DOUBLES_EQUAL(0.25 / radius, v, 1e-9);
    }
    CHECK(fsw.manualDrive().driving());
    runFrames(60);  // 0.5 s and a little
    CHECK_FALSE(fsw.manualDrive().driving());
    CHECK(core::isOk(fsw.bus().receive(probe, &m)));
    CHECK(core::isOk(m.decode(&cmd)));
    for (double v : cmd.velocityRadS) {
        DOUBLES_EQUAL(0.0, v, 0.0);
    }
}

TEST(GroundCommands, EstopZeroesTheDrivesAndHoldsOffCommands) {
    msg::WheelCommandMsg moving{};
    for (double& v : moving.velocityRadS) {
        v = 2.0;
    }
    CHECK(core::isOk(fsw.bus().publish(moving)));
    runFrames(1);
    CHECK(fsw.canIo().drive(0).targetVelocityMradS() != 0);
    send("ESTOP_SET");
    runFrames(2);  // executed in one frame, enforced by CAN I/O in the next
    CHECK(fsw.canIo().estopHeld());
    LONGS_EQUAL(0, fsw.canIo().drive(0).targetVelocityMradS());
    CHECK(core::isOk(fsw.bus().publish(moving)));
    runFrames(1);
    LONGS_EQUAL(0, fsw.canIo().drive(0).targetVelocityMradS());
    LONGS_EQUAL(1, fsw.canIo().commandsHeldByEstop());
    send("ESTOP_CLEAR");
    runFrames(2);
    CHECK_FALSE(fsw.canIo().estopHeld());
    LONGS_EQUAL(0, fsw.canIo().drive(0).targetVelocityMradS());  // stays at zero until commanded
}

// RESET_INTERLOCK is taken in SAFE (the mode a call home leaves the rover in)
// and reaches CAN I/O (no drive attached here: none is unhealthy, so the reset
// goes through); it is refused as wrong_mode while AUTONOMOUS. The trip,
// refused reset and release on simulated drives: unit_test/system/lockstep.
TEST(GroundCommands, ResetInterlockIsTakenInSafeAndRefusedWhileAutonomous) {
    send("RESET_INTERLOCK");
    runFrames(2);
    expectAccepted("RESET_INTERLOCK");
    CHECK_FALSE(fsw.canIo().interlock().tripped());
    send("SET_MODE", {2});
    send("RESET_INTERLOCK");
    runFrames(2);
    const Packet& ack = last("CMD_ACK");
    LONGS_EQUAL(findCommand("RESET_INTERLOCK")->apid, static_cast<long>(field(ack, "apid")));
    CHECK(static_cast<long>(field(ack, "reason")) != 0);
}

TEST(GroundCommands, AModeChangeStopsTheWheelsTheLayerLeftTurning) {
    core::EventLog::Cursor events;  // the telemetry task pops events; read them beside it
    send("SET_MODE", {3});
    send("DRIVE", f32s({0.25F, 0.0F, 5.0F}));
    runFrames(3);
    CHECK(fsw.canIo().drive(0).targetVelocityMradS() != 0);
    send("SET_MODE", {1});  // STANDBY: manual drive loses authority mid-drive
    runFrames(2);           // executed in one frame, applied by CAN I/O in the next
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        LONGS_EQUAL(0, fsw.canIo().drive(w).targetVelocityMradS());
    }
    // Evented once, and not again for a mode change with nothing turning.
    send("SET_MODE", {0});
    runFrames(2);
    unsigned stops = 0;
    core::Event e;
    while (core::isOk(fsw.events().read(&events, &e))) {
        stops += e.id == 212 ? 1U : 0U;
    }
    LONGS_EQUAL(1, stops);
}

TEST(GroundCommands, TableActivationThroughCommandsLandsAtTheNextFrameBoundary) {
    tables::RoverGeometryTable g = fsw.tables().roverGeometry();
    const float before = g.max_wheel_speed_rad_s;
    g.max_wheel_speed_rad_s = 3.0F;
    std::uint8_t image[tables::kMaxTableImageSize];
    const std::size_t n = tables::encodeTable(g, 7, image, sizeof image);
    uploadTable(image, n, 1);
    expectAccepted("TABLE_VALIDATE");
    send("TABLE_ACTIVATE", u16(1));
    runFrames(1);  // executed by the command task, after the table task ran in this frame
    expectAccepted("TABLE_ACTIVATE");
    DOUBLES_EQUAL(before, fsw.tables().roverGeometry().max_wheel_speed_rad_s, 0.0);
    runFrames(1);  // the table task applies it first thing in the next frame
    DOUBLES_EQUAL(3.0, fsw.tables().roverGeometry().max_wheel_speed_rad_s, 0.0);
    LONGS_EQUAL(7, fsw.tables().status(tables::TableId::kRoverGeometry).activeVersion);
    // The CAN I/O task now refuses wheel commands beyond the new limit.
    msg::WheelCommandMsg fast{};
    fast.velocityRadS[0] = 4.0;
    CHECK(core::isOk(fsw.bus().publish(fast)));
    const std::uint32_t refusedBefore = fsw.canIo().commandsRejected();
    runFrames(1);
    LONGS_EQUAL(refusedBefore + 1, fsw.canIo().commandsRejected());
}

TEST(GroundCommands, BadTableImageIsRejectedWithTheReasonAndTheActiveTableStays) {
    tables::RoverGeometryTable g = fsw.tables().roverGeometry();
    const float before = g.max_wheel_speed_rad_s;
    g.max_wheel_speed_rad_s = 3.0F;
    std::uint8_t image[tables::kMaxTableImageSize];
    const std::size_t n = tables::encodeTable(g, 8, image, sizeof image);
    image[n - 1] ^= 0x40;  // one flipped bit in the payload
    uploadTable(image, n, 1);
    const Packet& ack = last("CMD_ACK");
    STRCMP_EQUAL("execution_failed", toString(static_cast<CommandReject>(field(ack, "reason"))));
    LONGS_EQUAL(static_cast<long>(tables::TableReject::kBadCrc), static_cast<long>(field(ack, "detail")));
    LONGS_EQUAL(static_cast<long>(tables::TableReject::kBadCrc),
                static_cast<long>(field(last("TABLE_STATUS"), "last_reject")));
    send("TABLE_ACTIVATE", u16(1));
    runFrames(3);
    STRCMP_EQUAL("execution_failed", toString(static_cast<CommandReject>(field(last("CMD_ACK"), "reason"))));
    DOUBLES_EQUAL(before, fsw.tables().roverGeometry().max_wheel_speed_rad_s, 0.0);
}

TEST(GroundCommands, TableDumpSendsTheActiveImage) {
    send("TABLE_DUMP", {0, 5, 0});  // CAN node map, active buffer
    runFrames(1);
    expectAccepted("TABLE_DUMP");
    std::vector<std::uint8_t> image;
    for (const Packet& p : received) {
        if (p.apid == findTelemetry("TABLE_DUMP")->apid) {
            LONGS_EQUAL(image.size(), static_cast<long>(field(p, "offset")));
            const auto length = static_cast<std::size_t>(field(p, "length"));
            image.insert(image.end(), p.payload.begin() + 9, p.payload.begin() + 9 + static_cast<long>(length));
        }
    }
    std::uint8_t expected[tables::kMaxTableImageSize];
    const std::size_t n = tables::encodeTable(fsw.tables().canNodeMap(), fsw.tables().status(tables::TableId::kCanNodeMap).activeVersion,
                                              expected, sizeof expected);
    LONGS_EQUAL(n, image.size());
    CHECK(std::memcmp(expected, image.data(), n) == 0);
}

TEST(GroundCommands, NoHeapUseWithCommandsAndTelemetryFlowing) {
    runFrames(5);
    received.clear();
    received.reserve(20000);
    test::AllocationWatch watch;
    for (int i = 0; i < 300; ++i) {
        CommandFields f;
        f.apid = 0x180;
        f.functionCode = 2;  // REQUEST_HK
        f.keyId = kLabKeyId;
        f.authSequence = authSequence++;
        std::uint8_t bytes[kMaxCommandPacket];
        const std::size_t n = encodeCommandPacket(f, nullptr, 0, kLabKey, hmac, bytes, sizeof bytes);
        (void)link.groundSend(bytes, n);
        fsw.run(nullptr, 1);
        std::uint8_t out[hal::kMemoryLinkMaxPacket];
        std::size_t length = 0;
        while (core::isOk(link.groundReceive(out, sizeof out, &length))) {
        }
    }
    LONGS_EQUAL(0, watch.count());
    LONGS_EQUAL(300, fsw.commands().counters().accepted);
}

TEST(GroundCommands, MalformedBusMessagesAreCountedNotSilentlyDropped) {
    const std::uint8_t garbage[3] = {1, 2, 3};  // the wrong size for every message type
    const std::uint32_t refusedBefore = fsw.canIo().malformed();
    CHECK(core::isOk(fsw.bus().publish(msg::ids::kMode, garbage, sizeof garbage)));
    CHECK(core::isOk(fsw.bus().publish(msg::ids::kManualDrive, garbage, sizeof garbage)));
    runFrames(1);
    LONGS_EQUAL(refusedBefore + 1, fsw.canIo().malformed());  // e-stop state unchanged
    CHECK_FALSE(fsw.canIo().estopHeld());
    LONGS_EQUAL(1, fsw.telemetry().malformed());
    LONGS_EQUAL(2, fsw.manualDrive().malformed());  // both ids reach the manual-drive pipe
}

// No CAN devices here: no position fix ever comes, so the estimate stays
// uninitialised and the health monitor raises pose-uncertain once the first-fix
// wait (3 s) is over; HEALTH goes down when it changes and at 1 Hz. The six
// drives never boot either: past CAN_NODE_MAP.drive_boot_timeout_ms (3 s) they
// are reported lost, so their heartbeat faults are raised too. No device
// ever sends data either, so each one's sensor-stale fault (36..39) comes up
// after its own stale time (0.2 to 3 s, ESTIMATOR_NOISE).
TEST(GroundCommands, ExecSetTaskDisablesARowWhichFaultProtectionThenRestarts) {
    const std::size_t row = rowOf("habitual");
    runFrames(50);
    send("EXEC_SET_TASK", {static_cast<std::uint8_t>(row), 0});
    runFrames(1);
    expectAccepted("EXEC_SET_TASK");
    CHECK_FALSE(fsw.executive().taskLiveness(row)->enabled);
    LONGS_EQUAL(1, eventCount(224));
    LONGS_EQUAL(1, fsw.executiveCommands().taskCommands());
    const std::uint32_t runsWhenDisabled = fsw.executive().taskStats(row)->runs;
    runFrames(20);  // two of its periods: it has not run
    LONGS_EQUAL(runsWhenDisabled, fsw.executive().taskStats(row)->runs);
    runFrames(200);
    LONGS_EQUAL(1, eventCount(732));  // task stalled, raised once
    CHECK(fsw.executiveCommands().taskRestarts() >= 1);
    CHECK(fsw.executive().taskLiveness(row)->enabled);
    CHECK(fsw.executive().taskStats(row)->runs > runsWhenDisabled + 10);
    // Enabling a row that runs is accepted and changes nothing.
    send("EXEC_SET_TASK", {static_cast<std::uint8_t>(row), 1});
    runFrames(1);
    expectAccepted("EXEC_SET_TASK");
    CHECK(fsw.executive().taskLiveness(row)->enabled);
    LONGS_EQUAL(2, fsw.executiveCommands().taskCommands());
    LONGS_EQUAL(0, fsw.executiveCommands().taskCommandsRefused());
}

// A row the table does not have: the dictionary's range (0..31) lets row 16
// through, the executive's 16-row table does not (execution_failed, detail 1:
// no such row); row 32 is outside the dictionary's range (argument_out_of_range,
// detail 0: the first argument). Each is counted by reason in HK and evented.
TEST(GroundCommands, ExecSetTaskOnARowBeyondTheTableIsRefusedWithItsReason) {
    LONGS_EQUAL(16, fsw.executive().taskCount());
    runFrames(50);  // the start-up events downlinked (8 a frame)
    send("EXEC_SET_TASK", {16, 0});
    runFrames(1);
    const Packet& ack = last("CMD_ACK");
    LONGS_EQUAL(14, static_cast<long>(field(ack, "reason")));
    LONGS_EQUAL(1, static_cast<long>(field(ack, "detail")));
    LONGS_EQUAL(1, eventCount(225));
    LONGS_EQUAL(1, fsw.executiveCommands().taskCommandsRefused());
    CHECK(cmdtlm::TaskCommandRefusal::kNoSuchRow == fsw.executiveCommands().lastTaskRefusal());
    send("EXEC_SET_TASK", {32, 0});
    runFrames(1);
    LONGS_EQUAL(12, static_cast<long>(field(last("CMD_ACK"), "reason")));
    LONGS_EQUAL(0, static_cast<long>(field(last("CMD_ACK"), "detail")));
    send("EXEC_SET_TASK", {3, 2});  // enabled is 0 or 1
    runFrames(1);
    LONGS_EQUAL(12, static_cast<long>(field(last("CMD_ACK"), "reason")));
    LONGS_EQUAL(1, static_cast<long>(field(last("CMD_ACK"), "detail")));
    send("REQUEST_HK");
    runFrames(1);
    LONGS_EQUAL(1, static_cast<long>(field(last("HK"), "cmd_rejected_by_reason", 14)));
    LONGS_EQUAL(2, static_cast<long>(field(last("HK"), "cmd_rejected_by_reason", 12)));
    LONGS_EQUAL(0, fsw.executiveCommands().taskCommands());
    for (std::size_t i = 0; i < fsw.executive().taskCount(); ++i) {
        CHECK(fsw.executive().taskLiveness(i)->enabled);
    }
}

// The rows whose loss could not be undone are never disabled by ground: the
// command ingest (nothing could enable it again; it also carries out fault
// protection's restarts), CAN I/O (the CAN ground link and every drive
// command), health (its own stall would go unseen) and fault protection (the
// one that restarts rows). Each refusal names its reason; enabling them is
// harmless and accepted.
TEST(GroundCommands, ExecSetTaskRefusesToDisableTheRowsWhoseLossCouldNotBeUndone) {
    const struct {
        const char* name;
        cmdtlm::TaskCommandRefusal why;
    } essential[] = {{"commands", cmdtlm::TaskCommandRefusal::kCommandIngest},
                     {"can_io", cmdtlm::TaskCommandRefusal::kCanIo},
                     {"health", cmdtlm::TaskCommandRefusal::kFaultDetection},
                     {"fault_prot", cmdtlm::TaskCommandRefusal::kFaultResponse}};
    unsigned refused = 0;
    runFrames(50);  // the start-up events downlinked (8 a frame)
    for (const auto& e : essential) {
        const std::size_t row = rowOf(e.name);
        const std::uint32_t runs = fsw.executive().taskStats(row)->runs;
        send("EXEC_SET_TASK", {static_cast<std::uint8_t>(row), 0});
        runFrames(2);
        const Packet& ack = last("CMD_ACK");
        LONGS_EQUAL(14, static_cast<long>(field(ack, "reason")));
        LONGS_EQUAL(static_cast<long>(e.why), static_cast<long>(field(ack, "detail")));
        CHECK_TEXT(fsw.executive().taskLiveness(row)->enabled, e.name);
        CHECK_TEXT(fsw.executive().taskStats(row)->runs >= runs + 2, e.name);
        CHECK(e.why == fsw.executiveCommands().lastTaskRefusal());
        LONGS_EQUAL(++refused, fsw.executiveCommands().taskCommandsRefused());
        LONGS_EQUAL(refused, eventCount(225));
        send("EXEC_SET_TASK", {static_cast<std::uint8_t>(row), 1});
        runFrames(1);
        expectAccepted("EXEC_SET_TASK");
    }
    // Every other row may be disabled (and is restarted by fault protection).
    for (std::size_t row = 0; row < fsw.executive().taskCount(); ++row) {
        bool isEssential = false;
        for (const auto& e : essential) {
            isEssential = isEssential || row == rowOf(e.name);
        }
        if (!isEssential) {
            send("EXEC_SET_TASK", {static_cast<std::uint8_t>(row), 0});
            runFrames(1);
            expectAccepted("EXEC_SET_TASK");
            send("EXEC_SET_TASK", {static_cast<std::uint8_t>(row), 1});
            runFrames(1);
        }
    }
    LONGS_EQUAL(refused, fsw.executiveCommands().taskCommandsRefused());
}

// Issue 14 item 1: commands captured on the link (SET_MODE MANUAL, DRIVE) must
// not move the wheels again after rse-fsw restarts. Each boot is a new FswApp
// over the same anti-replay store, as a restart of the process is.
namespace {

struct Rover {
    core::VirtualClock clock;
    hal::MemoryCanBus can{clock};
    hal::MemoryPacketLink link;
    app::FswApp fsw{clock, *can.attach("fsw")};
    std::vector<Packet> received;

    Rover(hal::RecordStore* store, bool provision, std::uint64_t nonce) {
        CHECK(core::isOk(fsw.addGroundLink(&link)));
        fsw.attachAuthStore(store, provision);
        fsw.setAuthChallengeSeed(nonce);
        CHECK(core::isOk(fsw.useLabKey()));
        CHECK(core::isOk(fsw.init(nullptr)));
    }
    void runFrames(int n) { runAndCollect(fsw, link, n, &received); }
    const Packet& last(const char* name) { return lastOf(received, name); }
    void send(const std::vector<std::uint8_t>& p) { CHECK(core::isOk(link.groundSend(p.data(), p.size()))); }
};

}  // namespace

TEST_GROUP(GroundCommandsAcrossRestart) {
    hal::MemoryRecordStore store;
    HmacSha256 hmac;
    void setup() override { CHECK(core::isOk(hmac.init())); }

    std::vector<std::uint8_t> packet(const char* name, const std::vector<std::uint8_t>& args, std::uint32_t seq) {
        const CommandDesc* c = findCommand(name);
        CHECK(c != nullptr);
        CommandFields f;
        f.apid = c->apid;
        f.functionCode = c->functionCode;
        f.keyId = kLabKeyId;
        f.authSequence = seq;
        std::vector<std::uint8_t> bytes(kMaxCommandPacket);
        const std::size_t n = encodeCommandPacket(f, args.data(), args.size(), kLabKey, hmac, bytes.data(), bytes.size());
        CHECK(n > 0);
        bytes.resize(n);
        return bytes;
    }
    static std::vector<std::uint8_t> driveArgs() {
        std::vector<std::uint8_t> a(12);
        core::BeWriter w(a.data(), a.size());
        w.f32(0.2F);
        w.f32(0.0F);
        w.f32(3.0F);
        return a;
    }
};

TEST(GroundCommandsAcrossRestart, CapturedManualDriveCommandsAreRefusedAfterARestart) {
    const auto manual = packet("SET_MODE", {3}, 1);
    const auto drive = packet("DRIVE", driveArgs(), 2);
    {
        auto first = std::make_unique<Rover>(&store, true, 42);
        first->send(manual);
        first->runFrames(2);
        first->send(drive);
        first->runFrames(2);
        LONGS_EQUAL(0, static_cast<long>(field(first->last("CMD_ACK"), "reason")));
        first->runFrames(100);
        LONGS_EQUAL(3, static_cast<long>(field(first->last("HK"), "mode")));
    }
    auto second = std::make_unique<Rover>(&store, false, 43);
    second->send(manual);
    second->runFrames(2);
    CHECK(field(second->last("CMD_ACK"), "reason") != 0);
    second->send(drive);
    second->runFrames(100);
    CHECK(field(second->last("CMD_ACK"), "reason") != 0);
    const Packet& hk = second->last("HK");
    LONGS_EQUAL(0, static_cast<long>(field(hk, "mode")));  // still SAFE: the wheels did not move
    LONGS_EQUAL(0, static_cast<long>(field(hk, "cmd_accepted")));
    LONGS_EQUAL(1, static_cast<long>(field(hk, "auth_store_state")));
    LONGS_EQUAL(43, static_cast<long>(field(hk, "auth_challenge_low")));
}

TEST(GroundCommandsAcrossRestart, ALostStoreIsRecoveredWithTheNonceFromHousekeeping) {
    auto rover = std::make_unique<Rover>(&store, false, 0x0000000700000009ULL);
    rover->runFrames(100);
    const Packet& hk = rover->last("HK");
    LONGS_EQUAL(2, static_cast<long>(field(hk, "auth_store_state")));  // missing
    LONGS_EQUAL(1, static_cast<long>(field(hk, "auth_keys_unsynced")));
    const auto high = static_cast<std::uint32_t>(field(hk, "auth_challenge_high"));
    const auto low = static_cast<std::uint32_t>(field(hk, "auth_challenge_low"));
    rover->send(packet("SET_MODE", {1}, 500));
    rover->runFrames(2);
    LONGS_EQUAL(static_cast<long>(CommandReject::kSequenceUnsynchronised),
                static_cast<long>(field(rover->last("CMD_ACK"), "reason")));
    std::vector<std::uint8_t> args(8);
    core::BeWriter w(args.data(), args.size());
    w.u32(high);
    w.u32(low);
    rover->send(packet("AUTH_RESYNC", args, 1000));
    rover->runFrames(2);
    LONGS_EQUAL(0, static_cast<long>(field(rover->last("CMD_ACK"), "reason")));
    rover->send(packet("SET_MODE", {1}, 1001));
    rover->runFrames(100);
    LONGS_EQUAL(0, static_cast<long>(field(rover->last("CMD_ACK"), "reason")));
    const Packet& after = rover->last("HK");
    LONGS_EQUAL(1, static_cast<long>(field(after, "mode")));
    LONGS_EQUAL(1, static_cast<long>(field(after, "auth_store_state")));
    LONGS_EQUAL(0, static_cast<long>(field(after, "auth_keys_unsynced")));
    LONGS_EQUAL(10, static_cast<long>(field(after, "auth_challenge_low")));  // moved on after use
}

// Issue 14 item 4: HK.lab_key_in_use follows the key store: 1 while the public
// lab key's bytes are loaded, under whatever key id.
TEST(GroundCommands, HousekeepingSaysWhenThePublicLabKeyIsInUse) {
    runFrames(1);
    LONGS_EQUAL(1, static_cast<long>(field(last("HK"), "lab_key_in_use")));
    std::uint8_t own[kKeySize];
    for (std::size_t i = 0; i < kKeySize; ++i) {
        own[i] = static_cast<std::uint8_t>(i * 37 + 11);
    }
    fsw.keys().clear();
    CHECK(core::isOk(fsw.keys().add(5, own)));
    runFrames(100);  // the next 1 Hz HK
    LONGS_EQUAL(0, static_cast<long>(field(last("HK"), "lab_key_in_use")));
    CHECK(core::isOk(fsw.keys().add(9, kLabKey)));  // the lab key's bytes under another id
    runFrames(100);
    LONGS_EQUAL(1, static_cast<long>(field(last("HK"), "lab_key_in_use")));
}

// Issue 14 item 4: a sender without a key must not learn which key ids exist.
// An unknown key id and a bad MAC give the same CMD_ACK (reason bad_mac, same
// detail) and the same event (529); only HK's per-reason counters tell them apart.
TEST(GroundCommands, AnUnknownKeyIdAndABadMacLookTheSameOnTheLink) {
    runFrames(50);  // the start-up events downlinked
    const auto sendSigned = [this](std::uint16_t keyId, const std::uint8_t* key) {
        const CommandDesc* c = findCommand("NOOP");
        CommandFields f;
        f.apid = c->apid;
        f.functionCode = c->functionCode;
        f.keyId = keyId;
        f.authSequence = authSequence++;
        std::uint8_t bytes[kMaxCommandPacket];
        const std::size_t n = encodeCommandPacket(f, nullptr, 0, key, hmac, bytes, sizeof bytes);
        CHECK(n > 0);
        CHECK(core::isOk(link.groundSend(bytes, n)));
    };
    std::uint8_t wrongKey[kKeySize];
    std::memcpy(wrongKey, kLabKey, kKeySize);
    wrongKey[5] ^= 0x40;

    sendSigned(9, kLabKey);  // key id 9 is not loaded
    runFrames(2);
    const Packet unknownKey = last("CMD_ACK");
    sendSigned(kLabKeyId, wrongKey);  // key id 1 is, but the MAC is wrong
    runFrames(2);
    const Packet badMac = last("CMD_ACK");

    LONGS_EQUAL(9, static_cast<long>(field(unknownKey, "key_id")));
    LONGS_EQUAL(static_cast<long>(CommandReject::kBadMac), static_cast<long>(field(unknownKey, "reason")));
    LONGS_EQUAL(static_cast<long>(CommandReject::kBadMac), static_cast<long>(field(badMac, "reason")));
    LONGS_EQUAL(static_cast<long>(field(badMac, "detail")), static_cast<long>(field(unknownKey, "detail")));
    LONGS_EQUAL(0, eventCount(528));  // no "unknown_key" event on the link
    LONGS_EQUAL(2, eventCount(529));

    send("REQUEST_HK");
    runFrames(2);
    const Packet& hk = last("HK");
    LONGS_EQUAL(1, static_cast<long>(field(hk, "cmd_rejected_by_reason", 8)));  // unknown_key
    LONGS_EQUAL(1, static_cast<long>(field(hk, "cmd_rejected_by_reason", 9)));  // bad_mac
}

// A flood of garbage through the whole application (docs/icd.md, "Floods"): every
// packet counted in HK, rejection acknowledgements rate-limited and the rest
// counted, and a valid command still accepted in the middle of it.
TEST(GroundCommands, AGarbageFloodIsCountedInHousekeepingAndItsAcknowledgementsRateLimited) {
    const std::uint8_t junk[10] = {0xde, 0xad, 0xbe, 0xef, 0, 1, 2, 3, 4, 5};
    constexpr int kFrames = 20;
    constexpr int kPerFrame = 30;  // the in-memory uplink holds 32
    for (int f = 0; f < kFrames; ++f) {
        for (int i = 0; i < kPerFrame; ++i) {
            CHECK(core::isOk(link.groundSend(junk, sizeof junk)));
        }
        if (f == kFrames / 2) {
            send("NOOP");
        }
        runFrames(1);
        if (f == kFrames / 2) {
            expectAccepted("NOOP");
        }
    }
    send("REQUEST_HK");
    runFrames(2);
    const Packet& hk = last("HK");
    const long garbage = kFrames * kPerFrame;
    LONGS_EQUAL(garbage + 2, static_cast<long>(field(hk, "link_rx_packets")));
    LONGS_EQUAL(0, static_cast<long>(field(hk, "link_rx_dropped")));
    LONGS_EQUAL(0, static_cast<long>(field(hk, "link_rx_kernel_drops")));
    LONGS_EQUAL(garbage, static_cast<long>(field(hk, "cmd_rejected_by_reason", 2)));  // bad_length
    LONGS_EQUAL(0, static_cast<long>(field(hk, "cmd_ingest_limited")));
    const long suppressed = static_cast<long>(field(hk, "cmd_acks_suppressed"));
    long rejectionAcks = 0;
    for (const Packet& p : received) {
        rejectionAcks += p.apid == findTelemetry("CMD_ACK")->apid && field(p, "reason") != 0 ? 1 : 0;
    }
    LONGS_EQUAL(garbage, rejectionAcks + suppressed);
    // 20 at once, then 20 a second: 0.2 s of flood adds about 4.
    CHECK(rejectionAcks >= static_cast<long>(cmdtlm::kRejectAckBurst));
    CHECK(rejectionAcks <= static_cast<long>(cmdtlm::kRejectAckBurst) + 4);
}

// rse-fsw --time-scale N (lab only): the start-up event says so and every HK
// carries N; without it HK.time_scale is 1 and nothing is evented.
TEST_GROUP(GroundCommandsTimeScale){};

TEST(GroundCommandsTimeScale, HousekeepingAndAnEventSayTheTimelineIsSlowed) {
    for (const std::uint8_t factor : {std::uint8_t{1}, std::uint8_t{5}}) {
        core::VirtualClock clock;
        hal::MemoryCanBus can{clock};
        hal::MemoryPacketLink link;
        auto fsw = std::make_unique<app::FswApp>(clock, *can.attach("fsw"));
        CHECK(core::isOk(fsw->addGroundLink(&link)));
        CHECK(core::isOk(fsw->useLabKey()));
        fsw->setTimeScale(factor);
        CHECK(core::isOk(fsw->init(nullptr)));
        bool evented = false;
        core::Event e;
        core::EventLog::Cursor cursor{};
        while (core::isOk(fsw->events().read(&cursor, &e))) {
            if (e.id == app::events::kTimeScaled) {
                evented = true;
                STRCMP_EQUAL("app: time scale 5: mission time runs 5 times slower than real time (lab only, never flight)",
                             e.text);
                LONGS_EQUAL(static_cast<long>(core::Severity::kWarning), static_cast<long>(e.severity));
            }
        }
        CHECK_EQUAL(factor > 1, evented);
        std::vector<Packet> received;
        runAndCollect(*fsw, link, 1, &received);
        LONGS_EQUAL(factor, static_cast<long>(field(lastOf(received, "HK"), "time_scale")));
    }
}

// A burst of events larger than the link can take at once waits in the event
// log and goes down in order as the link drains: not one event refused.

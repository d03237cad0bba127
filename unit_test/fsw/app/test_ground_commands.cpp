// The whole flight application commanded from a ground station over an
// in-memory link: commands in as CCSDS packets, acknowledgements and telemetry
// out, decoded with the dictionary's descriptors (so this also checks that the
// flight's telemetry matches the dictionary the ground reads).
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "fsw/app/app_events.hpp"
#include "fsw/app/fsw_app.hpp"
#include "fsw/cmdtlm/command_packet.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/tables/table_image.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/link/memory_packet_link.hpp"
#include "hal/nvm/record_store.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::cmdtlm;

namespace {

struct Packet {
    std::uint16_t apid = 0;
    std::vector<std::uint8_t> payload;
};

// Value of one field (element) of a telemetry payload, found by name in the dictionary.
double field(const Packet& p, const char* name, std::size_t element = 0) {
    const TelemetryDesc* t = findTelemetry(p.apid);
    CHECK(t != nullptr);
    core::BeReader r(p.payload.data(), p.payload.size());
    for (std::size_t i = 0; i < t->fieldCount; ++i) {
        const FieldDesc& f = t->fields[i];
        for (std::size_t e = 0; e < f.count; ++e) {
            const double v = readAsDouble(r, f.type);
            if (std::strcmp(f.name, name) == 0 && e == element) {
                return v;
            }
        }
    }
    FAIL(name);
    return 0.0;
}

// Takes what the flight software sent down the link so far (each packet
// checked against its dictionary size).
void collectDownlink(hal::MemoryPacketLink& link, std::vector<Packet>* received) {
    std::uint8_t bytes[hal::kMemoryLinkMaxPacket];
    std::size_t length = 0;
    while (core::isOk(link.groundReceive(bytes, sizeof bytes, &length))) {
        const PrimaryHeader h = decodePrimaryHeader(bytes);
        LONGS_EQUAL(length, h.dataLength + 7u);
        Packet p;
        p.apid = h.apid;
        p.payload.assign(bytes + kTelemetryHeaderSize, bytes + length);
        const TelemetryDesc* t = findTelemetry(h.apid);
        CHECK(t != nullptr);
        LONGS_EQUAL(t->payloadSize, p.payload.size());
        received->push_back(p);
    }
}

// Runs the flight software n frames, collecting what it sends down the link.
void runAndCollect(app::FswApp& fsw, hal::MemoryPacketLink& link, int n, std::vector<Packet>* received) {
    for (int i = 0; i < n; ++i) {
        fsw.run(nullptr, 1);
        collectDownlink(link, received);
    }
}

// The last packet of a kind received so far (fails if none).
const Packet& lastOf(const std::vector<Packet>& received, const char* name) {
    const TelemetryDesc* t = findTelemetry(name);
    for (auto it = received.rbegin(); it != received.rend(); ++it) {
        if (it->apid == t->apid) {
            return *it;
        }
    }
    FAIL(name);
    return received.front();
}

}  // namespace

TEST_GROUP(GroundCommands) {
    core::VirtualClock clock;
    hal::MemoryCanBus can{clock};
    hal::MemoryPacketLink link;
    app::FswApp fsw{clock, *can.attach("fsw")};
    HmacSha256 hmac;
    std::uint32_t authSequence = 1;
    std::vector<Packet> received;
    core::PipeId probe = 0;

    void setup() override {
        CHECK(core::isOk(fsw.addGroundLink(&link)));
        CHECK(core::isOk(fsw.useLabKey()));  // a lab bench: asked for explicitly
        CHECK(core::isOk(fsw.init(nullptr)));
        CHECK(core::isOk(hmac.init()));
        CHECK(core::isOk(fsw.bus().createPipe("probe", 16, &probe)));
        CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kWheelCommand)));
    }

    void send(const char* name, const std::vector<std::uint8_t>& args = {}) {
        const CommandDesc* c = findCommand(name);
        CHECK(c != nullptr);
        CommandFields f;
        f.apid = c->apid;
        f.functionCode = c->functionCode;
        f.keyId = kLabKeyId;
        f.authSequence = authSequence++;
        std::uint8_t bytes[kMaxCommandPacket];
        const std::size_t n = encodeCommandPacket(f, args.data(), args.size(), kLabKey, hmac, bytes, sizeof bytes);
        CHECK(n > 0);
        CHECK(core::isOk(link.groundSend(bytes, n)));
    }
    void runFrames(int n) { runAndCollect(fsw, link, n, &received); }
    const Packet& last(const char* name) { return lastOf(received, name); }
    std::size_t countOf(const char* name) {
        std::size_t n = 0;
        for (const Packet& p : received) {
            n += p.apid == findTelemetry(name)->apid ? 1 : 0;
        }
        return n;
    }
    void expectAccepted(const char* name) {
        const Packet& ack = last("CMD_ACK");
        LONGS_EQUAL(findCommand(name)->apid, static_cast<long>(field(ack, "apid")));
        LONGS_EQUAL(0, static_cast<long>(field(ack, "reason")));
    }
    // EVENT packets received with this id.
    long eventCount(std::uint16_t id) {
        long n = 0;
        for (const Packet& p : received) {
            n += p.apid == findTelemetry("EVENT")->apid && static_cast<std::uint16_t>(field(p, "event_id")) == id ? 1 : 0;
        }
        return n;
    }
    // The rate-group row of a task, by the name TASK_TIMING gives it.
    std::size_t rowOf(const char* name) {
        const std::size_t row = fsw.executive().findTask(name);
        CHECK_TEXT(row < fsw.executive().taskCount(), name);
        return row;
    }
    std::vector<std::uint8_t> u16(std::uint16_t v) { return {static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v)}; }
    std::vector<std::uint8_t> f32s(std::initializer_list<float> values) {
        std::vector<std::uint8_t> out(values.size() * 4);
        core::BeWriter w(out.data(), out.size());
        for (float v : values) {
            w.f32(v);
        }
        return out;
    }
    // TABLE_LOAD in chunks of at most 40 bytes, then TABLE_VALIDATE.
    void uploadTable(const std::uint8_t* image, std::size_t length, std::uint16_t id) {
        for (std::size_t offset = 0; offset < length; offset += 40) {
            std::vector<std::uint8_t> args = u16(id);
            const std::vector<std::uint8_t> off = u16(static_cast<std::uint16_t>(offset));
            args.insert(args.end(), off.begin(), off.end());
            args.insert(args.end(), image + offset, image + std::min(length, offset + 40));
            send("TABLE_LOAD", args);
            runFrames(1);
            expectAccepted("TABLE_LOAD");
        }
        send("TABLE_VALIDATE", u16(id));
        runFrames(1);
    }
};

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

TEST(GroundCommands, GoalsAndRiskBoundShowInThePlanPacket) {
    send("SET_MODE", {1});
    std::vector<std::uint8_t> args(24);
    core::BeWriter w(args.data(), args.size());
    w.f64(12.5);
    w.f64(-3.0);
    w.f64(1e-6);
    send("GOTO", args);
    runFrames(3);
    expectAccepted("GOTO");
    const Packet& plan = last("PLAN");
    LONGS_EQUAL(1, static_cast<long>(field(plan, "goal_count")));
    DOUBLES_EQUAL(12.5, field(plan, "goal_x"), 1e-6);
    DOUBLES_EQUAL(-3.0, field(plan, "goal_y"), 1e-6);
    DOUBLES_EQUAL(1e-6, field(plan, "risk_bound"), 1e-15);
    // STANDBY: the deliberative layer (10 Hz) takes the goal and waits for
    // AUTONOMOUS; PLAN is sent again when its state changes. No legs yet.
    runFrames(10);
    const Packet& waiting = last("PLAN");
    LONGS_EQUAL(1, static_cast<long>(field(waiting, "status")));
    LONGS_EQUAL(1, static_cast<long>(field(waiting, "goal_count")));
    LONGS_EQUAL(0, static_cast<long>(field(waiting, "waypoint_count")));
}

// PLAN_PATH: the telemetry task sends one packet per PlanPathMsg it takes off
// the bus (an on-event packet, never repeated), its fields decoded by the
// dictionary's descriptors carrying the message's values; no heap on the way.
// A message with more steps than means is malformed: counted, not sent.
TEST(GroundCommands, APlanPathOnTheBusGoesDownAsOnePlanPathPacket) {
    runFrames(3);
    received.clear();
    msg::PlanPathMsg m{};
    m.timeNs = 12 * core::kNsPerSec + 250 * core::kNsPerMs;
    m.planNumber = 7;
    m.status = 1;
    m.steps = 3;
    m.riskBound = 1e-3;
    m.riskUsed = 7.5e-4;
    m.lengthM = 20.25;
    m.processSigmaM = 0.0625;
    m.startCov[0] = 0.04;
    m.startCov[1] = 0.005;
    m.startCov[2] = 0.005;
    m.startCov[3] = 0.09;
    m.goalX = 20.0;
    m.goalY = -1.5;
    const double xs[4] = {0.5, 7.0, 13.5, 20.0};
    const double ys[4] = {0.0, 1.25, -0.75, -1.5};
    for (std::size_t t = 0; t < 4; ++t) {
        m.meanX[t] = xs[t];
        m.meanY[t] = ys[t];
    }
    std::size_t downlinked = 0;
    {
        test::AllocationWatch watch;
        CHECK(core::isOk(fsw.bus().publish(m)));
        fsw.run(nullptr, 1);
        LONGS_EQUAL(0, watch.count());
        std::uint8_t bytes[hal::kMemoryLinkMaxPacket];
        std::size_t length = 0;
        while (core::isOk(link.groundReceive(bytes, sizeof bytes, &length))) {
            const PrimaryHeader h = decodePrimaryHeader(bytes);
            downlinked += h.apid == findTelemetry("PLAN_PATH")->apid ? 1U : 0U;
            if (h.apid == findTelemetry("PLAN_PATH")->apid) {
                LONGS_EQUAL(findTelemetry("PLAN_PATH")->payloadSize, length - kTelemetryHeaderSize);
                Packet p;
                p.apid = h.apid;
                received.push_back(p);  // after the watch's count: the test's own heap
                received.back().payload.assign(bytes + kTelemetryHeaderSize, bytes + length);
            }
        }
    }
    LONGS_EQUAL(1, downlinked);
    LONGS_EQUAL(0x017, findTelemetry("PLAN_PATH")->apid);
    const Packet& path = last("PLAN_PATH");
    LONGS_EQUAL(7, static_cast<long>(field(path, "plan_number")));
    DOUBLES_EQUAL(12.25, field(path, "plan_time"), 1e-12);
    LONGS_EQUAL(1, static_cast<long>(field(path, "status")));
    LONGS_EQUAL(3, static_cast<long>(field(path, "steps")));
    DOUBLES_EQUAL(1e-3, field(path, "risk_bound"), 0.0);
    DOUBLES_EQUAL(7.5e-4, field(path, "risk_used"), 0.0);
    DOUBLES_EQUAL(20.25, field(path, "length"), 0.0);
    DOUBLES_EQUAL(0.0625, field(path, "process_sigma"), 0.0);
    DOUBLES_EQUAL(0.04, field(path, "start_cov", 0), 1e-8);
    DOUBLES_EQUAL(0.005, field(path, "start_cov", 1), 1e-9);
    DOUBLES_EQUAL(0.005, field(path, "start_cov", 2), 1e-9);
    DOUBLES_EQUAL(0.09, field(path, "start_cov", 3), 1e-8);
    DOUBLES_EQUAL(20.0, field(path, "goal_x"), 0.0);
    DOUBLES_EQUAL(-1.5, field(path, "goal_y"), 0.0);
    for (std::size_t t = 0; t < 4; ++t) {
        DOUBLES_EQUAL(xs[t], field(path, "mean_x", t), 0.0);
        DOUBLES_EQUAL(ys[t], field(path, "mean_y", t), 0.0);
    }
    for (std::size_t t = 4; t < msg::kPlanPathMeans; ++t) {
        DOUBLES_EQUAL(0.0, field(path, "mean_x", t), 0.0);
        DOUBLES_EQUAL(0.0, field(path, "mean_y", t), 0.0);
    }
    LONGS_EQUAL(1, fsw.planTelemetry().planPathsSent());

    // Not repeated: nothing new on the bus, no packet.
    runFrames(120);
    LONGS_EQUAL(1, countOf("PLAN_PATH"));

    // More steps than the message has means: malformed, counted, not sent.
    const std::uint32_t malformed = fsw.telemetry().malformed();
    m.steps = static_cast<std::uint8_t>(msg::kPlanPathMeans);
    CHECK(core::isOk(fsw.bus().publish(m)));
    runFrames(1);
    LONGS_EQUAL(malformed + 1, fsw.telemetry().malformed());
    LONGS_EQUAL(1, countOf("PLAN_PATH"));
    LONGS_EQUAL(1, fsw.planTelemetry().planPathsSent());
}

// PLAN_EXTEND: refused by mode in SAFE; in STANDBY passed to the plan
// executive as a PlanCommandMsg (the extra time in ms, the name's bytes),
// which refuses it with no plan running: event 976, PLAN_EXEC's counters.
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
TEST(GroundCommands, RoverStateAndHealthReportTheEstimatorAndFaults) {
    const std::uint64_t staleBits = std::uint64_t{0xF} << msg::fault::kSensorStale;
    runFrames(250);
    const Packet& early = last("HEALTH");
    const auto earlyMask = static_cast<std::uint64_t>(field(early, "active_faults"));
    CHECK((earlyMask & ~staleBits) == 0);
    LONGS_EQUAL(0, static_cast<long>(field(last("ROVER_STATE"), "estimate_valid")));
    const std::size_t before = countOf("HEALTH");
    runFrames(100);  // past 3 s
    CHECK(countOf("HEALTH") >= before + 1);
    const Packet& health = last("HEALTH");
    std::uint64_t expected = (std::uint64_t{1} << msg::fault::kPoseUncertain) | staleBits;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        expected |= std::uint64_t{1} << (msg::fault::kDriveHeartbeatLost + w);
    }
    DOUBLES_EQUAL(static_cast<double>(expected), field(health, "active_faults"), 0.0);
    LONGS_EQUAL(msg::fault::kPoseUncertain, static_cast<long>(field(health, "last_fault_id")));
    LONGS_EQUAL(1, static_cast<long>(field(health, "last_fault_raised")));
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        LONGS_EQUAL(0, static_cast<long>(field(health, "drive_mode", w)));  // nominal
        DOUBLES_EQUAL(1.0, field(health, "power_factor", w), 1e-6);
    }
    DOUBLES_EQUAL(1000.0, field(last("ROVER_STATE"), "position_sigma"), 1e-3);
}

// EXEC_SET_TASK: ground disables a rate-group row; it stops running, the health
// monitor sees it stall and fault protection runs it again (FAULT_PROTECTION
// class 7, restart the task), as documented in docs/fault_protection.md.
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
TEST(GroundCommands, AnEventBurstBeyondTheLinksRoomWaitsInTheEventLogAndArrivesWhole) {
    runFrames(2);
    received.clear();
    constexpr int kBurst = 3 * static_cast<int>(hal::kMemoryLinkDownlinkDepth);
    static_assert(kBurst < static_cast<int>(core::kEventRingDepth), "the burst fits the event log");
    for (int i = 0; i < kBurst; ++i) {
        fsw.events().report(999, core::Severity::kInfo, "burst %d", i);
    }
    fsw.run(nullptr, 10);  // the ground reads nothing for 10 frames: the downlink fills
    CHECK(link.downlinkQueued() > 0);
    runFrames(60);
    std::vector<long> sequences;
    int next = 0;
    for (const Packet& p : received) {
        if (p.apid != findTelemetry("EVENT")->apid) {
            continue;
        }
        sequences.push_back(static_cast<long>(field(p, "event_sequence")));
        if (static_cast<long>(field(p, "event_id")) == 999) {
            ++next;
        }
    }
    LONGS_EQUAL(kBurst, next);
    for (std::size_t i = 1; i < sequences.size(); ++i) {
        LONGS_EQUAL(sequences[i - 1] + 1, sequences[i]);  // no gap: nothing lost on the way
    }
    LONGS_EQUAL(0, fsw.events().lost());
    LONGS_EQUAL(0, fsw.telemetryOutput().dropped(hal::TxPriority::kEvent));
}

// POWER (1 Hz, minor frame 30): the power monitor's sample and every drive's
// motor temperature, from the frames the devices put on the CAN bus through
// CAN I/O's bus messages, each field equal to what PowerMsg and
// DriveStatusMsg carried. A drive that has not reported a temperature reads
// invalid (0). No heap on the way.
TEST(GroundCommands, PowerCarriesTheBatteryAndEveryMotorTemperatureFromTheBus) {
    hal::MemoryCanEndpoint* devices = can.attach("devices");
    CHECK(devices != nullptr);
    CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kPower)));
    runFrames(100);
    LONGS_EQUAL(1, countOf("POWER"));  // nothing heard yet: all zero, no temperature valid
    LONGS_EQUAL(0x018, findTelemetry("POWER")->apid);
    DOUBLES_EQUAL(0.0, field(last("POWER"), "battery_voltage"), 0.0);
    DOUBLES_EQUAL(0.0, field(last("POWER"), "power_sample_time"), 0.0);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        LONGS_EQUAL(0, static_cast<long>(field(last("POWER"), "temperature_valid", w)));
    }

    // The power monitor (0x6A1: mV, mA + discharge, 0.01 %, mA) and TPDO2 of
    // drive nodes 1..5 (0.1 degC); node 6 (RR) stays silent.
    hal::CanFrame power{};
    power.id = hal::device_ids::kPower;
    power.dlc = 8;
    const std::uint16_t millivolts = 27123;
    const auto charging = static_cast<std::uint16_t>(-1500);
    const std::uint16_t soc = 8765;
    const std::uint16_t solar = 2500;
    const std::uint16_t words[4] = {millivolts, charging, soc, solar};
    for (std::size_t i = 0; i < 4; ++i) {
        power.data[2 * i] = static_cast<std::uint8_t>(words[i]);
        power.data[2 * i + 1] = static_cast<std::uint8_t>(words[i] >> 8);
    }
    CHECK(core::isOk(devices->send(power)));
    const std::int16_t deciC[5] = {215, 350, -105, 812, 650};
    for (std::size_t node = 1; node <= 5; ++node) {
        hal::CanFrame tpdo2{};
        tpdo2.id = 0x280 + static_cast<std::uint32_t>(node);
        tpdo2.dlc = 2;
        tpdo2.data[0] = static_cast<std::uint8_t>(deciC[node - 1]);
        tpdo2.data[1] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(deciC[node - 1]) >> 8);
        CHECK(core::isOk(devices->send(tpdo2)));
    }
    // What CAN I/O published, as the telemetry task read it: the power sample,
    // and the drive status of the frame POWER went down in (one a frame).
    CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kDriveStatus)));
    msg::PowerMsg published{};
    int powerMessages = 0;
    msg::DriveStatusMsg drives{};
    msg::DriveStatusMsg drivesWhenSent{};
    std::uint64_t allocations = 0;
    for (int i = 0; i < 100; ++i) {
        {
            test::AllocationWatch watch;
            fsw.run(nullptr, 1);
            allocations += watch.count();
        }
        core::Message m;
        while (core::isOk(fsw.bus().receive(probe, &m))) {
            if (m.header.id == msg::ids::kPower) {
                CHECK(core::isOk(m.decode(&published)));
                ++powerMessages;
            } else if (m.header.id == msg::ids::kDriveStatus) {
                CHECK(core::isOk(m.decode(&drives)));
            }
        }
        const std::size_t before = countOf("POWER");
        collectDownlink(link, &received);
        if (countOf("POWER") > before) {
            drivesWhenSent = drives;
        }
    }
    LONGS_EQUAL(0, allocations);
    LONGS_EQUAL(2, countOf("POWER"));
    LONGS_EQUAL(1, powerMessages);
    const Packet& p = last("POWER");
    DOUBLES_EQUAL(27.123, published.busVoltageV, 1e-12);
    DOUBLES_EQUAL(static_cast<float>(published.busVoltageV), field(p, "battery_voltage"), 0.0);
    DOUBLES_EQUAL(static_cast<float>(published.busCurrentA), field(p, "battery_current"), 0.0);
    DOUBLES_EQUAL(-1.5, field(p, "battery_current"), 0.0);
    DOUBLES_EQUAL(static_cast<float>(published.stateOfCharge), field(p, "state_of_charge"), 0.0);
    DOUBLES_EQUAL(0.8765, field(p, "state_of_charge"), 1e-7);
    DOUBLES_EQUAL(2.5, field(p, "solar_current"), 0.0);
    CHECK(published.timeNs > 0);
    DOUBLES_EQUAL(static_cast<float>(static_cast<double>(published.timeNs) / 1e9), field(p, "power_sample_time"), 0.0);
    for (std::size_t w = 0; w < 5; ++w) {
        LONGS_EQUAL(1, drivesWhenSent.wheels[w].temperatureValid);
        LONGS_EQUAL(1, static_cast<long>(field(p, "temperature_valid", w)));
        DOUBLES_EQUAL(drivesWhenSent.wheels[w].temperatureC, field(p, "motor_temperature", w), 0.0);
        DOUBLES_EQUAL(static_cast<float>(deciC[w]) * 0.1F, field(p, "motor_temperature", w), 0.0);
    }
    LONGS_EQUAL(0, drivesWhenSent.wheels[5].temperatureValid);
    LONGS_EQUAL(0, static_cast<long>(field(p, "temperature_valid", 5)));
    DOUBLES_EQUAL(0.0, field(p, "motor_temperature", 5), 0.0);
}

// HAZARDS (APID 0x019): the habitual layer's remembered hazards. With the
// hazard map unchanged it goes down every 5 s (minor frame 45 of every fifth
// second); a new revision goes down in the next minor frame 45, carrying the
// message's hazards, with no heap. A message listing more hazards than it
// holds is malformed: counted, not sent.
TEST(GroundCommands, HazardsGoDownEveryFiveSecondsAndWithinASecondOfANewRevision) {
    CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kKnownHazards)));
    std::vector<std::uint64_t> hazardFrames;
    msg::KnownHazardsMsg habitual{};  // the habitual layer's latest
    std::uint64_t allocations = 0;
    // One frame: run (heap counted), the packets taken, the probe drained;
    // true when the habitual layer published its hazards in it.
    auto step = [&]() {
        {
            test::AllocationWatch watch;
            fsw.run(nullptr, 1);
            allocations += watch.count();
        }
        const std::size_t before = received.size();
        collectDownlink(link, &received);
        for (std::size_t i = before; i < received.size(); ++i) {
            if (received[i].apid == findTelemetry("HAZARDS")->apid) {
                hazardFrames.push_back(fsw.executive().stats().framesRun - 1);
            }
        }
        bool published = false;
        core::Message m;
        while (core::isOk(fsw.bus().receive(probe, &m))) {
            if (m.header.id == msg::ids::kKnownHazards) {
                CHECK(core::isOk(m.decode(&habitual)));
                published = true;
            }
        }
        return published;
    };
    for (int i = 0; i < 1000; ++i) {
        (void)step();
    }
    // Ten seconds, the map unchanged (nothing seen): two packets, at frames 45 and 545.
    LONGS_EQUAL(2, hazardFrames.size());
    LONGS_EQUAL(45, static_cast<long>(hazardFrames[0]));
    LONGS_EQUAL(545, static_cast<long>(hazardFrames[1]));
    LONGS_EQUAL(habitual.revision, static_cast<long>(field(last("HAZARDS"), "revision")));
    LONGS_EQUAL(0, static_cast<long>(field(last("HAZARDS"), "count")));
    LONGS_EQUAL(2, fsw.hazardsTelemetry().hazardsSent());

    // Just after the habitual layer's 1 Hz publication (so none of its own
    // comes before the next frame 45), and not in a second whose frame 45 is
    // the 5 s one: a new revision.
    std::uint64_t frame = 0;
    std::uint64_t next45 = 0;
    for (int i = 0; i < 1000; ++i) {
        const bool published = step();
        frame = fsw.executive().stats().framesRun - 1;
        next45 = frame + (145 - frame % 100) % 100;
        next45 += next45 == frame ? 100 : 0;
        if (published && next45 % 500 != 45) {
            break;
        }
    }
    CHECK(next45 % 500 != 45);
    msg::KnownHazardsMsg seen{};
    seen.timeNs = 1;
    seen.revision = habitual.revision + 7;
    seen.count = 2;
    seen.hazards[0] = msg::KnownHazard{12.5F, -1.25F, 0.5F, 7, {}};
    seen.hazards[1] = msg::KnownHazard{3.0F, 4.0F, 0.25F, 9, {}};
    CHECK(core::isOk(fsw.bus().publish(seen)));
    const std::size_t sentBefore = hazardFrames.size();
    while (fsw.executive().stats().framesRun - 1 < next45) {
        (void)step();
    }
    LONGS_EQUAL(sentBefore + 1, hazardFrames.size());
    LONGS_EQUAL(static_cast<long>(next45), static_cast<long>(hazardFrames.back()));
    const Packet& h = last("HAZARDS");
    LONGS_EQUAL(seen.revision, static_cast<long>(field(h, "revision")));
    LONGS_EQUAL(2, static_cast<long>(field(h, "count")));
    DOUBLES_EQUAL(12.5, field(h, "x", 0), 0.0);
    DOUBLES_EQUAL(-1.25, field(h, "y", 0), 0.0);
    DOUBLES_EQUAL(0.5, field(h, "radius", 0), 0.0);
    LONGS_EQUAL(7, static_cast<long>(field(h, "obstacle_id", 0)));
    DOUBLES_EQUAL(3.0, field(h, "x", 1), 0.0);
    DOUBLES_EQUAL(4.0, field(h, "y", 1), 0.0);
    DOUBLES_EQUAL(0.25, field(h, "radius", 1), 0.0);
    LONGS_EQUAL(9, static_cast<long>(field(h, "obstacle_id", 1)));
    for (std::size_t i = 2; i < msg::kMaxKnownHazards; ++i) {
        DOUBLES_EQUAL(0.0, field(h, "radius", i), 0.0);
        LONGS_EQUAL(0, static_cast<long>(field(h, "obstacle_id", i)));
    }
    LONGS_EQUAL(0, allocations);

    // More hazards than the message holds: malformed, counted, not taken.
    const std::uint32_t malformed = fsw.telemetry().malformed();
    msg::KnownHazardsMsg bad = seen;
    bad.revision = seen.revision + 1;
    bad.count = static_cast<std::uint8_t>(msg::kMaxKnownHazards + 1);
    CHECK(core::isOk(fsw.bus().publish(bad)));
    (void)step();
    LONGS_EQUAL(malformed + 1, fsw.telemetry().malformed());
}

// The CAN I/O task configured from its tables (node ids, boot timeout, the
// drives' fault-response limits) and taking fault protection's recovery
// actions and mission hold, against six emulated drives on an in-memory bus.
#include <array>
#include <functional>
#include <vector>

#include "fsw/io/io_events.hpp"
#include "fsw/io/can_io_task.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/canopen/canopen_events.hpp"
#include "hal/devices/device_events.hpp"
#include "hal/devices/instrument_protocol.hpp"
#include "hal/devices/rse_device_ids.hpp"
#include "sim_stub/drives/drive_bank.hpp"
#include "unit_test/support/table_loader.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;

namespace {

constexpr core::TimeNs kFrame = 10 * kNsPerMs;

struct CanIoRig {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    hal::MemoryCanBus wire{clock};
    hal::MemoryCanEndpoint* fswEnd = wire.attach("fsw");
    std::array<hal::CanBus*, msg::kWheelCount> driveEnds{};
    tables::TableService tables{events};
    std::uint64_t frame = 0;
    core::PipeId probe = 0;
    msg::NodeStatusMsg nodes{};
    unsigned eventCount[1000] = {};

    CanIoRig() {
        for (auto& e : driveEnds) {
            e = wire.attach("drive");
        }
        CHECK(core::Status::kOk == tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount));
        CHECK(core::Status::kOk == bus.createPipe("probe", 4, &probe));
        CHECK(core::Status::kOk == bus.subscribe(probe, msg::ids::kNodeStatus));
    }
    void setNodeMap(const tables::CanNodeMapTable& map) {
        CHECK_TRUE(test::activateTable(tables, tables::TableId::kCanNodeMap, map, 2));
    }
    void setFaultResponse(const tables::FaultResponseTable& response) {
        CHECK_TRUE(test::activateTable(tables, tables::TableId::kFaultResponse, response, 2));
    }
    std::array<std::uint8_t, msg::kWheelCount> driveNodes() const {
        std::array<std::uint8_t, msg::kWheelCount> ids{};
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            ids[w] = tables.canNodeMap().drive_node_id[w];
        }
        return ids;
    }
    void step(io::CanIoTask& io, sim::DriveBank& bank) {
        clock.advance(kFrame);
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            bank.drive(w).step(clock.now());
        }
        core::FrameContext ctx{frame, static_cast<std::uint32_t>(frame % 100), clock.now(), clock.now()};
        ++frame;
        io.run(ctx);
        core::Message m;
        while (core::isOk(bus.receive(probe, &m))) {
            (void)m.decode(&nodes);
        }
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            eventCount[e.id < 1000 ? e.id : 0] += 1;
        }
    }
    template <typename Pred>
    bool runUntil(io::CanIoTask& io, sim::DriveBank& bank, Pred done, core::TimeNs limit) {
        for (core::TimeNs t = 0; t < limit; t += kFrame) {
            step(io, bank);
            if (done()) {
                return true;
            }
        }
        return false;
    }
    static bool allOperational(const io::CanIoTask& io) {
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            if (io.drive(w).state() != hal::DriveState::kOperational) {
                return false;
            }
        }
        return true;
    }
    void recovery(std::uint8_t wheel, msg::DriveRecoveryAction action) {
        CHECK(core::Status::kOk == bus.publish(msg::DriveRecoveryMsg{clock.now(), wheel, action, {}}));
    }
    void hold(std::uint8_t estop) {
        const std::uint32_t reasons = estop != 0 ? (1U << msg::hold::kDriveRecovery) : 0U;
        CHECK(core::Status::kOk == bus.publish(msg::MissionHoldMsg{clock.now(), reasons, 0, estop, {}}));
    }
    void wheels(double radS) {
        msg::WheelCommandMsg cmd{};
        cmd.timeNs = clock.now();
        for (double& v : cmd.velocityRadS) {
            v = radS;
        }
        CHECK(core::Status::kOk == bus.publish(cmd));
    }
};

// A rig whose tables are already set, with the task and drives built from them.
struct Started {
    CanIoRig& rig;
    io::CanIoTask io;
    sim::DriveBank bank;
    explicit Started(CanIoRig& r)
        : rig(r), io(*r.fswEnd, r.clock, r.bus, r.events, r.tables), bank(r.driveEnds, r.driveNodes()) {
        CHECK(core::Status::kOk == io.init());
    }
    bool runUntil(const std::function<bool()>& done, core::TimeNs limit) { return rig.runUntil(io, bank, done, limit); }
    void run(core::TimeNs duration) { (void)rig.runUntil(io, bank, [] { return false; }, duration); }
    bool bootAll() {
        bank.powerOn();
        return runUntil([&] { return CanIoRig::allOperational(io); }, 3 * kNsPerSec);
    }
};

}  // namespace

TEST_GROUP(CanIoTables) {};

TEST(CanIoTables, DriveAndDeviceNodeIdsComeFromTheNodeMap) {
    CanIoRig rig;
    tables::CanNodeMapTable map = rig.tables.canNodeMap();
    map.drive_node_id[0] = 7;
    map.imu_node_id = 40;
    map.power_node_id = 41;
    map.hazard_node_id = 42;
    map.position_fix_node_id = 43;
    rig.setNodeMap(map);
    Started s(rig);
    CHECK_TRUE(s.bootAll());
    LONGS_EQUAL(7, s.bank.drive(0).nodeId());
    LONGS_EQUAL(7, s.io.drive(0).nodeId());
    // Heartbeat monitoring and NodeStatusMsg use the table's ids.
    LONGS_EQUAL(7, rig.nodes.nodes[0].nodeId);
    CHECK(rig.nodes.nodes[0].everSeen == 1);
    for (std::uint8_t d = 0; d < msg::kDeviceNodeCount; ++d) {
        const auto id = static_cast<std::uint8_t>(40 + d);
        LONGS_EQUAL(id, rig.nodes.nodes[msg::kWheelCount + d].nodeId);
        LONGS_EQUAL(id, s.io.monitoredNodeId(msg::kWheelCount + d));
        CHECK(s.io.master().heartbeats().node(id) != nullptr);
        CHECK(s.io.master().heartbeats().node(static_cast<std::uint8_t>(0x20 + d)) == nullptr);
    }
    CHECK(s.io.master().heartbeats().node(1) == nullptr);
}

TEST(CanIoTables, ADuplicateNodeIdIsRefusedByTheTable) {
    CanIoRig rig;
    tables::CanNodeMapTable map = rig.tables.canNodeMap();
    map.drive_node_id[3] = map.drive_node_id[1];
    std::uint8_t image[tables::kMaxTableImageSize];
    const std::size_t length = tables::encodeTable(map, 2, image, sizeof image);
    const tables::TableCheck check = tables::checkTableImage(image, length);
    CHECK(tables::TableReject::kInconsistent == check.reason);
    LONGS_EQUAL(tables::CanNodeMapField::drive_node_id, check.field);
    LONGS_EQUAL(3, check.element);
    CHECK_FALSE(test::activateTable(rig.tables, tables::TableId::kCanNodeMap, map, 2));
    map = rig.tables.canNodeMap();
    map.hazard_node_id = map.drive_node_id[5];
    CHECK_FALSE(test::activateTable(rig.tables, tables::TableId::kCanNodeMap, map, 2));
    LONGS_EQUAL(1, rig.tables.canNodeMap().drive_node_id[0]);  // the shipped map stays in force
}

TEST(CanIoTables, ADriveThatNeverBootsIsReportedLostAfterTheTablesBootTimeout) {
    for (const std::uint16_t timeoutMs : {500, 2000}) {
        CanIoRig rig;
        tables::CanNodeMapTable map = rig.tables.canNodeMap();
        map.drive_boot_timeout_ms = timeoutMs;
        rig.setNodeMap(map);
        Started s(rig);
        for (std::size_t w = 0; w + 1 < msg::kWheelCount; ++w) {
            s.bank.drive(w).powerOn();  // the last drive never does
        }
        const core::TimeNs timeout = static_cast<core::TimeNs>(timeoutMs) * kNsPerMs;
        s.run(timeout - 2 * kFrame);
        CHECK(rig.nodes.nodes[5].lost == 0);
        s.run(4 * kFrame);
        CHECK(rig.nodes.nodes[5].lost == 1);
        CHECK(rig.nodes.nodes[5].everSeen == 0);
        CHECK(s.io.drive(5).state() == hal::DriveState::kLost);
        LONGS_EQUAL(1, rig.eventCount[hal::events::kNodeNeverBooted]);
        CHECK(rig.nodes.nodes[4].lost == 0);
    }
}

TEST(CanIoTables, FaultResponseLimitsReachTheDrives) {
    CanIoRig rig;
    tables::FaultResponseTable response = rig.tables.faultResponse();
    response.sdo_retries = 0;
    response.sdo_timeout_ms = 70;
    response.drive_restart_attempts = 1;
    response.drive_fault_reset_wait_ms = 40;
    rig.setFaultResponse(response);
    Started s(rig);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        LONGS_EQUAL(0, s.io.drive(w).config().sdoRetries);
        LONGS_EQUAL(70 * kNsPerMs, s.io.drive(w).config().sdoTimeout);
        LONGS_EQUAL(1, s.io.drive(w).config().faultResets);
        LONGS_EQUAL(40 * kNsPerMs, s.io.drive(w).config().faultResetWait);
    }
    // And they act: one refused reset, then the motor is out of service.
    CHECK_TRUE(s.bootAll());
    s.bank.failMotor(2);
    CHECK_TRUE(s.runUntil([&] { return s.io.drive(2).state() == hal::DriveState::kFailed; }, 1 * kNsPerSec));
    LONGS_EQUAL(1, s.bank.drive(2).stats().faultResetsRefused);
}

TEST_GROUP(CanIoRecovery) {};

TEST(CanIoRecovery, ResetNodeRebootsTheDriveAndItIsConfiguredAgain) {
    CanIoRig rig;
    Started s(rig);
    CHECK_TRUE(s.bootAll());
    const std::uint32_t bootUps = s.bank.drive(2).stats().bootUps;
    const std::uint32_t configs = s.io.drive(2).stats().configAttempts;
    rig.recovery(2, msg::DriveRecoveryAction::kResetNode);
    s.run(2 * kFrame);
    LONGS_EQUAL(bootUps + 1, s.bank.drive(2).stats().bootUps);
    LONGS_EQUAL(1, s.io.recoveriesTaken());
    CHECK_TRUE(s.runUntil([&] { return CanIoRig::allOperational(s.io); }, 2 * kNsPerSec));
    LONGS_EQUAL(configs + 1, s.io.drive(2).stats().configAttempts);
    LONGS_EQUAL(1, rig.eventCount[io::events::kDriveRecoveryTaken]);
}

TEST(CanIoRecovery, FaultResetGivesAFailedDriveAFreshRound) {
    CanIoRig rig;
    tables::FaultResponseTable response = rig.tables.faultResponse();
    response.drive_restart_attempts = 1;
    rig.setFaultResponse(response);
    Started s(rig);
    CHECK_TRUE(s.bootAll());
    const std::uint8_t node = s.io.drive(4).nodeId();
    hal::CanFaultRule drop;  // the drive's one reset is lost on the bus
    drop.id = 0x200U + node;
    drop.mask = 0x7FF;
    drop.count = 0;
    CHECK(core::Status::kOk == rig.wire.addFault(drop));
    s.bank.drive(4).injectFault(0x4310);
    CHECK_TRUE(s.runUntil([&] { return s.io.drive(4).state() == hal::DriveState::kFailed; }, 2 * kNsPerSec));
    rig.wire.clearFaults();
    s.run(200 * kNsPerMs);
    CHECK(s.io.drive(4).state() == hal::DriveState::kFailed);
    rig.recovery(4, msg::DriveRecoveryAction::kFaultReset);
    CHECK_TRUE(s.runUntil([&] { return s.io.drive(4).state() == hal::DriveState::kOperational; }, 2 * kNsPerSec));
    LONGS_EQUAL(1, s.io.recoveriesTaken());
    // The interlock latched on the failure; fault protection's reset releases it now the drive is healthy.
    CHECK_TRUE(s.io.interlock().tripped());
    rig.recovery(0, msg::DriveRecoveryAction::kResetInterlock);
    s.run(2 * kFrame);
    CHECK_FALSE(s.io.interlock().tripped());
    LONGS_EQUAL(2, s.io.recoveriesTaken());
}

TEST(CanIoRecovery, BadRequestsAreRefusedCountedAndEvented) {
    CanIoRig rig;
    Started s(rig);
    CHECK_TRUE(s.bootAll());
    rig.recovery(6, msg::DriveRecoveryAction::kResetNode);                          // no such wheel
    rig.recovery(0, static_cast<msg::DriveRecoveryAction>(9));                      // no such action
    rig.recovery(1, msg::DriveRecoveryAction::kFaultReset);                         // nothing to reset
    const std::uint8_t shortMsg[4] = {};
    CHECK(core::Status::kOk == rig.bus.publish(msg::ids::kDriveRecovery, shortMsg, sizeof shortMsg));  // malformed
    const std::uint32_t bootUps = s.bank.drive(0).stats().bootUps;
    s.run(3 * kFrame);
    LONGS_EQUAL(3, s.io.recoveriesRefused());
    LONGS_EQUAL(1, s.io.malformed());  // refused by the input pipe: it does not decode
    CHECK(rig.eventCount[io::events::kBusMessageMalformed] >= 1);
    LONGS_EQUAL(0, s.io.recoveriesTaken());
    CHECK(rig.eventCount[io::events::kDriveRecoveryRefused] >= 1);
    LONGS_EQUAL(bootUps, s.bank.drive(0).stats().bootUps);
    CHECK_TRUE(CanIoRig::allOperational(s.io));
}

TEST(CanIoRecovery, TheHoldAndTheOperatorsEstopAreReleasedEachByItsOwner) {
    CanIoRig rig;
    Started s(rig);
    CHECK_TRUE(s.bootAll());
    rig.wheels(1.0);
    s.run(kFrame);
    LONGS_EQUAL(1000, s.io.drive(0).targetVelocityMradS());
    rig.hold(1);
    s.run(kFrame);
    CHECK_TRUE(s.io.holdEstopHeld());
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        LONGS_EQUAL(0, s.io.drive(w).targetVelocityMradS());
    }
    rig.wheels(1.0);
    s.run(kFrame);
    LONGS_EQUAL(0, s.io.drive(0).targetVelocityMradS());
    LONGS_EQUAL(1, s.io.commandsHeldByHold());
    // The operator's ESTOP_CLEAR (an e-stop flag of 0) does not release fault protection's hold.
    CHECK(core::Status::kOk == rig.bus.publish(msg::ModeMsg{rig.clock.now(), 0, 1, {}}));
    CHECK(core::Status::kOk == rig.bus.publish(msg::ModeMsg{rig.clock.now(), 0, 0, {}}));
    rig.wheels(1.0);
    s.run(kFrame);
    LONGS_EQUAL(0, s.io.drive(0).targetVelocityMradS());
    LONGS_EQUAL(2, s.io.commandsHeldByHold());
    // Nor does releasing the hold release the operator's e-stop.
    CHECK(core::Status::kOk == rig.bus.publish(msg::ModeMsg{rig.clock.now(), 0, 1, {}}));
    rig.hold(0);
    rig.wheels(1.0);
    s.run(kFrame);
    CHECK_FALSE(s.io.holdEstopHeld());
    LONGS_EQUAL(0, s.io.drive(0).targetVelocityMradS());
    LONGS_EQUAL(1, s.io.commandsHeldByEstop());
    CHECK(core::Status::kOk == rig.bus.publish(msg::ModeMsg{rig.clock.now(), 0, 0, {}}));
    rig.wheels(1.0);
    s.run(kFrame);
    LONGS_EQUAL(1000, s.io.drive(0).targetVelocityMradS());
    LONGS_EQUAL(2, rig.eventCount[io::events::kHoldEstopChanged]);
}

// The science instruments through the CAN I/O task: a hand-made instrument on
// the bus (its reports written here, its command frames read here).
TEST_GROUP(CanIoInstruments) {};

TEST(CanIoInstruments, CommandsGoOutStatusIsPublishedOnChangeAndAt1HzAndBadMessagesAreDropped) {
    CanIoRig rig;
    core::PipeId pipe = 0;
    CHECK(core::Status::kOk == rig.bus.createPipe("instruments", 8, &pipe));
    CHECK(core::Status::kOk == rig.bus.subscribe(pipe, msg::ids::kInstrumentStatus));
    hal::MemoryCanEndpoint* instrumentEnd = rig.wire.attach("instruments");
    Started s(rig);
    msg::InstrumentStatusMsg latest[msg::kInstrumentCount] = {};
    unsigned published[msg::kInstrumentCount] = {};
    auto collect = [&] {
        core::Message m;
        msg::InstrumentStatusMsg st{};
        while (core::isOk(rig.bus.receive(pipe, &m))) {
            CHECK(core::isOk(m.decode(&st)));
            const auto i = static_cast<std::size_t>(st.instrument);
            CHECK(i < msg::kInstrumentCount);
            latest[i] = st;
            ++published[i];
        }
    };
    auto report = [&](hal::instrument::Kind kind, hal::instrument::State state, hal::instrument::Action action,
                      std::uint8_t target, std::uint16_t id, std::uint8_t progress) {
        const hal::instrument::Report r{hal::instrument::ReportKind::kStatus, state, action, target, id, progress};
        hal::CanFrame f;
        hal::instrument::encodeReport(kind, r, &f);
        CHECK(core::Status::kOk == instrumentEnd->send(f));
    };
    // Frame 0 publishes both (offline: never heard); then nothing until 1 s.
    s.run(kFrame);
    collect();
    LONGS_EQUAL(1, published[0]);
    LONGS_EQUAL(1, published[1]);
    CHECK(latest[0].state == msg::InstrumentState::kOffline);
    CHECK(latest[1].instrument == msg::Instrument::kCamera);
    s.run(50 * kFrame);
    collect();
    LONGS_EQUAL(1, published[0]);
    // The grinder reports: published in that frame.
    report(hal::instrument::Kind::kGrinder, hal::instrument::State::kIdle, hal::instrument::Action::kNone, 0, 0, 0);
    s.run(kFrame);
    collect();
    LONGS_EQUAL(2, published[0]);
    LONGS_EQUAL(1, published[1]);
    CHECK(latest[0].state == msg::InstrumentState::kIdle);
    CHECK(latest[0].lastReportNs > 0);
    // A command to it goes out as its frame.
    msg::InstrumentCommandMsg cmd{};
    cmd.instrument = msg::Instrument::kGrinder;
    cmd.action = msg::InstrumentAction::kDig;
    cmd.targetId = 12;
    cmd.commandId = 600;
    cmd.maxDurationS = 90.0;
    CHECK(core::Status::kOk == rig.bus.publish(cmd));
    s.run(kFrame);
    collect();
    // The grinder's command frames sent since the last call.
    const auto grinderCommands = [&] {
        hal::CanFrame f;
        std::vector<hal::CanFrame> out;
        while (core::isOk(instrumentEnd->receive(&f))) {
            if (f.id == hal::device_ids::kGrinderCommand) {
                out.push_back(f);
            }
        }
        return out;
    };
    std::vector<hal::CanFrame> commands = grinderCommands();
    LONGS_EQUAL(1, commands.size());
    hal::instrument::Command c;
    hal::instrument::Refusal why = hal::instrument::Refusal::kNone;
    CHECK_TRUE(hal::instrument::decodeCommand(commands[0], &c, &why));
    CHECK(c.action == hal::instrument::Action::kDig);
    LONGS_EQUAL(12, c.target);
    LONGS_EQUAL(600, c.commandId);
    LONGS_EQUAL(900, c.maxDurationDs);
    LONGS_EQUAL(1, latest[0].commandsSent);  // a change: published
    // Its busy report is news too; a camera command while the camera is offline is not sent.
    report(hal::instrument::Kind::kGrinder, hal::instrument::State::kBusy, hal::instrument::Action::kDig, 12, 600, 0);
    cmd.instrument = msg::Instrument::kCamera;
    cmd.action = msg::InstrumentAction::kImage;
    CHECK(core::Status::kOk == rig.bus.publish(cmd));
    s.run(kFrame);
    collect();
    CHECK(latest[0].state == msg::InstrumentState::kBusy);
    LONGS_EQUAL(600, latest[0].commandId);
    LONGS_EQUAL(1, latest[0].commandsAccepted);
    CHECK(latest[1].lastRefusal == msg::InstrumentRefusal::kOffline);
    LONGS_EQUAL(1, latest[1].commandsNotSent);
    // A follow-on (extend) of the dig goes out with the id it continues and its extra work.
    cmd = msg::InstrumentCommandMsg{};
    cmd.instrument = msg::Instrument::kGrinder;
    cmd.action = msg::InstrumentAction::kExtend;
    cmd.targetId = 12;
    cmd.commandId = 601;
    cmd.extendsCommandId = 600;
    cmd.maxDurationS = 30.0;
    CHECK(core::Status::kOk == rig.bus.publish(cmd));
    s.run(kFrame);
    collect();
    commands = grinderCommands();
    LONGS_EQUAL(1, commands.size());
    CHECK_TRUE(hal::instrument::decodeCommand(commands[0], &c, &why));
    CHECK(c.action == hal::instrument::Action::kExtend);
    LONGS_EQUAL(601, c.commandId);
    LONGS_EQUAL(600, c.extendsCommandId);
    LONGS_EQUAL(300, c.maxDurationDs);
    LONGS_EQUAL(2, latest[0].commandsSent);
    cmd.instrument = msg::Instrument::kCamera;
    cmd.action = msg::InstrumentAction::kImage;
    cmd.extendsCommandId = 0;
    // Naming no instrument: dropped, counted, event 211; one that does not
    // decode is refused by the input pipe (malformed(), event 211).
    cmd.instrument = static_cast<msg::Instrument>(2);
    CHECK(core::Status::kOk == rig.bus.publish(cmd));
    const msg::WheelCommandMsg wrong{};
    CHECK(core::Status::kOk == rig.bus.publish(msg::ids::kInstrumentCommand, &wrong, sizeof wrong));
    s.run(kFrame);
    LONGS_EQUAL(1, s.io.instrumentCommandsDropped());
    LONGS_EQUAL(1, s.io.malformed());
    CHECK(rig.eventCount[io::events::kBusMessageMalformed] >= 2);
    // Reports that break the protocol are counted in framesBad (and published).
    hal::CanFrame bad;
    bad.id = hal::device_ids::kGrinderStatus;
    bad.dlc = 3;
    CHECK(core::Status::kOk == instrumentEnd->send(bad));
    s.run(kFrame);
    collect();
    LONGS_EQUAL(1, latest[0].framesBad);
    CHECK(latest[0].state == msg::InstrumentState::kBusy);  // the last good status kept
    CHECK(rig.eventCount[hal::events::kInstrumentBadFrame] >= 1);
    // Silent: offline 500 ms after its last report, published when it happens.
    const unsigned before = published[0];
    s.run(60 * kFrame);
    collect();
    CHECK(latest[0].state == msg::InstrumentState::kOffline);
    LONGS_EQUAL(1, latest[0].offlineCount);
    CHECK(published[0] >= before + 1);
    CHECK(rig.eventCount[hal::events::kInstrumentOffline] >= 1);
}

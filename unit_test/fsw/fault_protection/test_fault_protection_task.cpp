#include <cstring>
// The fault-protection task on a real bus with the default tables: the hold
// goes out in the run that first sees the fault, recovery requests and the call
// home are published, bad messages are counted, the FAULT_PROTECTION table is
// read at every run, and nothing is allocated.
#include <cstdint>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/fault_protection/fault_protection_task.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/support/alloc_guard.hpp"
#include "unit_test/support/event_probe.hpp"
#include "unit_test/support/table_loader.hpp"

#include <CppUTest/TestHarness.h>

using namespace rse;

namespace {

constexpr core::TimeNs kFrame = 10 * core::kNsPerMs;

struct TaskRig {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    tables::TableService tables{events};
    fault_protection::FaultProtectionTask task{bus, events, tables};
    core::PipeId probe = 0;
    core::Message inbox{};
    std::uint64_t frame = 0;
    msg::FaultStatusMsg faults{};
    msg::DriveStatusMsg drives{};
    // What came out in the last run.
    msg::MissionHoldMsg hold{};
    unsigned holds = 0, recoveries = 0, restarts = 0, safes = 0, statuses = 0;
    msg::DriveRecoveryMsg lastRecovery{};

    bool init() {
        if (!core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount)) ||
            !core::isOk(task.init()) || !core::isOk(bus.createPipe("probe", 32, &probe))) {
            return false;
        }
        for (core::MsgId id : {msg::ids::kMissionHold, msg::ids::kDriveRecovery, msg::ids::kTaskRestart,
                               msg::ids::kSafeRequest, msg::ids::kFaultProtectionStatus}) {
            if (!core::isOk(bus.subscribe(probe, id))) {
                return false;
            }
        }
        for (msg::WheelStatus& w : drives.wheels) {
            w.health = msg::DriveHealth::kOperational;
        }
        return true;
    }
    void mode(std::uint8_t m) {
        msg::ModeMsg mm{};
        mm.mode = m;
        (void)bus.publish(mm);
    }
    void runFrame() {
        faults.timeNs = clock.now();
        drives.timeNs = clock.now();
        (void)bus.publish(faults);
        (void)bus.publish(drives);
        core::FrameContext f{};
        f.frame = frame++;
        f.actualStart = clock.now();
        task.run(f);
        holds = recoveries = restarts = safes = statuses = 0;
        while (core::isOk(bus.receive(probe, &inbox))) {
            switch (inbox.header.id) {
                case msg::ids::kMissionHold: ++holds; (void)inbox.decode(&hold); break;
                case msg::ids::kDriveRecovery: ++recoveries; (void)inbox.decode(&lastRecovery); break;
                case msg::ids::kTaskRestart: ++restarts; break;
                case msg::ids::kSafeRequest: ++safes; break;
                case msg::ids::kFaultProtectionStatus: ++statuses; break;
                default: break;
            }
        }
        clock.advance(kFrame);
    }
};

}  // namespace

TEST_GROUP(FaultProtectionTask) {
    TaskRig rig;
    void setup() override { CHECK(rig.init()); }
};

TEST(FaultProtectionTask, TheHoldGoesOutInTheRunThatSeesTheFault) {
    rig.mode(msg::mode::kAutonomous);
    rig.runFrame();
    LONGS_EQUAL(1, rig.holds);  // the first run publishes the (empty) hold
    LONGS_EQUAL(0, rig.hold.reasons);
    rig.runFrame();
    LONGS_EQUAL(0, rig.holds);  // unchanged: not again until the 1 Hz repeat
    rig.faults.activeMask = std::uint64_t{1} << msg::fault::kPoseUncertain;
    rig.runFrame();
    LONGS_EQUAL(1, rig.holds);
    LONGS_EQUAL(1u << msg::hold::kPoseUncertain, rig.hold.reasons);
    LONGS_EQUAL(1, rig.hold.estop);
    LONGS_EQUAL(1, rig.statuses);
    rig.faults.activeMask = 0;
    rig.runFrame();
    LONGS_EQUAL(0, rig.hold.reasons);
    LONGS_EQUAL(0, rig.hold.estop);
    LONGS_EQUAL(1, rig.hold.resumeCount);
    LONGS_EQUAL(1, rig.task.status().recoveries);
}

TEST(FaultProtectionTask, AFailedDriveGetsAFaultResetOnTheBus) {
    rig.drives.wheels[3].health = msg::DriveHealth::kFailed;
    rig.runFrame();
    LONGS_EQUAL(1, rig.recoveries);
    LONGS_EQUAL(3, rig.lastRecovery.wheel);
    LONGS_EQUAL(static_cast<int>(msg::DriveRecoveryAction::kFaultReset), static_cast<int>(rig.lastRecovery.action));
    LONGS_EQUAL(1u << msg::hold::kDriveRecovery, rig.hold.reasons);  // drives are recovered in every mode
}

TEST(FaultProtectionTask, AStalledTaskIsRestartedAndAGiveUpCallsHome) {
    rig.faults.activeMask = std::uint64_t{1} << (msg::fault::kTaskStalled + 7);
    rig.runFrame();
    LONGS_EQUAL(1, rig.restarts);
    unsigned safes = 0;
    for (int i = 0; i < 400; ++i) {  // 3 tries x 1 s by default
        rig.runFrame();
        safes += rig.safes;
    }
    LONGS_EQUAL(1, safes);
    LONGS_EQUAL(1, rig.task.callHomes());
    cmdtlm::event_data::FAULT_CALL_HOME callHome;  // the reason by number, as the safe request's
    CHECK_TRUE(test::lastEventData(rig.events, fault_protection::events::kCallHome, &callHome));
    DOUBLES_EQUAL(static_cast<double>(msg::CallHomeReason::kFaultUnrecovered), callHome.reason, 0.0);
}

TEST(FaultProtectionTask, TheTableIsReadAtEveryRun) {
    tables::FaultProtectionTable t = rig.tables.faultProtection();
    t.response[static_cast<std::size_t>(msg::FaultClass::kPoseUncertain)] =
        static_cast<std::uint8_t>(msg::FaultResponseKind::kSafeAndCallHome);
    CHECK(test::activateTable(rig.tables, tables::TableId::kFaultProtection, t, 2));
    rig.mode(msg::mode::kAutonomous);
    rig.faults.activeMask = std::uint64_t{1} << msg::fault::kPoseUncertain;
    rig.runFrame();
    LONGS_EQUAL(1, rig.safes);
    LONGS_EQUAL(0, rig.hold.reasons);
}

TEST(FaultProtectionTask, OffTheMapSendsTheDefaultTablesReplanRequestInAutonomous) {
    core::PipeId replans = 0;
    CHECK(core::isOk(rig.bus.createPipe("replans", 4, &replans)));
    CHECK(core::isOk(rig.bus.subscribe(replans, msg::ids::kReplanRequest)));
    rig.mode(msg::mode::kAutonomous);
    rig.faults.activeMask = std::uint64_t{1} << msg::fault::kOffMap;
    rig.runFrame();
    msg::ReplanRequestMsg request{};
    CHECK(core::isOk(rig.bus.receive(replans, &rig.inbox)));
    CHECK(core::isOk(rig.inbox.decode(&request)));
    LONGS_EQUAL(msg::fault::kOffMap, request.faultId);
    LONGS_EQUAL(1, request.attempt);
    LONGS_EQUAL(0, rig.hold.reasons);
    LONGS_EQUAL(1, rig.task.status().actionsSent);
    CHECK_FALSE(core::isOk(rig.bus.receive(replans, &rig.inbox)));  // one per try, not one per frame
    rig.runFrame();
    CHECK_FALSE(core::isOk(rig.bus.receive(replans, &rig.inbox)));
}

TEST(FaultProtectionTask, MalformedInputIsCountedAndIgnored) {
    std::uint8_t junk[3] = {1, 2, 3};
    (void)rig.bus.publish(msg::ids::kFaultStatus, junk, sizeof junk);
    rig.runFrame();
    LONGS_EQUAL(1, rig.task.malformedMessages());
    LONGS_EQUAL(1, test::drainEventsWithId(rig.events, fault_protection::events::kMalformedInput));
}

// A wheel health outside DriveHealth reads as neither healthy nor faulted: the
// whole drive status is refused (its other wheels are not acted on), counted
// and evented; the last good status stands until a good one comes.
TEST(FaultProtectionTask, ADriveHealthOutsideItsEnumIsRefusedCountedAndEvented) {
    rig.runFrame();  // a good status: every drive operational
    LONGS_EQUAL(0, rig.task.malformedMessages());
    rig.drives.wheels[2].health = static_cast<msg::DriveHealth>(8);  // one past kLost
    rig.drives.wheels[0].health = msg::DriveHealth::kFailed;         // in range, but in a refused message
    rig.runFrame();
    LONGS_EQUAL(1, rig.task.malformedMessages());
    // The event says which wheel and what value, not just "invalid".
    core::Event e;
    unsigned refusals = 0;
    while (core::isOk(rig.events.pop(&e))) {
        if (e.id == fault_protection::events::kMalformedInput) {
            ++refusals;
            CHECK_TEXT(std::strstr(e.text, "wheel 2 (RL) health 8 is no drive state") != nullptr, e.text);
        }
    }
    LONGS_EQUAL(1, refusals);
    LONGS_EQUAL(0, rig.recoveries);  // wheel 0's failure was not taken from it
    LONGS_EQUAL(0, rig.hold.reasons);
    LONGS_EQUAL(0, rig.task.responder().responsesStarted());
    rig.drives.wheels[2].health = static_cast<msg::DriveHealth>(255);
    rig.runFrame();
    LONGS_EQUAL(2, rig.task.malformedMessages());
    // The next good status is taken: wheel 0's failure gets its fault reset.
    rig.drives.wheels[2].health = msg::DriveHealth::kOperational;
    rig.runFrame();
    LONGS_EQUAL(2, rig.task.malformedMessages());
    LONGS_EQUAL(1, rig.recoveries);
    LONGS_EQUAL(0, rig.lastRecovery.wheel);
}

// The last good status stands while bad ones come: a faulted drive is not
// taken for recovered, and its response goes on.
TEST(FaultProtectionTask, AFaultedDriveStaysFaultedThroughRefusedStatuses) {
    rig.drives.wheels[4].health = msg::DriveHealth::kFailed;
    rig.runFrame();
    LONGS_EQUAL(1, rig.recoveries);  // the first fault reset
    rig.drives.wheels[4].health = static_cast<msg::DriveHealth>(9);
    for (int i = 0; i < 300; ++i) {  // well past the 1 s wait for the next try
        rig.runFrame();
    }
    LONGS_EQUAL(300, rig.task.malformedMessages());
    LONGS_EQUAL(0, rig.task.responder().recoveries());
    LONGS_EQUAL(1u << msg::hold::kDriveRecovery, rig.hold.reasons);
    CHECK(rig.task.status().actionsSent >= 2);  // tries went on from the last good status (failed)
}

// kLost, the last value, is a drive state: taken, not refused.
TEST(FaultProtectionTask, TheLastDriveHealthIsInRange) {
    rig.drives.wheels[1].health = msg::DriveHealth::kLost;
    rig.runFrame();
    LONGS_EQUAL(0, rig.task.malformedMessages());
    LONGS_EQUAL(1u << msg::hold::kDriveRecovery, rig.hold.reasons);
}

TEST(FaultProtectionTask, NoHeapAcrossAFaultedMinute) {
    rig.mode(msg::mode::kAutonomous);
    rig.runFrame();
    test::AllocationWatch watch;
    for (int i = 0; i < 6000; ++i) {
        const int phase = i % 1000;
        rig.faults.activeMask = phase < 300 ? (std::uint64_t{1} << msg::fault::kBatteryLow) |
                                                  (std::uint64_t{1} << (msg::fault::kTaskStalled + 2))
                                            : 0;
        rig.drives.wheels[1].health = phase > 500 && phase < 900 ? msg::DriveHealth::kLost
                                                                 : msg::DriveHealth::kOperational;
        rig.drives.interlockTripped = phase >= 500 ? 1 : 0;
        rig.runFrame();
    }
    LONGS_EQUAL(0, watch.count());
    CHECK(rig.task.responder().responsesStarted() > 10);
}

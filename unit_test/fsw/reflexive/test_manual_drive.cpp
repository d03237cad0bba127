// Manual driving on an in-memory software bus: its input pipe (DRIVE requests
// and mode changes, in arrival order), the wheel commands it publishes and its
// malformed-input count (core::InputPipe, event 605).
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/reflexive/manual_drive.hpp"
#include "fsw/reflexive/reflexive_events.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::Status;
namespace ev = rse::reflexive::events;

namespace {

constexpr core::TimeNs kFrame = 10 * core::kNsPerMs;
constexpr std::uint8_t kStandby = 1;
constexpr std::uint8_t kManual = 3;

}  // namespace

TEST_GROUP(ManualDrive) {
    core::VirtualClock clock{1 * core::kNsPerSec};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    tables::TableService tables{events};
    reflexive::ManualDrive task{clock, bus, events, tables};
    core::PipeId wheels = 0;
    core::Message inbox{};

    void setup() override {
        CHECK_TRUE(Status::kOk == tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount));
        CHECK_TRUE(Status::kOk == task.init());
        CHECK_TRUE(Status::kOk == bus.createPipe("wheels", 8, &wheels));
        CHECK_TRUE(Status::kOk == bus.subscribe(wheels, msg::ids::kWheelCommand));
    }
    void runFrame() {
        clock.advance(kFrame);
        task.run(core::FrameContext{});
    }
    void publishMode(std::uint8_t mode, std::uint8_t estop = 0) {
        msg::ModeMsg m{};
        m.timeNs = clock.now();
        m.mode = mode;
        m.estop = estop;
        CHECK_TRUE(Status::kOk == bus.publish(m));
    }
    void publishDrive(double speedMS, double durationS) {
        msg::ManualDriveMsg d{};
        d.timeNs = clock.now();
        d.speedMS = speedMS;
        d.durationS = durationS;
        CHECK_TRUE(Status::kOk == bus.publish(d));
    }
    // The wheel commands published since the last call; the last one in *last.
    unsigned takeCommands(msg::WheelCommandMsg* last) {
        unsigned n = 0;
        while (core::isOk(bus.receive(wheels, &inbox))) {
            CHECK_TRUE(Status::kOk == inbox.decode(last));
            ++n;
        }
        return n;
    }
};

TEST(ManualDrive, InArrivalOrderAModeThenARequestStartsTheDriveAndLeavingManualStopsIt) {
    publishMode(kManual);
    publishDrive(0.2, 5.0);
    runFrame();
    CHECK_TRUE(task.driving());
    msg::WheelCommandMsg command{};
    LONGS_EQUAL(1, takeCommands(&command));
    CHECK_TRUE(command.velocityRadS[0] > 0.0);
    publishMode(kStandby);
    runFrame();
    CHECK_FALSE(task.driving());
    LONGS_EQUAL(1, takeCommands(&command));
    DOUBLES_EQUAL(0.0, command.velocityRadS[0], 0.0);
    LONGS_EQUAL(1, task.drivesStarted());
    LONGS_EQUAL(1, task.drivesEnded());
}

TEST(ManualDrive, ARequestBeforeTheModeChangeIsIgnoredAndSaid) {
    publishDrive(0.2, 5.0);
    publishMode(kManual);
    runFrame();
    CHECK_FALSE(task.driving());
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, ev::kManualDriveEnded));
    LONGS_EQUAL(0, task.malformed());
}

TEST(ManualDrive, AMessageThatDoesNotDecodeIsCountedAndEventedThrottled) {
    const std::uint8_t junk[3] = {1, 2, 3};
    for (int i = 0; i < 3; ++i) {
        CHECK_TRUE(Status::kOk == bus.publish(msg::ids::kManualDrive, junk, sizeof junk));
    }
    CHECK_TRUE(Status::kOk == bus.publish(msg::ids::kMode, junk, sizeof junk));
    runFrame();
    LONGS_EQUAL(4, task.malformed());
    LONGS_EQUAL(3, rse::test::drainEventsWithId(events, ev::kManualDriveMalformed));  // 1st, 2nd, 4th
    CHECK_FALSE(task.driving());
}

// The hardware's packets, each packed from what CAN I/O publishes: DRIVES in
// slot 50, INSTRUMENTS in slot 90 and on a change that matters, POWER in slot 30.
#include "fsw/io/io_telemetry.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::RecordingSink;

TEST_GROUP(DrivesTelemetry) {
    io::DrivesTelemetry packer;
    test::PackerRig rig{packer};
};

TEST(DrivesTelemetry, GoesInItsSlotWithTheDrivesTheCommandAndTheEstop) {
    msg::DriveStatusMsg drives{};
    drives.wheels[2].velocityRadS = 1.5;
    drives.wheels[2].currentA = 0.75;
    drives.wheels[2].lastEmcyCode = 0x5000;
    drives.wheels[2].health = msg::DriveHealth::kFaulted;
    drives.interlockTripped = 1;
    msg::WheelCommandMsg command{};
    command.velocityRadS[2] = 2.0;
    msg::ModeMsg mode{};
    mode.estop = 1;
    rig.publish(drives);
    rig.publish(command);
    rig.publish(mode);
    rig.runFrames(0, io::kDrivesSlot - 1);
    LONGS_EQUAL(0, rig.sink.packets.size());
    rig.run(io::kDrivesSlot);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::DRIVES_Tlm>());
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::DRIVES_Tlm>();
    DOUBLES_EQUAL(1.5, RecordingSink::field(p, "speed", 2), 1e-6);
    DOUBLES_EQUAL(2.0, RecordingSink::field(p, "commanded", 2), 1e-6);
    DOUBLES_EQUAL(0.75, RecordingSink::field(p, "current", 2), 1e-6);
    DOUBLES_EQUAL(0x5000, RecordingSink::field(p, "last_emcy", 2), 0.0);
    DOUBLES_EQUAL(static_cast<double>(msg::DriveHealth::kFaulted), RecordingSink::field(p, "state", 2), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(p, "interlock"), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(p, "estop"), 0.0);
    rig.runFrames(io::kDrivesSlot + 1, 100 + io::kDrivesSlot - 1);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::DRIVES_Tlm>());  // once a second
}

// The contact reflex's counts come from the follower's status.
TEST(DrivesTelemetry, CarriesTheContactReflexCountsFromTheFollowersStatus) {
    msg::FollowerStatusMsg status{};
    status.contactsUnplaced = 1;
    status.backoffs = 3;
    status.backoffsCut = 2;
    status.lastBackoffEnd = 4;
    status.wheelReadingsNotFinite = 7;
    rig.publish(status);
    rig.run(io::kDrivesSlot);
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::DRIVES_Tlm>();
    DOUBLES_EQUAL(1, RecordingSink::field(p, "contacts_unplaced"), 0.0);
    DOUBLES_EQUAL(3, RecordingSink::field(p, "backoffs"), 0.0);
    DOUBLES_EQUAL(2, RecordingSink::field(p, "backoffs_cut"), 0.0);
    DOUBLES_EQUAL(4, RecordingSink::field(p, "last_backoff_end"), 0.0);
    DOUBLES_EQUAL(7, RecordingSink::field(p, "wheel_readings_not_finite"), 0.0);
}

TEST_GROUP(InstrumentsTelemetry) {
    io::InstrumentsTelemetry packer;
    test::PackerRig rig{packer};
};

TEST(InstrumentsTelemetry, GoesInItsSlotAndAfterAChangeButNotForProgress) {
    msg::InstrumentStatusMsg camera{};
    camera.instrument = msg::Instrument::kCamera;
    camera.state = msg::InstrumentState::kBusy;
    camera.commandId = 12;
    camera.progressPct = 10;
    rig.publish(camera);
    rig.run(1);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::INSTRUMENTS_Tlm>());  // a new state and command
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::INSTRUMENTS_Tlm>();
    DOUBLES_EQUAL(12, RecordingSink::field(p, "command_id", 1), 0.0);
    DOUBLES_EQUAL(0, RecordingSink::field(p, "command_id", 0), 0.0);
    camera.progressPct = 50;  // progress alone is not news
    rig.publish(camera);
    rig.run(2);
    LONGS_EQUAL(1, rig.sink.count<cmdtlm::INSTRUMENTS_Tlm>());
    rig.runFrames(3, io::kInstrumentsSlot);
    LONGS_EQUAL(2, rig.sink.count<cmdtlm::INSTRUMENTS_Tlm>());
    DOUBLES_EQUAL(50, RecordingSink::field(rig.sink.last<cmdtlm::INSTRUMENTS_Tlm>(), "progress", 1), 0.0);
    camera.faultCode = 3;
    rig.publish(camera);
    rig.run(io::kInstrumentsSlot + 1);
    LONGS_EQUAL(3, rig.sink.count<cmdtlm::INSTRUMENTS_Tlm>());
}

TEST(InstrumentsTelemetry, AStatusNamingNoInstrumentIsRefused) {
    msg::InstrumentStatusMsg bad{};
    bad.instrument = static_cast<msg::Instrument>(msg::kInstrumentCount);
    bad.commandId = 9;
    rig.publish(bad);
    rig.run(1);
    LONGS_EQUAL(1, rig.pipe.malformed());
    LONGS_EQUAL(0, rig.sink.packets.size());
}

TEST_GROUP(PowerTelemetry) {
    io::PowerTelemetry packer;
    test::PackerRig rig{packer};
};

TEST(PowerTelemetry, GoesInItsSlotWithTheBatteryAndEveryMotorTemperature) {
    msg::PowerMsg power{};
    power.timeNs = 2 * core::kNsPerSec;
    power.busVoltageV = 27.5;
    power.stateOfCharge = 0.8;
    msg::DriveStatusMsg drives{};
    drives.wheels[4].temperatureValid = 1;
    drives.wheels[4].temperatureC = 41.5F;
    drives.wheels[5].temperatureC = 99.0F;  // not valid: sent as 0
    rig.publish(power);
    rig.publish(drives);
    rig.runFrames(0, io::kPowerSlot);
    LONGS_EQUAL(1, rig.sink.packets.size());
    const RecordingSink::Packet& p = rig.sink.last<cmdtlm::POWER_Tlm>();
    DOUBLES_EQUAL(27.5, RecordingSink::field(p, "battery_voltage"), 1e-6);
    DOUBLES_EQUAL(0.8, RecordingSink::field(p, "state_of_charge"), 1e-6);
    DOUBLES_EQUAL(2.0, RecordingSink::field(p, "power_sample_time"), 1e-6);
    DOUBLES_EQUAL(41.5, RecordingSink::field(p, "motor_temperature", 4), 1e-6);
    DOUBLES_EQUAL(1, RecordingSink::field(p, "temperature_valid", 4), 0.0);
    DOUBLES_EQUAL(0, RecordingSink::field(p, "motor_temperature", 5), 0.0);
    DOUBLES_EQUAL(0, RecordingSink::field(p, "temperature_valid", 5), 0.0);
}

// The scenario's motor_overheat fault and [drives] ambient_c: parsed, range
// checked, scheduled, and reaching the drive emulators through DriveBank.
#include <array>
#include <string>

#include "hal/can/memory_can_bus.hpp"
#include "sim_stub/drives/drive_bank.hpp"
#include "sim_stub/scenario/fault_scheduler.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "unit_test/sim_stub/recording_fault_target.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;

namespace {
const std::string kBase = test::kOpenSiteScenario;
const std::string kOverheat = kBase + R"(
[drives]
ambient_c = -60
[[faults]]
type = "motor_overheat"
at_s = 2.5
wheel = 3
heat_factor = 12
)";
}  // namespace

TEST_GROUP(MotorOverheatScenario){};

TEST(MotorOverheatScenario, ParsedScheduledAndAppliedToTheDrive) {
    const Scenario s = parseScenario(kOverheat, "overheat.toml");
    DOUBLES_EQUAL(-60.0, s.drives.ambientC, 0.0);
    LONGS_EQUAL(1, s.faults.size());
    CHECK(FaultType::kMotorOverheat == s.faults[0].type);
    STRCMP_EQUAL("motor_overheat", toString(s.faults[0].type));
    LONGS_EQUAL(2, s.faults[0].wheel);
    DOUBLES_EQUAL(12.0, s.faults[0].value, 0.0);

    test::RecordingFaultTarget target;
    FaultScheduler scheduler(s.faults, target);
    scheduler.step(2 * core::kNsPerSec);
    LONGS_EQUAL(0, target.log.size());
    scheduler.step(3 * core::kNsPerSec);
    LONGS_EQUAL(1, target.log.size());
    CHECK(target.log[0].find("overheat 2 12.00") != std::string::npos);

    core::VirtualClock clock;
    hal::MemoryCanBus wire{clock};
    std::array<hal::CanBus*, kWheelCount> buses{};
    for (auto& b : buses) {
        b = wire.attach("drive");
    }
    DriveBank bank(buses, s);
    DOUBLES_EQUAL(-60.0, bank.drive(0).temperatureC(), 0.0);
    bank.overheatMotor(2, s.faults[0].value);
    DOUBLES_EQUAL(12.0, bank.drive(2).overheat(), 0.0);
    DOUBLES_EQUAL(1.0, bank.drive(1).overheat(), 0.0);
}

TEST(MotorOverheatScenario, BadValuesAreRejected) {
    Scenario s;
    std::string error;
    CHECK_FALSE(tryParseScenario(kBase + "[[faults]]\ntype = \"motor_overheat\"\nat_s = 1\nwheel = 1\nheat_factor = 0.5\n",
                                 "a.toml", &s, &error));
    CHECK(error.find("heat_factor") != std::string::npos);
    CHECK_FALSE(tryParseScenario(kBase + "[[faults]]\ntype = \"motor_overheat\"\nat_s = 1\nwheel = 1\n", "b.toml", &s,
                                 &error));
    CHECK(error.find("heat_factor") != std::string::npos);
    CHECK_FALSE(tryParseScenario(kBase + "[drives]\nambient_c = 200\n", "c.toml", &s, &error));
    CHECK(error.find("ambient_c") != std::string::npos);
}

TEST(MotorOverheatScenario, DriveFaultIsParsedAndScheduledWithItsEmcyCode) {
    const Scenario s = parseScenario(kBase + "[[faults]]\ntype = \"drive_fault\"\nat_s = 1\nwheel = 6\n"
                                             "[[faults]]\ntype = \"drive_fault\"\nat_s = 2\nwheel = 1\nemcy_code = 0x3210\n",
                                     "drive_fault.toml");
    LONGS_EQUAL(2, s.faults.size());
    CHECK(FaultType::kDriveFault == s.faults[0].type);
    STRCMP_EQUAL("drive_fault", toString(s.faults[0].type));
    test::RecordingFaultTarget target;
    FaultScheduler scheduler(s.faults, target);
    scheduler.step(3 * core::kNsPerSec);
    LONGS_EQUAL(2, target.log.size());
    CHECK(target.log[0].find("drive-fault 5 0x4310") != std::string::npos);
    CHECK(target.log[1].find("drive-fault 0 0x3210") != std::string::npos);
    Scenario bad;
    std::string error;
    CHECK_FALSE(tryParseScenario(kBase + "[[faults]]\ntype = \"drive_fault\"\nat_s = 1\nwheel = 1\nemcy_code = 0\n",
                                 "e.toml", &bad, &error));
    CHECK(error.find("emcy_code") != std::string::npos);
}

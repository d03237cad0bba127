#include <string>
#include <vector>

#include "sim_stub/scenario/fault_scheduler.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "unit_test/sim_stub/recording_fault_target.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;

namespace {

const std::string kSchedule = test::kOpenSiteScenario + R"(
[[faults]]
type = "motor_degradation"
at_s = 1.0
wheel = 2
current_factor = 1.5
[[faults]]
type = "drive_heartbeat_loss"
at_s = 2.0
wheel = 3
duration_s = 0.5
[[faults]]
type = "drive_crash"
at_s = 2.2
wheel = 4
restart_at_s = 5.0
[[faults]]
type = "sensor_dropout"
at_s = 3.0
device = "imu"
until_s = 4.0
[[faults]]
type = "device_crash"
at_s = 3.0
device = "position_fix"
[[faults]]
type = "imu_bias_step"
at_s = 3.5
delta_rad_s = 0.02
[[faults]]
type = "bus_fault"
at_s = 6.0
action = "drop"
cob_id = 0x700
mask = 0x780
frames = 4
[[faults]]
type = "babbling_node"
at_s = 6.5
cob_id = 0x001
rate_hz = 1000
until_s = 7.0
[[faults]]
type = "motor_failure"
at_s = 8.0
wheel = 6
[[faults]]
type = "position_fix_outlier"
at_s = 9.0
offset_m = 12.5
count = 3
bearing_deg = 90
[[faults]]
type = "task_stall"
at_s = 9.5
task = "habitual"
duration_s = 0.4
[[faults]]
type = "task_stall"
at_s = 9.6
task = 11
[[faults]]
type = "instrument_failure"
at_s = 9.7
device = "grinder"
fault_code = 0x42
until_s = 9.95
[[faults]]
type = "instrument_failure"
at_s = 9.8
device = "camera"
silent = true
)";

const std::vector<std::string> kExpected = {
    "1.000 degrade 1 1.50",
    "2.000 heartbeat-loss 2 on",
    "2.200 crash-drive 3",
    "2.500 heartbeat-loss 2 off",
    "3.000 dropout imu on",
    "3.000 crash-device position_fix",
    "3.500 imu-bias 0.020",
    "4.000 dropout imu off",
    "5.000 restart-drive 3",
    "6.000 bus-fault 0 0x700/0x780 x4",
    "6.500 babble 0x001 1000 on",
    "7.000 babble 0x001 1000 off",
    "8.000 fail 5",
    "9.000 fix-outlier 12.50 1.5708 x3",
    "9.500 task-stall habitual on",
    "9.600 task-stall row 11 on",  // no end: the schedule never enables it again
    "9.700 instrument-failure grinder 66 on",
    "9.800 instrument-failure camera 1 silent on",  // no end: it stays failed
    "9.900 task-stall habitual off",
    "9.950 instrument-failure grinder 66 off",
};

void checkLog(const std::vector<std::string>& expected, const std::vector<std::string>& got) {
    LONGS_EQUAL(expected.size(), got.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        STRCMP_EQUAL(expected[i].c_str(), got[i].c_str());
    }
}

}  // namespace

TEST_GROUP(SimFaultScheduler){};

TEST(SimFaultScheduler, EventsFireAtTheirTimesInOrder) {
    const Scenario s = parseScenario(kSchedule, "schedule.toml");
    test::RecordingFaultTarget target;
    FaultScheduler scheduler(s.faults, target);
    LONGS_EQUAL(20, scheduler.eventCount());
    CHECK_EQUAL(core::kNsPerSec, scheduler.nextAt());
    for (core::TimeNs t = 0; t <= 10 * core::kNsPerSec; t += 10 * core::kNsPerMs) {
        target.now = t;
        scheduler.step(t);
    }
    checkLog(kExpected, target.log);
    LONGS_EQUAL(20, scheduler.fired());
    CHECK_EQUAL(kNever, scheduler.nextAt());
}

TEST(SimFaultScheduler, NothingFiresEarlyAndACoarseStepFiresEverythingDueInOrder) {
    const Scenario s = parseScenario(kSchedule, "schedule.toml");
    test::RecordingFaultTarget target;
    FaultScheduler scheduler(s.faults, target);
    target.now = 999 * core::kNsPerMs;
    scheduler.step(target.now);
    CHECK(target.log.empty());
    target.now = 0;  // logged with time 0 so the lines show order only
    scheduler.step(100 * core::kNsPerSec);
    LONGS_EQUAL(kExpected.size(), target.log.size());
    for (std::size_t i = 0; i < kExpected.size(); ++i) {
        STRCMP_EQUAL(("0.000" + kExpected[i].substr(5)).c_str(), target.log[i].c_str());
    }
    scheduler.step(200 * core::kNsPerSec);  // nothing left
    LONGS_EQUAL(kExpected.size(), target.log.size());
}

TEST(SimFaultScheduler, EventsAtTheSameTimeKeepTheFileOrder) {
    std::vector<FaultSpec> faults(3);
    for (std::size_t i = 0; i < faults.size(); ++i) {
        faults[i].type = FaultType::kMotorFailure;
        faults[i].at = core::kNsPerSec;
        faults[i].wheel = 5 - i;
    }
    faults[1].type = FaultType::kSensorDropout;  // its end lands at the same time as nothing else
    faults[1].device = SimDevice::kHazard;
    faults[1].until = 2 * core::kNsPerSec;
    test::RecordingFaultTarget target;
    FaultScheduler scheduler(faults, target);
    target.now = core::kNsPerSec;
    scheduler.step(core::kNsPerSec);
    checkLog({"1.000 fail 5", "1.000 dropout hazard on", "1.000 fail 3"}, target.log);
    target.now = 2 * core::kNsPerSec;
    scheduler.step(target.now);
    LONGS_EQUAL(4, target.log.size());
    STRCMP_EQUAL("2.000 dropout hazard off", target.log[3].c_str());
}

TEST(SimFaultScheduler, AnEmptyScheduleDoesNothing) {
    test::RecordingFaultTarget target;
    FaultScheduler scheduler(std::vector<FaultSpec>{}, target);
    scheduler.step(kNever - 1);
    LONGS_EQUAL(0, scheduler.eventCount());
    CHECK(target.log.empty());
}

TEST(SimFaultScheduler, ASlideFiresOnceAtItsStartWithItsDuration) {
    std::vector<FaultSpec> faults(1);
    faults[0].type = FaultType::kSlide;
    faults[0].at = 25 * core::kNsPerSec;
    faults[0].until = 27 * core::kNsPerSec;
    faults[0].value = 2.5;
    faults[0].bearingRad = -1.5;
    test::RecordingFaultTarget target;
    FaultScheduler scheduler(faults, target);
    LONGS_EQUAL(1, scheduler.eventCount());
    target.now = 30 * core::kNsPerSec;
    scheduler.step(target.now);
    LONGS_EQUAL(1, target.log.size());
    STRCMP_CONTAINS("slide 2.50 -1.5000 2.00 s", target.log[0].c_str());
}

#include <cmath>
#include <string>
#include <vector>

#include "sim_stub/scenario/scenario_parser.hpp"
#include "sim_stub/world/geometry.hpp"
#include "sim_stub/world/terrain.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;

namespace {

const std::string kBase = test::kOpenSiteScenario;

std::string errorOf(const std::string& text) {
    Scenario s;
    std::string error;
    if (tryParseScenario(text, "inline.toml", &s, &error)) {
        return "(accepted)";
    }
    return error;
}

constexpr core::TimeNs kSec = core::kNsPerSec;

}  // namespace

TEST_GROUP(SimScenario){};

TEST(SimScenario, StraightTenMetreExampleLoads) {
    Scenario s;
    std::string error;
    CHECK_TRUE_TEXT(tryLoadScenarioFile("sim_stub/scenarios/straight_10m.toml", &s, &error), error.c_str());
    STRCMP_EQUAL("straight_10m", s.name.c_str());
    LONGS_EQUAL(1, s.seed);
    LONGS_EQUAL(0, s.obstacles.size());
    LONGS_EQUAL(0, s.faults.size());
    DOUBLES_EQUAL(0.0, s.start.x, 0.0);
    DOUBLES_EQUAL(0.0, s.start.theta, 0.0);
    CHECK(s.map.containsDisc({10.0, 0.0}, s.rover.radiusM));  // the goal is on the map
    DOUBLES_EQUAL(0.10, s.rover.wheelRadiusM, 0.0);          // defaults
    LONGS_EQUAL(6, s.rover.driveNodes[5]);
}

TEST(SimScenario, DemoMissionLoadsWithAHiddenRockOnTheDirectLine) {
    const Scenario s = loadScenarioFile("sim_stub/scenarios/demo_mission.toml");
    STRCMP_EQUAL("demo_mission", s.name.c_str());
    CHECK(s.obstacles.size() >= 3);
    const Terrain terrain(s.map, s.obstacles);
    const std::size_t onLine = terrain.firstOnSegment({0.0, 0.0}, {20.0, 0.0});
    CHECK(onLine != kNoObstacle);
    CHECK_FALSE(terrain.obstacle(onLine).known);
    std::size_t hidden = 0;
    std::size_t known = 0;
    for (const Obstacle& o : s.obstacles) {
        hidden += o.known ? 0U : 1U;
        known += o.known ? 1U : 0U;
        if (o.known) {
            // No known rock blocks the direct line (with the footprint): only the hidden one does.
            CHECK_FALSE(segmentIntersectsPolygon({0.0, 0.0}, {20.0, 0.0}, o.shape));
        }
    }
    LONGS_EQUAL(1, hidden);
    CHECK(known >= 2);
    // The ten points' motor (docs/mission.md): the middle-left motor wears,
    // then the same motor fails.
    LONGS_EQUAL(2, s.faults.size());
    CHECK(FaultType::kMotorDegradation == s.faults[0].type);
    LONGS_EQUAL(1, s.faults[0].wheel);  // file wheel 2: middle-left
    DOUBLES_EQUAL(1.4, s.faults[0].value, 0.0);
    CHECK_EQUAL(79 * kSec, s.faults[0].at);
    CHECK(FaultType::kMotorFailure == s.faults[1].type);
    LONGS_EQUAL(1, s.faults[1].wheel);  // the same motor
    CHECK_EQUAL(87 * kSec, s.faults[1].at);
    DOUBLES_EQUAL(0.0005, s.devices.imu.biasRadS, 0.0);
    DOUBLES_EQUAL(kPi / 3.0, s.devices.hazard.halfFovRad, 1e-12);
}

TEST(SimScenario, TheInvalidExampleFileIsRejectedWithItsReason) {
    Scenario s;
    std::string error;
    CHECK_FALSE(tryLoadScenarioFile("unit_test/sim_stub/scenario/data/invalid_scenario.toml", &s, &error));
    STRCMP_EQUAL(
        "unit_test/sim_stub/scenario/data/invalid_scenario.toml: obstacles[1].vertices: polygon must be convex and "
        "counter-clockwise",
        error.c_str());
}

TEST(SimScenario, AMissingFileIsReported) {
    Scenario s;
    std::string error;
    CHECK_FALSE(tryLoadScenarioFile("no/such/scenario.toml", &s, &error));
    STRCMP_EQUAL("no/such/scenario.toml: cannot open the file", error.c_str());
}

TEST(SimScenario, TheMinimalFileTakesEveryDefault) {
    const Scenario s = parseScenario(kBase, "min.toml");
    const RoverParams rover;
    const DeviceParams devices;
    STRCMP_EQUAL("min.toml", s.name.c_str());
    DOUBLES_EQUAL(60.0, s.durationS, 0.0);
    DOUBLES_EQUAL(rover.trackWidthM, s.rover.trackWidthM, 0.0);
    DOUBLES_EQUAL(rover.skidFactor, s.rover.skidFactor, 0.0);
    DOUBLES_EQUAL(devices.imu.noiseSigmaRadS, s.devices.imu.noiseSigmaRadS, 0.0);
    DOUBLES_EQUAL(devices.hazard.rangeM, s.devices.hazard.rangeM, 0.0);
    DOUBLES_EQUAL(devices.positionFix.sigmaM, s.devices.positionFix.sigmaM, 0.0);
    DOUBLES_EQUAL(0.9, s.battery.initialSoc, 0.0);
    CHECK(SolarProfile::kConstant == s.solar.profile);
}

TEST(SimScenario, EveryFaultTypeParses) {
    const Scenario s = parseScenario(kBase + R"(
[[faults]]
type = "motor_degradation"
at_s = 1
wheel = 1
current_factor = 2
[[faults]]
type = "motor_failure"
at_s = 2.5
wheel = 6
[[faults]]
type = "drive_heartbeat_loss"
at_s = 3
wheel = 3
duration_s = 0.5
[[faults]]
type = "drive_crash"
at_s = 4
wheel = 4
[[faults]]
type = "drive_crash"
at_s = 4
wheel = 5
restart_at_s = 9
[[faults]]
type = "sensor_dropout"
at_s = 5
device = "position_fix"
until_s = 7
[[faults]]
type = "device_crash"
at_s = 6
device = "hazard"
restart_at_s = 8
[[faults]]
type = "imu_bias_step"
at_s = 7
delta_rad_s = -0.01
[[faults]]
type = "bus_fault"
at_s = 8
action = "corrupt"
cob_id = 0x185
byte = 2
xor = 0x0F
frames = 3
[[faults]]
type = "bus_fault"
at_s = 8
action = "delay"
cob_id = 0x700
mask = 0x780
delay_s = 0.25
[[faults]]
type = "babbling_node"
at_s = 9
cob_id = 0x001
duration_s = 0.5
)",
                                     "faults.toml");
    LONGS_EQUAL(11, s.faults.size());
    const FaultSpec* f = s.faults.data();
    CHECK(FaultType::kMotorDegradation == f[0].type);
    LONGS_EQUAL(0, f[0].wheel);
    DOUBLES_EQUAL(2.0, f[0].value, 0.0);
    CHECK_EQUAL(2500 * core::kNsPerMs, f[1].at);
    LONGS_EQUAL(5, f[1].wheel);
    CHECK_EQUAL(3500 * core::kNsPerMs, f[2].until);
    CHECK_EQUAL(kNever, f[3].until);  // a crash with no restart
    CHECK_EQUAL(9 * kSec, f[4].until);
    CHECK(SimDevice::kPositionFix == f[5].device);
    CHECK_EQUAL(7 * kSec, f[5].until);
    CHECK(SimDevice::kHazard == f[6].device);
    DOUBLES_EQUAL(-0.01, f[7].value, 0.0);
    CHECK(hal::CanFaultKind::kCorrupt == f[8].busRule.kind);
    LONGS_EQUAL(0x185, f[8].busRule.id);
    LONGS_EQUAL(0x7FF, f[8].busRule.mask);
    LONGS_EQUAL(3, f[8].busRule.count);
    LONGS_EQUAL(2, f[8].busRule.corruptByte);
    LONGS_EQUAL(0x0F, f[8].busRule.corruptXor);
    CHECK(hal::CanFaultKind::kDelay == f[9].busRule.kind);
    LONGS_EQUAL(0x780, f[9].busRule.mask);
    CHECK_EQUAL(250 * core::kNsPerMs, f[9].busRule.delay);
    LONGS_EQUAL(1, f[9].busRule.count);
    LONGS_EQUAL(0x001, f[10].cobId);
    DOUBLES_EQUAL(kDefaultBabbleRateHz, f[10].value, 0.0);
    CHECK_EQUAL(9500 * core::kNsPerMs, f[10].until);
}

TEST(SimScenario, BadScenariosAreRejectedWithSpecificMessages) {
    struct Case {
        std::string text;
        const char* message;
    };
    const std::string obstacle = "\n[[obstacles]]\nid = 1\nknown = false\n";
    const std::vector<Case> cases = {
        {kBase + obstacle + "vertices = [[2.0, 0.0], [4.0, 0.0], [3.0, 1.0], [4.0, 2.0], [2.0, 2.0]]",
         "inline.toml: obstacles[0].vertices: polygon must be convex and counter-clockwise"},
        {kBase + obstacle + "vertices = [[2.0, 0.0], [2.0, 1.0], [3.0, 1.0], [3.0, 0.0]]",
         "inline.toml: obstacles[0].vertices: polygon must be convex and counter-clockwise"},
        {kBase + obstacle + "vertices = [[2.0, 0.0], [3.0, 0.0]]",
         "inline.toml: obstacles[0].vertices: needs 3 to 16 vertices (got 2)"},
        {kBase + obstacle + "vertices = [[2.0, 0.0], [30.0, 0.0], [3.0, 1.0]]",
         "inline.toml: obstacles[0].vertices[1]: (30, 0) is outside the map"},
        {kBase + obstacle + "vertices = [[2.0, 0.0], [3.0, 0.0], [3.0]]",
         "inline.toml: obstacles[0].vertices[2]: must be a pair [x, y] of numbers in metres"},
        {kBase + obstacle + "vertices = [[0.5, -0.5], [1.5, -0.5], [1.5, 0.5], [0.5, 0.5]]",
         "inline.toml: start: rover footprint (radius 0.6 m) overlaps obstacle 1"},
        {kBase + obstacle + "vertices = [[2.0, 0.0], [3.0, 0.0], [3.0, 1.0]]" + obstacle +
             "vertices = [[5.0, 0.0], [6.0, 0.0], [6.0, 1.0]]",
         "inline.toml: obstacles[1].id: 1 is already used by obstacles[0]"},
        {kBase + "\n[rover]\nwheel_radus = 0.1\n", "inline.toml: rover.wheel_radus: unknown key"},
        {"sead = 4\n" + kBase, "inline.toml: sead: unknown key"},
        {kBase + "\n[devices.imu]\nsigma = 0.1\n", "inline.toml: devices.imu.sigma: unknown key"},
        {kBase + "\n[rover]\nradius_m = -0.5\n", "inline.toml: rover.radius_m: must be > 0 (got -0.5)"},
        {kBase + "\n[rover]\nskid_factor = 0.5\n", "inline.toml: rover.skid_factor: must be in [1, 10] (got 0.5)"},
        {kBase + "\n[rover]\nmass_kg = \"heavy\"\n", "inline.toml: rover.mass_kg: must be a number (got a string)"},
        {kBase + "\n[rover]\ndrive_nodes = [1, 2, 3, 4, 5]\n",
         "inline.toml: rover.drive_nodes: must list 6 node ids (got 5)"},
        {kBase + "\n[rover]\ndrive_nodes = [1, 2, 0x21, 4, 5, 6]\n",
         "inline.toml: rover.drive_nodes[2]: node 33 belongs to an RSE device (0x20-0x25)"},
        {kBase + "\n[rover]\ndrive_nodes = [1, 2, 3, 4, 5, 0x25]\n",
         "inline.toml: rover.drive_nodes[5]: node 37 belongs to an RSE device (0x20-0x25)"},
        {kBase + "\n[rover]\ndrive_nodes = [1, 2, 3, 4, 5, 1]\n",
         "inline.toml: rover.drive_nodes[5]: node 1 is listed twice"},
        {kBase + "\n[battery]\ninitial_soc = 1.5\n",
         "inline.toml: battery.initial_soc: must be in [0, 1] (got 1.5)"},
        {kBase + "\n[solar]\nprofile = \"night\"\n",
         "inline.toml: solar.profile: unknown profile \"night\" (expected constant or day)"},
        {kBase + "\n[devices.hazard]\nhalf_fov_deg = 120\n",
         "inline.toml: devices.hazard.half_fov_deg: must be in (0, 90] (got 120)"},
        {"[map]\nx_min_m = -1\nx_max_m = 1\ny_min_m = -1\ny_max_m = 1\n[start]\nx_m = 0\ny_m = 0\n",
         "inline.toml: seed: missing (required)"},
        {"seed = \"one\"\n", "inline.toml: seed: must be an integer (got a string)"},
        {"seed = 1\n[map]\nx_min_m = 5\nx_max_m = 1\ny_min_m = -1\ny_max_m = 1\n",
         "inline.toml: map.x_max_m: must be greater than x_min_m (5)"},
        {"seed = 1\n[map]\nx_min_m = -1\nx_max_m = 1\ny_min_m = -1\ny_max_m = 1\n[start]\nx_m = 0.8\ny_m = 0\n",
         "inline.toml: start: rover footprint (radius 0.6 m) at (0.8, 0) is not inside the map"},
        {kBase + "\n[[faults]]\ntype = \"motor_failure\"\nat_s = 10\nwheel = 1\n"
                 "[[faults]]\ntype = \"motor_failure\"\nat_s = 5\nwheel = 2\n",
         "inline.toml: faults[1].at_s: 5 is earlier than the previous fault's 10: faults must be listed in time "
         "order"},
        {kBase + "\n[[faults]]\ntype = \"motor_failure\"\nat_s = 1\nwheel = 7\n",
         "inline.toml: faults[0].wheel: must be 1..6 (got 7)"},
        {kBase + "\n[[faults]]\ntype = \"motor_failure\"\nat_s = 1\nwheel = 0\n",
         "inline.toml: faults[0].wheel: must be 1..6 (got 0)"},
        {kBase + "\n[[faults]]\ntype = \"sensor_dropout\"\nat_s = 1\ndevice = \"lidar\"\nduration_s = 1\n",
         "inline.toml: faults[0].device: unknown device \"lidar\" (expected imu, power, hazard, position_fix, grinder or camera)"},
        {kBase + "\n[[faults]]\ntype = \"sensor_dropout\"\nat_s = 1\ndevice = \"imu\"\n",
         "inline.toml: faults[0]: needs duration_s or until_s"},
        {kBase + "\n[[faults]]\ntype = \"sensor_dropout\"\nat_s = 1\ndevice = \"imu\"\nduration_s = 1\nuntil_s = 3\n",
         "inline.toml: faults[0]: give duration_s or until_s, not both"},
        {kBase + "\n[[faults]]\ntype = \"sensor_dropout\"\nat_s = 5\ndevice = \"imu\"\nuntil_s = 4\n",
         "inline.toml: faults[0].until_s: must be after at_s (5) (got 4)"},
        {kBase + "\n[[faults]]\ntype = \"imu_bias_step\"\nat_s = 1\ndelta_rad_s = 0.1\nwheel = 2\n",
         "inline.toml: faults[0].wheel: unknown key for fault type imu_bias_step"},
        {kBase + "\n[[faults]]\ntype = \"bus_fault\"\nat_s = 1\naction = \"drop\"\ncob_id = 0x181\ndelay_s = 1\n",
         "inline.toml: faults[0].delay_s: unknown key for bus_fault action \"drop\""},
        {kBase + "\n[[faults]]\ntype = \"bus_fault\"\nat_s = 1\naction = \"drop\"\ncob_id = 0x800\n",
         "inline.toml: faults[0].cob_id: must be an 11-bit CAN id 0..0x7FF (got 2048)"},
        {kBase + "\n[[faults]]\ntype = \"meteor\"\nat_s = 1\n",
         "inline.toml: faults[0].type: unknown fault type \"meteor\" (expected motor_degradation, motor_failure, "
         "drive_heartbeat_loss, drive_crash, sensor_dropout, device_crash, imu_bias_step, bus_fault, "
         "babbling_node, position_fix_outlier, motor_overheat, drive_fault, slide, task_stall or "
         "instrument_failure)"},
        {kBase + "\n[[faults]]\ntype = \"motor_degradation\"\nat_s = -1\nwheel = 1\ncurrent_factor = 2\n",
         "inline.toml: faults[0].at_s: must be in [0, 1e+07] (got -1)"},
        {kBase + "\n[[faults]]\ntype = \"motor_degradation\"\nat_s = 1\nwheel = 1\n",
         "inline.toml: faults[0].current_factor: missing (required)"},
    };
    for (const Case& c : cases) {
        const std::string got = errorOf(c.text);
        STRCMP_EQUAL_TEXT(c.message, got.c_str(), c.text.c_str());
    }
}

TEST(SimScenario, TomlSyntaxErrorsGiveTheLineAndColumn) {
    const std::string got = errorOf("seed = 1\n[map\n");
    CHECK_TEXT(got.rfind("inline.toml:2:", 0) == 0, got.c_str());
}

TEST(SimScenario, TheEstimatorBenchmarkScenarioLoadsAndItsSeedCanBeSet) {
    Scenario s;
    std::string error;
    CHECK_TRUE_TEXT(tryLoadScenarioFile("sim_stub/scenarios/estimator_drive.toml", &s, &error), error.c_str());
    STRCMP_EQUAL("estimator_drive", s.name.c_str());
    LONGS_EQUAL(1, s.seed);
    DOUBLES_EQUAL(300.0, s.durationS, 0.0);
    DOUBLES_EQUAL(-150.0, s.map.xMin, 0.0);
    DOUBLES_EQUAL(150.0, s.map.xMax, 0.0);
    DOUBLES_EQUAL(-150.0, s.map.yMin, 0.0);
    DOUBLES_EQUAL(150.0, s.map.yMax, 0.0);
    LONGS_EQUAL(0, s.obstacles.size());
    LONGS_EQUAL(0, s.faults.size());
    DOUBLES_EQUAL(0.0, s.start.x, 0.0);
    DOUBLES_EQUAL(0.0, s.start.y, 0.0);
    DOUBLES_EQUAL(0.0, s.start.theta, 0.0);
    DOUBLES_EQUAL(0.05, s.rover.slipSigma, 0.0);
    DOUBLES_EQUAL(0.002, s.devices.imu.noiseSigmaRadS, 0.0);
    DOUBLES_EQUAL(0.003, s.devices.imu.biasRadS, 0.0);
    DOUBLES_EQUAL(0.05, s.devices.positionFix.sigmaM, 0.0);
    DOUBLES_EQUAL(0.005, s.devices.positionFix.headingSigmaRad, 0.0);
    DOUBLES_EQUAL(0.02, s.drives.currentSigmaA, 0.0);
    DOUBLES_EQUAL(0.0, s.drives.velocitySigmaRadS, 0.0);
    s.seed = 1234;  // what the benchmark does per run: a plain member
    LONGS_EQUAL(1234, s.worldConfig().seed);
}

TEST(SimScenario, DriveNoiseKeysParseAndDefaultToZero) {
    const Scenario none = parseScenario(kBase, "min.toml");
    DOUBLES_EQUAL(0.0, none.drives.currentSigmaA, 0.0);
    DOUBLES_EQUAL(0.0, none.drives.velocitySigmaRadS, 0.0);
    const Scenario s =
        parseScenario(kBase + "\n[drives]\ncurrent_sigma_a = 0.02\nvelocity_sigma_rad_s = 1\n", "drives.toml");
    DOUBLES_EQUAL(0.02, s.drives.currentSigmaA, 0.0);
    DOUBLES_EQUAL(1.0, s.drives.velocitySigmaRadS, 0.0);
    const Scenario zero = parseScenario(kBase + "\n[drives]\ncurrent_sigma_a = 0\n", "drives.toml");
    DOUBLES_EQUAL(0.0, zero.drives.currentSigmaA, 0.0);
}

TEST(SimScenario, PositionFixOutliersParseWithDefaults) {
    const Scenario s = parseScenario(kBase + R"(
[[faults]]
type = "position_fix_outlier"
at_s = 12.5
offset_m = 20
[[faults]]
type = "position_fix_outlier"
at_s = 30
offset_m = 0.75
count = 1000
bearing_deg = -90
)",
                                     "outliers.toml");
    LONGS_EQUAL(2, s.faults.size());
    CHECK(FaultType::kPositionFixOutlier == s.faults[0].type);
    STRCMP_EQUAL("position_fix_outlier", toString(s.faults[0].type));
    CHECK_EQUAL(12500 * core::kNsPerMs, s.faults[0].at);
    DOUBLES_EQUAL(20.0, s.faults[0].value, 0.0);
    LONGS_EQUAL(1, s.faults[0].count);
    DOUBLES_EQUAL(0.0, s.faults[0].bearingRad, 0.0);
    CHECK_EQUAL(kNever, s.faults[0].until);
    DOUBLES_EQUAL(0.75, s.faults[1].value, 0.0);
    LONGS_EQUAL(1000, s.faults[1].count);
    DOUBLES_EQUAL(-kPi / 2.0, s.faults[1].bearingRad, 1e-12);
}

TEST(SimScenario, SlidesParseAndBadOnesAreRejectedWithTheKeyPath) {
    const Scenario s = parseScenario(kBase + R"(
[[faults]]
type = "slide"
at_s = 25
offset_m = 2.5
bearing_deg = -90
duration_s = 2
)",
                                     "slide.toml");
    LONGS_EQUAL(1, s.faults.size());
    CHECK(FaultType::kSlide == s.faults[0].type);
    STRCMP_EQUAL("slide", toString(s.faults[0].type));
    CHECK_EQUAL(25 * core::kNsPerSec, s.faults[0].at);
    CHECK_EQUAL(27 * core::kNsPerSec, s.faults[0].until);
    DOUBLES_EQUAL(2.5, s.faults[0].value, 0.0);
    DOUBLES_EQUAL(-kPi / 2.0, s.faults[0].bearingRad, 1e-12);
    const std::string head = kBase + "\n[[faults]]\ntype = \"slide\"\nat_s = 1\n";
    STRCMP_EQUAL("inline.toml: faults[0]: needs duration_s or until_s", errorOf(head + "offset_m = 1\n").c_str());
    STRCMP_EQUAL("inline.toml: faults[0].offset_m: missing (required)", errorOf(head + "duration_s = 1\n").c_str());
    STRCMP_CONTAINS("faults[0].offset_m", errorOf(head + "offset_m = 0\nduration_s = 1\n").c_str());
    STRCMP_CONTAINS("faults[0].offset_m", errorOf(head + "offset_m = 101\nduration_s = 1\n").c_str());
    STRCMP_CONTAINS("faults[0].wheel", errorOf(head + "offset_m = 1\nduration_s = 1\nwheel = 2\n").c_str());
}

TEST(SimScenario, BadDriveNoiseAndOutlierKeysAreRejectedWithTheKeyPath) {
    struct Case {
        std::string text;
        const char* message;
    };
    const std::string outlier = "\n[[faults]]\ntype = \"position_fix_outlier\"\nat_s = 1\n";
    const std::vector<Case> cases = {
        {kBase + "\n[drives]\ncurrent_sigma_a = 1.5\n",
         "inline.toml: drives.current_sigma_a: must be in [0, 1] (got 1.5)"},
        {kBase + "\n[drives]\ncurrent_sigma_a = -0.01\n",
         "inline.toml: drives.current_sigma_a: must be in [0, 1] (got -0.01)"},
        {kBase + "\n[drives]\nvelocity_sigma_rad_s = 2\n",
         "inline.toml: drives.velocity_sigma_rad_s: must be in [0, 1] (got 2)"},
        {kBase + "\n[drives]\ncurrent_sigma_a = \"low\"\n",
         "inline.toml: drives.current_sigma_a: must be a number (got a string)"},
        {kBase + "\n[drives]\ncurrent_sigma_ma = 20\n", "inline.toml: drives.current_sigma_ma: unknown key"},
        {"drives = 3\n" + kBase, "inline.toml: drives: must be a table (got an integer)"},
        {kBase + outlier, "inline.toml: faults[0].offset_m: missing (required)"},
        {kBase + outlier + "offset_m = 0\n", "inline.toml: faults[0].offset_m: must be in (0, 1000] (got 0)"},
        {kBase + outlier + "offset_m = 1000.5\n",
         "inline.toml: faults[0].offset_m: must be in (0, 1000] (got 1000.5)"},
        {kBase + outlier + "offset_m = 5\ncount = 0\n", "inline.toml: faults[0].count: must be 1..1000 (got 0)"},
        {kBase + outlier + "offset_m = 5\ncount = 1001\n",
         "inline.toml: faults[0].count: must be 1..1000 (got 1001)"},
        {kBase + outlier + "offset_m = 5\ncount = 2.5\n",
         "inline.toml: faults[0].count: must be an integer (got a floating-point number)"},
        {kBase + outlier + "offset_m = 5\nbearing_deg = 400\n",
         "inline.toml: faults[0].bearing_deg: must be in [-360, 360] (got 400)"},
        {kBase + outlier + "offset_m = 5\ndevice = \"position_fix\"\n",
         "inline.toml: faults[0].device: unknown key for fault type position_fix_outlier"},
        {kBase + outlier + "offset_m = 5\nduration_s = 1\n",
         "inline.toml: faults[0].duration_s: unknown key for fault type position_fix_outlier"},
    };
    for (const Case& c : cases) {
        const std::string got = errorOf(c.text);
        STRCMP_EQUAL_TEXT(c.message, got.c_str(), c.text.c_str());
    }
}

// task_stall: the flight task by rate-group row or by the name TASK_TIMING
// gives it; an optional end (duration_s or until_s) when the schedule enables
// it again, none when only fault protection may.
TEST(SimScenario, TaskStallsParseByRowOrByNameWithAnOptionalEnd) {
    const Scenario s = parseScenario(kBase + R"(
[[faults]]
type = "task_stall"
at_s = 2
task = "habitual"
[[faults]]
type = "task_stall"
at_s = 3
task = 11
duration_s = 1.5
[[faults]]
type = "task_stall"
at_s = 4
task = "manual_drive"
until_s = 9
)",
                                     "stall.toml");
    LONGS_EQUAL(3, s.faults.size());
    const FaultSpec* f = s.faults.data();
    CHECK(FaultType::kTaskStall == f[0].type);
    STRCMP_EQUAL("task_stall", toString(f[0].type));
    STRCMP_EQUAL("habitual", f[0].taskName.c_str());
    CHECK_EQUAL(2 * kSec, f[0].at);
    CHECK_EQUAL(kNever, f[0].until);  // no end: fault protection must restart it
    CHECK(f[1].taskName.empty());
    LONGS_EQUAL(11, f[1].taskRow);
    CHECK_EQUAL(4500 * core::kNsPerMs, f[1].until);
    STRCMP_EQUAL("manual_drive", f[2].taskName.c_str());
    CHECK_EQUAL(9 * kSec, f[2].until);
}

TEST(SimScenario, BadTaskStallsAreRejectedWithSpecificMessages) {
    const std::string head = kBase + "\n[[faults]]\ntype = \"task_stall\"\nat_s = 5\n";
    const struct {
        std::string text;
        const char* message;
    } cases[] = {
        {head, "inline.toml: faults[0].task: missing (required)"},
        {head + "task = 32\n", "inline.toml: faults[0].task: a row must be 0..31 (got 32)"},
        {head + "task = -1\n", "inline.toml: faults[0].task: a row must be 0..31 (got -1)"},
        {head + "task = 2.5\n",
         "inline.toml: faults[0].task: must be a rate-group row (integer) or a task name (string) (got a "
         "floating-point number)"},
        {head + "task = \"\"\n",
         "inline.toml: faults[0].task: \"\" is not a task name (1 to 15 of a-z, 0-9, _; as TASK_TIMING names it)"},
        {head + "task = \"Habitual\"\n",
         "inline.toml: faults[0].task: \"Habitual\" is not a task name (1 to 15 of a-z, 0-9, _; as TASK_TIMING "
         "names it)"},
        {head + "task = \"a_task_name_too_long\"\n",
         "inline.toml: faults[0].task: \"a_task_name_too_long\" is not a task name (1 to 15 of a-z, 0-9, _; as "
         "TASK_TIMING names it)"},
        {head + "task = 3\nuntil_s = 4\n", "inline.toml: faults[0].until_s: must be after at_s (5) (got 4)"},
        {head + "task = 3\nduration_s = 1\nuntil_s = 8\n", "inline.toml: faults[0]: give duration_s or until_s, not both"},
        {head + "task = 3\nwheel = 1\n", "inline.toml: faults[0].wheel: unknown key for fault type task_stall"},
    };
    for (const auto& c : cases) {
        const std::string got = errorOf(c.text);
        STRCMP_EQUAL_TEXT(c.message, got.c_str(), c.text.c_str());
    }
}

TEST(SimScenario, TheHabitualStallScenarioLoadsWithItsOneTaskStall) {
    Scenario s;
    std::string error;
    CHECK_TRUE_TEXT(tryLoadScenarioFile("sim_stub/scenarios/habitual_stall.toml", &s, &error), error.c_str());
    LONGS_EQUAL(1, s.faults.size());
    CHECK(FaultType::kTaskStall == s.faults[0].type);
    STRCMP_EQUAL("habitual", s.faults[0].taskName.c_str());
    CHECK_EQUAL(20 * kSec, s.faults[0].at);
    CHECK_EQUAL(kNever, s.faults[0].until);
    LONGS_EQUAL(5, s.obstacles.size());  // the demo's site
}

TEST(SimScenario, ScienceTargetsInstrumentTimingAndInstrumentFailuresParse) {
    const Scenario s = parseScenario(kBase + R"(
[[targets]]
id = 1
x_m = 5.0
y_m = -2.5
[[targets]]
id = 255
x_m = -9.0
y_m = 9.0
[devices.grinder]
sample_s = 30
dig_s = 60.5
duration_sigma = 0.2
reach_m = 2.0
[devices.camera]
image_s = 4
range_m = 8
[[faults]]
type = "instrument_failure"
at_s = 10
device = "grinder"
[[faults]]
type = "instrument_failure"
at_s = 12
device = "camera"
fault_code = 0xFF
silent = true
duration_s = 3
[[faults]]
type = "sensor_dropout"
at_s = 13
device = "camera"
duration_s = 1
[[faults]]
type = "device_crash"
at_s = 14
device = "grinder"
restart_at_s = 15
)",
                                     "instruments.toml");
    LONGS_EQUAL(2, s.targets.size());
    LONGS_EQUAL(1, s.targets[0].id);
    DOUBLES_EQUAL(5.0, s.targets[0].position.x, 0.0);
    DOUBLES_EQUAL(-2.5, s.targets[0].position.y, 0.0);
    LONGS_EQUAL(255, s.targets[1].id);
    DOUBLES_EQUAL(30.0, s.devices.grinder.sampleS, 0.0);
    DOUBLES_EQUAL(60.5, s.devices.grinder.digS, 0.0);
    DOUBLES_EQUAL(0.2, s.devices.grinder.durationSigma, 0.0);
    DOUBLES_EQUAL(2.0, s.devices.grinder.reachM, 0.0);
    DOUBLES_EQUAL(4.0, s.devices.camera.imageS, 0.0);
    DOUBLES_EQUAL(8.0, s.devices.camera.reachM, 0.0);
    DOUBLES_EQUAL(0.05, s.devices.camera.durationSigma, 0.0);  // default
    LONGS_EQUAL(4, s.faults.size());
    CHECK(FaultType::kInstrumentFailure == s.faults[0].type);
    CHECK(SimDevice::kGrinder == s.faults[0].device);
    LONGS_EQUAL(1, s.faults[0].faultCode);  // default
    CHECK_FALSE(s.faults[0].silent);
    CHECK_EQUAL(kNever, s.faults[0].until);  // no end: failed for good
    CHECK(SimDevice::kCamera == s.faults[1].device);
    LONGS_EQUAL(0xFF, s.faults[1].faultCode);
    CHECK_TRUE(s.faults[1].silent);
    CHECK_EQUAL(15 * kSec, s.faults[1].until);
    CHECK(SimDevice::kCamera == s.faults[2].device);
    CHECK(SimDevice::kGrinder == s.faults[3].device);
    // Without a [devices.*] table the defaults hold: the grinder's reach, the camera's range.
    const Scenario plain = parseScenario(kBase, "plain.toml");
    LONGS_EQUAL(0, plain.targets.size());
    DOUBLES_EQUAL(150.0, plain.devices.grinder.sampleS, 0.0);
    DOUBLES_EQUAL(1.5, plain.devices.grinder.reachM, 0.0);
    DOUBLES_EQUAL(40.0, plain.devices.camera.imageS, 0.0);
    DOUBLES_EQUAL(5.0, plain.devices.camera.reachM, 0.0);
}

TEST(SimScenario, BadTargetsInstrumentKeysAndInstrumentFailuresAreRejectedWithTheKeyPath) {
    struct Case {
        std::string text;
        const char* message;
    };
    const std::string target = "\n[[targets]]\n";
    const std::string failure = "\n[[faults]]\ntype = \"instrument_failure\"\nat_s = 1\n";
    const std::vector<Case> cases = {
        {kBase + target + "id = 0\nx_m = 1\ny_m = 1\n", "inline.toml: targets[0].id: must be 1..255 (got 0)"},
        {kBase + target + "id = 256\nx_m = 1\ny_m = 1\n", "inline.toml: targets[0].id: must be 1..255 (got 256)"},
        {kBase + target + "id = 3\nx_m = 1\ny_m = 1\n" + target + "id = 3\nx_m = 2\ny_m = 2\n",
         "inline.toml: targets[1].id: 3 is already used by targets[0]"},
        {kBase + target + "id = 3\nx_m = 11\ny_m = 1\n", "inline.toml: targets[0]: (11, 1) is not inside the map"},
        {kBase + target + "id = 3\nx_m = 1\n", "inline.toml: targets[0].y_m: missing (required)"},
        {kBase + target + "id = 3\nx_m = 1\ny_m = 1\nz_m = 0\n", "inline.toml: targets[0].z_m: unknown key"},
        {"targets = 4\n" + kBase, "inline.toml: targets: must be an array of tables ([[targets]]) (got an integer)"},
        {kBase + "\n[devices.grinder]\nimage_s = 3\n", "inline.toml: devices.grinder.image_s: unknown key"},
        {kBase + "\n[devices.camera]\nreach_m = 3\n", "inline.toml: devices.camera.reach_m: unknown key"},
        {kBase + "\n[devices.grinder]\nsample_s = 0\n",
         "inline.toml: devices.grinder.sample_s: must be in (0, 6553.5] (got 0)"},
        {kBase + "\n[devices.camera]\nimage_s = 7000\n",
         "inline.toml: devices.camera.image_s: must be in (0, 6553.5] (got 7000)"},
        {kBase + "\n[devices.grinder]\nduration_sigma = 0.6\n",
         "inline.toml: devices.grinder.duration_sigma: must be in [0, 0.5] (got 0.6)"},
        {kBase + "\n[devices.camera]\nrange_m = -1\n", "inline.toml: devices.camera.range_m: must be in (0, 100] (got -1)"},
        {kBase + failure + "device = \"imu\"\n",
         "inline.toml: faults[0].device: unknown instrument \"imu\" (expected grinder or camera)"},
        {kBase + failure, "inline.toml: faults[0].device: missing (required)"},
        {kBase + failure + "device = \"camera\"\nfault_code = 0\n",
         "inline.toml: faults[0].fault_code: must be 1..255 (got 0)"},
        {kBase + failure + "device = \"camera\"\nfault_code = 256\n",
         "inline.toml: faults[0].fault_code: must be 1..255 (got 256)"},
        {kBase + failure + "device = \"camera\"\nsilent = 1\n",
         "inline.toml: faults[0].silent: must be true or false (got an integer)"},
        {kBase + failure + "device = \"camera\"\nrestart_at_s = 3\n",
         "inline.toml: faults[0].restart_at_s: unknown key for fault type instrument_failure"},
        {kBase + failure + "device = \"camera\"\nduration_s = 1\nuntil_s = 3\n",
         "inline.toml: faults[0]: give duration_s or until_s, not both"},
    };
    for (const Case& c : cases) {
        const std::string got = errorOf(c.text);
        STRCMP_EQUAL_TEXT(c.message, got.c_str(), c.text.c_str());
    }
}

TEST(SimScenario, TheTwoTargetsScenarioLoadsWithItsTargetsInstrumentsAndGrinderFailure) {
    const Scenario s = loadScenarioFile("sim_stub/scenarios/two_targets.toml");
    STRCMP_EQUAL("two_targets", s.name.c_str());
    LONGS_EQUAL(2, s.targets.size());
    LONGS_EQUAL(1, s.targets[0].id);
    DOUBLES_EQUAL(10.0, s.targets[0].position.x, 0.0);
    DOUBLES_EQUAL(0.0, s.targets[0].position.y, 0.0);
    LONGS_EQUAL(2, s.targets[1].id);
    DOUBLES_EQUAL(20.0, s.targets[1].position.x, 0.0);
    DOUBLES_EQUAL(5.0, s.targets[1].position.y, 0.0);
    // Both targets stand clear of every rock by more than the rover's footprint,
    // so the rover can park within reach of each.
    for (const ScienceTarget& t : s.targets) {
        for (const Obstacle& o : s.obstacles) {
            CHECK(distanceToPolygon(t.position, o.shape) > s.rover.radiusM);
        }
    }
    DOUBLES_EQUAL(150.0, s.devices.grinder.sampleS, 0.0);
    DOUBLES_EQUAL(40.0, s.devices.camera.imageS, 0.0);
    LONGS_EQUAL(1, s.faults.size());
    CHECK(FaultType::kInstrumentFailure == s.faults[0].type);
    CHECK(SimDevice::kGrinder == s.faults[0].device);
    LONGS_EQUAL(0x42, s.faults[0].faultCode);
    CHECK_FALSE(s.faults[0].silent);
    CHECK_EQUAL(240 * kSec, s.faults[0].at);
    CHECK_EQUAL(kNever, s.faults[0].until);
}

// [mission]: the scenario as a mission of its own (rse-demo --scenario FILE).
TEST(SimScenario, AMissionIsAGoalOrAPlanAtARiskBound) {
    const Scenario none = parseScenario(kBase, "none.toml");
    CHECK_FALSE(none.mission.present);
    const Scenario goal = parseScenario(kBase + "\n[mission]\ngoal_x_m = 9\ngoal_y_m = -2.5\nrisk_bound = 1e-6\n",
                                        "goal.toml");
    CHECK_TRUE(goal.mission.present);
    CHECK_TRUE(goal.mission.hasGoal);
    DOUBLES_EQUAL(9.0, goal.mission.goalX, 0.0);
    DOUBLES_EQUAL(-2.5, goal.mission.goalY, 0.0);
    DOUBLES_EQUAL(1e-6, goal.mission.riskBound, 0.0);
    CHECK_TRUE(goal.mission.planText.empty());
    const Scenario defaultRisk = parseScenario(kBase + "\n[mission]\ngoal_x_m = 1\ngoal_y_m = 1\n", "d.toml");
    DOUBLES_EQUAL(kDefaultMissionRiskBound, defaultRisk.mission.riskBound, 0.0);
    // A plan file is named from the scenario file's folder, and read.
    const Scenario plan = parseScenario(kBase + "\n[mission]\nplan_file = \"../../fuzz/corpus/plan/two_targets.plan\"\n",
                                        "unit_test/sim_stub/scenario/plan.toml");
    CHECK_TRUE(plan.mission.present);
    CHECK_FALSE(plan.mission.hasGoal);
    STRCMP_EQUAL("unit_test/fuzz/corpus/plan/two_targets.plan", plan.mission.planFile.c_str());
    CHECK_TRUE(plan.mission.planText.rfind("# Two targets", 0) == 0);
    CHECK(plan.mission.planText.find("\nend\n") != std::string::npos);
}

TEST(SimScenario, BadMissionsAreRejectedWithTheKeyPath) {
    struct Case {
        std::string text;
        const char* message;
    };
    const std::string m = kBase + "\n[mission]\n";
    const std::vector<Case> cases = {
        {m + "goal_x_m = 1\ngoal_y_m = 1\ngoal_z_m = 0\n", "inline.toml: mission.goal_z_m: unknown key"},
        {m, "inline.toml: mission: needs a goal (goal_x_m, goal_y_m) or a plan_file"},
        {m + "risk_bound = 1e-3\n", "inline.toml: mission: needs a goal (goal_x_m, goal_y_m) or a plan_file"},
        {m + "goal_x_m = 1\n", "inline.toml: mission.goal_y_m: missing (a goal needs both; goal_x_m is given)"},
        {m + "goal_y_m = 1\n", "inline.toml: mission.goal_x_m: missing (a goal needs both; goal_y_m is given)"},
        {m + "goal_x_m = 1\ngoal_y_m = 1\nplan_file = \"p.plan\"\n",
         "inline.toml: mission: give a goal (goal_x_m, goal_y_m) or a plan_file, not both"},
        {m + "goal_x_m = 11\ngoal_y_m = 0\n", "inline.toml: mission: goal (11, 0) is outside the map"},
        {m + "goal_x_m = \"east\"\ngoal_y_m = 0\n", "inline.toml: mission.goal_x_m: must be a number (got a string)"},
        {m + "goal_x_m = 1\ngoal_y_m = 0\nrisk_bound = 0.5\n",
         "inline.toml: mission.risk_bound: must be in [1e-09, 0.49] (got 0.5)"},
        {m + "goal_x_m = 1\ngoal_y_m = 0\nrisk_bound = 0\n",
         "inline.toml: mission.risk_bound: must be in [1e-09, 0.49] (got 0)"},
        {m + "plan_file = 7\n", "inline.toml: mission.plan_file: must be a string (got an integer)"},
        {m + "plan_file = \"\"\n", "inline.toml: mission.plan_file: must name a plan file"},
        {m + "plan_file = \"no/such.plan\"\n", "inline.toml: mission.plan_file: cannot read 'no/such.plan'"},
        {m + "plan_file = \"/dev/null\"\n", "inline.toml: mission.plan_file: '/dev/null' is empty"},
        {"mission = 3\n" + kBase, "inline.toml: mission: must be a table (got an integer)"},
    };
    for (const Case& c : cases) {
        const std::string got = errorOf(c.text);
        STRCMP_EQUAL_TEXT(c.message, got.c_str(), c.text.c_str());
    }
}

// The scenario files that are missions say what they fly (the suite that
// flies each: unit_test/system/lockstep/test_scenario_suite.cpp).
TEST(SimScenario, TheShippedMissionsAreTheirFilesGoalsAndPlans) {
    const Scenario demo = loadScenarioFile("sim_stub/scenarios/demo_mission.toml");
    CHECK_TRUE(demo.mission.hasGoal);
    DOUBLES_EQUAL(20.0, demo.mission.goalX, 0.0);
    DOUBLES_EQUAL(0.0, demo.mission.goalY, 0.0);
    DOUBLES_EQUAL(1e-3, demo.mission.riskBound, 0.0);
    const Scenario two = loadScenarioFile("sim_stub/scenarios/two_targets.toml");
    CHECK_FALSE(two.mission.hasGoal);
    STRCMP_EQUAL("unit_test/fuzz/corpus/plan/two_targets.plan", two.mission.planFile.c_str());
    CHECK(two.mission.planText.find("plan two_targets\n") != std::string::npos);
    const Scenario estimator = loadScenarioFile("sim_stub/scenarios/estimator_drive.toml");
    CHECK_FALSE(estimator.mission.present);  // a drive profile, not a mission
}

// [field]: a generated rock field on the map, clear of the start and the goal;
// its errors named.
TEST(SimScenario, AFieldAddsGeneratedRocksClearOfTheStartAndTheGoal) {
    Scenario s;
    std::string error;
    CHECK_TRUE_TEXT(tryLoadScenarioFile("sim_stub/scenarios/rock_field_100m.toml", &s, &error), error.c_str());
    CHECK_TRUE(s.field.present);
    DOUBLES_EQUAL(0.10, s.field.rocks.k, 0.0);
    const FieldCounts c = fieldCounts(s);
    CHECK(c.rocks >= 300);
    LONGS_EQUAL(c.rocks, s.obstacles.size());
    const Vec2 start{s.start.x, s.start.y};
    const Vec2 goal{s.mission.goalX, s.mission.goalY};
    std::uint32_t lastId = 0;
    for (const Obstacle& o : s.obstacles) {
        CHECK(o.id >= kFirstFieldRockId);
        CHECK(o.id > lastId);
        lastId = o.id;
        CHECK(isConvexCcw(o.shape.v.data(), o.shape.n));
        for (std::size_t k = 0; k < o.shape.n; ++k) {
            CHECK(s.map.contains(o.shape.v[k]));
        }
        CHECK(distanceToPolygon(start, o.shape) > s.field.clearM + s.rover.radiusM);
        CHECK(distanceToPolygon(goal, o.shape) > s.field.clearM + s.rover.radiusM);
    }
    CHECK_TRUE(s.usesSiteMap());
    // The same seed, the same field; another seed, another.
    Scenario again;
    CHECK_TRUE(tryLoadScenarioFile("sim_stub/scenarios/rock_field_100m.toml", &again, &error));
    LONGS_EQUAL(s.obstacles.size(), again.obstacles.size());
    DOUBLES_EQUAL(s.obstacles[7].shape.v[0].x, again.obstacles[7].shape.v[0].x, 0.0);
    const Scenario other = parseScenario(kBase + "\n[field]\nk = 0.1\nseed = 2\n", "field.toml");
    CHECK(other.field.rocks.seed == 2);
    CHECK_FALSE(parseScenario(kBase, "min.toml").usesSiteMap());
}

TEST(SimScenario, AFieldsErrorsAreNamed) {
    STRCMP_CONTAINS("field.k", errorOf(kBase + "\n[field]\nseed = 1\n").c_str());
    STRCMP_CONTAINS("field.k", errorOf(kBase + "\n[field]\nk = 0.9\n").c_str());
    STRCMP_CONTAINS("field.max_diameter_m",
                    errorOf(kBase + "\n[field]\nk = 0.1\nmin_diameter_m = 2\nmax_diameter_m = 1\n").c_str());
    STRCMP_CONTAINS("field.seed", errorOf(kBase + "\n[field]\nk = 0.1\nseed = -1\n").c_str());
    STRCMP_CONTAINS("field.colour", errorOf(kBase + "\n[field]\nk = 0.1\ncolour = 1\n").c_str());
}

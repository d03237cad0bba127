// A simulation scenario: everything rse-sim needs to build the world, the
// devices and the fault schedule. Produced by the scenario parser from a TOML
// file (format: sim_stub/scenarios/README.md) or filled in directly by tests.
// Built at start-up only (std::vector and std::string are fine here).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fsw/core/clock.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "sim_stub/devices/hazard_detector_emulator.hpp"
#include "sim_stub/devices/imu_emulator.hpp"
#include "sim_stub/devices/instrument_emulator.hpp"
#include "sim_stub/devices/position_fix_emulator.hpp"
#include "sim_stub/devices/power_monitor_emulator.hpp"
#include "sim_stub/scenario/fault_target.hpp"
#include "sim_stub/scenario/field_rocks.hpp"
#include "sim_stub/world/world.hpp"

namespace rse::sim {

constexpr core::TimeNs kNever = std::numeric_limits<core::TimeNs>::max();
constexpr double kDefaultBabbleRateHz = 8000.0;
constexpr std::size_t kCoarseMapObstacleSlots = 16;   // COARSE_MAP's rock slots (docs/tables.md)  // about a saturated 1 Mbit/s bus of 8-byte frames

enum class FaultType : std::uint8_t {
    kMotorDegradation,  // wheel, value = current factor k
    kMotorFailure,      // wheel
    kDriveHeartbeatLoss,  // wheel, until
    kDriveCrash,        // wheel, until = restart time (kNever: no restart)
    kSensorDropout,     // device, until
    kDeviceCrash,       // device, until = restart time (kNever: no restart)
    kImuBiasStep,       // value = bias step, rad/s
    kBusFault,          // busRule
    kBabblingNode,      // cobId, value = frames per second, until
    kPositionFixOutlier,  // value = offset, m; bearingRad; count = how many fixes
    kMotorOverheat,     // wheel, value = heat gain factor (the motor heats that many times faster)
    kDriveFault,        // wheel, cobId = EMCY code: a one-shot fault a fault reset clears
    kSlide,             // value = offset, m; bearingRad; until = end of the slide
    kTaskStall,         // taskRow or taskName, until = the row enabled again (kNever: never by the schedule)
    kInstrumentFailure, // device (grinder, camera), faultCode, silent, until = healthy again (kNever: never)
};
constexpr FaultType kLastFaultType = FaultType::kInstrumentFailure;
// The names scenario files use ("motor_degradation", ...).
const char* toString(FaultType type);

struct FaultSpec {
    FaultType type = FaultType::kMotorFailure;
    core::TimeNs at = 0;
    core::TimeNs until = kNever;  // end of an interval fault, or a crash's restart
    std::size_t wheel = 0;        // 0..5
    SimDevice device = SimDevice::kImu;
    double value = 0.0;
    hal::CanFaultRule busRule;
    std::uint32_t cobId = 0;
    std::uint32_t count = 1;  // position_fix_outlier: how many fixes
    double bearingRad = 0.0;  // position_fix_outlier, slide: direction of the offset (map frame, CCW from +x)
    std::size_t taskRow = 0;  // task_stall: the flight software's rate-group row, when taskName is empty
    std::string taskName;     // task_stall: the row by its task name (TASK_TIMING.task_name), "" for by taskRow
    std::uint8_t faultCode = 1;  // instrument_failure: the code the instrument reports (1..255)
    bool silent = false;         // instrument_failure: no report, commands ignored (else failed + code)
};

// Measurement noise of the six wheel drives' reports (scenario [drives]; see
// DriveEmulatorConfig). The physical current and speed stay noise-free.
struct DriveNoiseParams {
    double currentSigmaA = 0.0;      // on the reported current actual
    double velocitySigmaRadS = 0.0;  // on the reported velocity actual
    double ambientC = 20.0;          // [drives] ambient_c: what the motors cool to (and start at)
};

struct DeviceParams {
    ImuParams imu;
    PowerMonitorParams power;
    HazardDetectorParams hazard;
    PositionFixParams positionFix;
    InstrumentParams grinder = defaultInstrumentParams(hal::instrument::Kind::kGrinder);
    InstrumentParams camera = defaultInstrumentParams(hal::instrument::Kind::kCamera);
};

// The scenario as a mission of its own ([mission], optional): what rse-demo
// --scenario FILE flies when its command line names no goal. Either a goal
// (a GOTO to goal at riskBound) or a mission plan (planText, sent as PLAN_LOAD
// and PLAN_START after SET_RISK_BOUND riskBound).
constexpr double kDefaultMissionRiskBound = 1e-3;
struct MissionSpec {
    bool present = false;   // the file has a [mission] section
    bool hasGoal = false;   // goal_x_m, goal_y_m given (else planFile)
    double goalX = 0.0;
    double goalY = 0.0;
    double riskBound = kDefaultMissionRiskBound;
    std::string planFile;   // plan_file as read: relative to the scenario file's folder ("" for a goal)
    std::string planText;   // its text
};

struct Scenario {
    std::string source;       // file name (or the name given for inline text)
    std::string name;
    std::string description;
    std::uint64_t seed = 1;   // a program may set it after loading (e.g. one run per seed)
    double durationS = 60.0;  // how long a run of this scenario lasts
    RoverParams rover;
    BatteryParams battery;
    SolarParams solar;
    MapBounds map;
    Pose2 start;
    std::vector<Obstacle> obstacles;     // the file's [[obstacles]], then the [field]'s or the site file's rocks
    FieldSpec field;                     // [field]: a generated rock field (field_rocks.hpp)
    std::string siteFile;                // [site] file: the rocks from a site file (site_file.hpp), as read; "" for none
    std::vector<ScienceTarget> targets;  // what the instruments can work on (ids 1..255, unique)
    DeviceParams devices;
    DriveNoiseParams drives;
    std::vector<FaultSpec> faults;  // in time order (by at)
    MissionSpec mission;

    WorldConfig worldConfig() const;
    // The rover is told of the known rocks with the site map (MAP_LOAD, docs/site_map.md)
    // rather than COARSE_MAP: a [field], a [site] file, or more known rocks than COARSE_MAP's 16.
    bool usesSiteMap() const;
};

}  // namespace rse::sim

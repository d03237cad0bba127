#include "sim_stub/scenario/scenario.hpp"

namespace rse::sim {

const char* toString(SimDevice device) {
    switch (device) {
        case SimDevice::kImu:
            return "imu";
        case SimDevice::kPower:
            return "power";
        case SimDevice::kHazard:
            return "hazard";
        case SimDevice::kPositionFix:
            return "position_fix";
        case SimDevice::kGrinder:
            return "grinder";
        case SimDevice::kCamera:
            return "camera";
    }
    return "?";
}

const char* toString(FaultType type) {
    switch (type) {
        case FaultType::kMotorDegradation:
            return "motor_degradation";
        case FaultType::kMotorFailure:
            return "motor_failure";
        case FaultType::kDriveHeartbeatLoss:
            return "drive_heartbeat_loss";
        case FaultType::kDriveCrash:
            return "drive_crash";
        case FaultType::kSensorDropout:
            return "sensor_dropout";
        case FaultType::kDeviceCrash:
            return "device_crash";
        case FaultType::kImuBiasStep:
            return "imu_bias_step";
        case FaultType::kBusFault:
            return "bus_fault";
        case FaultType::kBabblingNode:
            return "babbling_node";
        case FaultType::kPositionFixOutlier:
            return "position_fix_outlier";
        case FaultType::kMotorOverheat:
            return "motor_overheat";
        case FaultType::kDriveFault:
            return "drive_fault";
        case FaultType::kSlide:
            return "slide";
        case FaultType::kTaskStall:
            return "task_stall";
        case FaultType::kInstrumentFailure:
            return "instrument_failure";
    }
    return "?";
}

WorldConfig Scenario::worldConfig() const {
    WorldConfig c;
    c.rover = rover;
    c.battery = battery;
    c.solar = solar;
    c.map = map;
    c.start = start;
    c.obstacles = obstacles;
    c.seed = seed;
    return c;
}

bool Scenario::usesSiteMap() const {
    std::size_t known = 0;
    for (const Obstacle& o : obstacles) {
        known += o.known ? 1U : 0U;
    }
    return field.present || !siteFile.empty() || known > kCoarseMapObstacleSlots;
}

}  // namespace rse::sim

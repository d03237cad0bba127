// The health monitor's detection rules (IDEA rover executive / cFS Health and
// Safety): each rule turns an input into the raise or clear of a fault id
// (fsw/msg/health_msgs.hpp), with an event on every transition
// (fsw/estimator/health_events.hpp). Pure logic: HealthTask feeds it from the
// bus and publishes FaultStatusMsg.
//
// Detection bounds (frames are the 10 ms minor frames; the health task runs
// after the CAN I/O and pose estimator tasks in the same frame):
//   1..6, 7..10 heartbeat lost: mirrors the heartbeat consumer's verdict in the
//     latest NodeStatusMsg. The consumer declares a node lost in the first frame
//     more than heartbeat_timeout_ms after its last heartbeat was read, so the
//     fault is raised within heartbeat_timeout_ms + 10 ms of the last heartbeat,
//     i.e. within heartbeat_timeout_ms + 20 ms of the node falling silent. It
//     clears in the frame its next heartbeat is read.
//   11..16 drive over-current: |currentA| > drive_overcurrent_a on every
//     DriveStatusMsg (100 Hz) for fault_persist_ms; clears after
//     |currentA| < 0.9 * drive_overcurrent_a held as long. Raised at the first
//     sample at least fault_persist_ms (and at least one sample) after the first
//     over-limit sample: never earlier, and at most fault_persist_ms + 10 ms
//     after it.
//   17 battery low: busVoltageV < battery_low_v held fault_persist_ms on the
//     PowerMsg samples (10 Hz); clears above battery_clear_v held as long.
//   18 bus over-current: busCurrentA > overcurrent_a held fault_persist_ms;
//     clears below 0.9 * overcurrent_a held as long. For 17 and 18 persistence is
//     measured on sample times, so the 10 Hz sampling adds up to 100 ms: raised at
//     most fault_persist_ms + 100 ms after the first sample showing the
//     condition (at the second such sample at the earliest).
//   19 pose uncertain: initialised and positionSigmaM > pose_fault_sigma_m or
//     the estimate flagged inconsistent (fix_reject_limit fixes refused in a
//     row), or not initialised more than first_fix_wait_ms after the health
//     task's first run; clears once initialised, consistent and
//     positionSigmaM < pose_clear_sigma_m.
//     Judged every frame on the latest PoseEstimateMsg; raised (cleared) in the
//     second consecutive frame that shows the condition, so at most 10 ms after
//     the first such estimate (no fix: within first_fix_wait_ms + 20 ms).
//   20..35 task stalled (rate-group row 0..15): now - lastRunEnd >
//     task_stall_periods * (rateDivisor * minor frame), measured from the health
//     task's first run for a task that never ran. Raised within
//     task_stall_periods * period + 10 ms of its last run's end; cleared in the
//     first health run after it runs again (the same frame when its row is above
//     the health task's).
//   46 off the map: an initialised, consistent estimate (sigma <=
//     pose_fault_sigma_m) whose position lies outside the site, the COARSE_MAP
//     bounds; clears once such an estimate lies kOffMapClearMarginM inside
//     them. An uncertain estimate neither raises nor clears it (where the
//     rover stands is then not known well enough to say). Judged every frame
//     on the latest PoseEstimateMsg; raised (cleared) in the second
//     consecutive frame that shows it, as fault 19.
//   40..45 drive over-temperature: a reported (temperatureValid) motor
//     temperature > drive_overtemp_c held fault_persist_ms on the DriveStatusMsg
//     samples; clears below drive_overtemp_c - 15 degC held as long.
//   36..39 sensor stale (DeviceNode IMU, power, hazard, position fix): no
//     data from the device for its stale time (imu_stale_ms, power_stale_ms,
//     hazard_stale_ms, fix_stale_ms), whether its heartbeat goes on (a
//     dropout) or not (a crash also raises 7..10). Data time: the sample's CAN
//     receive time for the IMU, power and fix messages (published only for a
//     new sample); for the hazard detector, whose HazardMsg comes every 100 ms
//     regardless, the time of the first HazardMsg whose detectorFrames moved
//     (up to 100 ms late). A device never heard is judged from the health
//     task's first run. Judged every frame: raised within stale time + 10 ms
//     of the last data (hazard: + 110 ms); cleared in the frame its data is
//     read again (hazard: within 100 ms).
// Every threshold rule needs its condition on at least two samples at different
// times (PersistenceFilter), and the heartbeat and stall rules need a timeout
// to pass, so no fault can change state on every frame and flood the events.
//
// A non-finite (or, for a sigma, negative) value is counted and evented
// (throttled) and carries no information: the rule it feeds keeps its state.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/estimator/fault_book.hpp"
#include "fsw/estimator/persistence_filter.hpp"
#include "fsw/geometry/site_bounds.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/node_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::estimator {

// Rate-group rows the task-stall faults cover (fault ids 20..35).
constexpr std::size_t kWatchedTaskRows = msg::fault::kTaskStalledCount;
static_assert(kWatchedTaskRows == core::kMaxTasks, "one task-stall fault id per rate-group row");

// The thresholds of every rule, taken from the tables at each run.
struct HealthLimits {
    core::TimeNs persist = 0;           // fault_persist_ms
    double driveOvercurrentA = 0.0;     // raise above; clear below 0.9 of it
    double busOvercurrentA = 0.0;       // raise above; clear below 0.9 of it
    double batteryLowV = 0.0;           // raise below
    double batteryClearV = 0.0;         // clear above
    std::uint32_t taskStallPeriods = 0;
    double poseFaultSigmaM = 0.0;       // raise above
    double poseClearSigmaM = 0.0;       // clear below
    core::TimeNs firstFixWait = 0;
    double driveOvertempC = 0.0;        // raise above; clear kOvertempClearMarginC below
    core::TimeNs sensorStale[msg::kDeviceNodeCount] = {};  // by DeviceNode: *_stale_ms
    geometry::SiteBox site;             // COARSE_MAP bounds
};
HealthLimits healthLimitsFrom(const tables::FaultResponseTable& faults, const tables::EstimatorNoiseTable& noise,
                              const tables::CoarseMapTable& site);

// How far inside the site an off-map rover must be before fault 46 clears:
// a rover driving back along the edge must not raise and clear it on the
// estimate's noise.
constexpr double kOffMapClearMarginM = 0.1;

// Fraction of an over-current limit below which the current must fall to clear.
constexpr double kOvercurrentClearFraction = 0.9;
// Degrees below drive_overtemp_c a motor must cool to clear its fault.
// A motor must cool this far below drive_overtemp_c to clear: with the
// drives' ~60 s thermal time constant that is about 20 s of rest, so a rover
// resumed after an over-temperature hold does not reach the limit again at once.
constexpr double kOvertempClearMarginC = 15.0;

class HealthMonitor {
public:
    explicit HealthMonitor(core::EventLog& events) : events_(events) {}

    // The health task's first run: the origin for "never ran" and the first fix wait.
    void start(core::TimeNs now);
    bool started() const { return started_; }

    void onNodeStatus(const msg::NodeStatusMsg& status, core::TimeNs now);
    void onDriveStatus(const msg::DriveStatusMsg& status, const HealthLimits& limits, core::TimeNs now);
    void onPower(const msg::PowerMsg& power, const HealthLimits& limits, core::TimeNs now);
    void onPose(const msg::PoseEstimateMsg& pose);  // kept for checkPose()
    void checkPose(const HealthLimits& limits, core::TimeNs now);
    void checkOffMap(const HealthLimits& limits, core::TimeNs now);
    // Data from a device arrived (sampleTime: its receive time); for checkSensors().
    void onSensorData(msg::DeviceNode device, core::TimeNs sampleTime);
    // The hazard detector's data: new when detectorFrames moved since the last HazardMsg.
    void onHazards(const msg::HazardMsg& hazards);
    void checkSensors(const HealthLimits& limits, core::TimeNs now);
    // self: the health task's own row is skipped (see the .cpp).
    void checkTasks(const core::Executive& executive, const core::Task* self, const HealthLimits& limits,
                    core::TimeNs now);

    const FaultBook& faults() const { return faults_; }
    // Values that were not finite (or out of their domain), each counted once.
    std::uint32_t nonFiniteInputs() const { return nonFinite_; }

private:
    void rejectValue(const char* input, const char* field);
    void checkDriveTemperature(const msg::DriveStatusMsg& status, const HealthLimits& limits, core::TimeNs now);
    void setHeartbeat(std::uint8_t id, bool lost, const msg::NodeStatusMsg& status, std::size_t node,
                      core::TimeNs now);

    core::EventLog& events_;
    FaultBook faults_;
    PersistenceFilter driveCurrent_[msg::kWheelCount];
    PersistenceFilter driveTemperature_[msg::kWheelCount];
    PersistenceFilter batteryLow_;
    PersistenceFilter busCurrent_;
    PersistenceFilter pose_;
    PersistenceFilter offMap_;
    bool started_ = false;
    core::TimeNs start_ = 0;
    bool poseSeen_ = false;
    bool poseInitialised_ = false;
    bool poseInconsistent_ = false;
    std::uint32_t poseRejections_ = 0;  // consecutive fixes refused, for the event text
    double poseSigmaM_ = 0.0;
    double poseX_ = 0.0;
    double poseY_ = 0.0;
    core::TimeNs sensorDataAt_[msg::kDeviceNodeCount] = {};  // latest data time, 0: none yet
    bool hazardFramesSeen_ = false;
    std::uint32_t hazardFrames_ = 0;
    std::uint32_t nonFinite_ = 0;
};

}  // namespace rse::estimator

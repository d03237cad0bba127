// rse-fsw assembled: the event log, software bus, executive and every task, with
// the one rate-group table that says which task runs when (fsw_app.cpp). It
// only composes: each application's commands register with the command router
// by APID, each packet family's packer with the telemetry task, each owner of
// HK fields with the HK packer (docs/architecture.md, "Commands and telemetry
// by owner"); the code of each lives with its owner.
//
// All of it lives inside one FswApp object, which main() makes static: every
// byte the flight software uses is reserved before the first frame.
#pragma once

#include <csignal>
#include <cstdio>

#include "fsw/cmdtlm/command_router.hpp"
#include "fsw/cmdtlm/command_task.hpp"
#include "fsw/cmdtlm/console_task.hpp"
#include "fsw/cmdtlm/executive_commands.hpp"
#include "fsw/cmdtlm/housekeeping_task.hpp"
#include "fsw/cmdtlm/housekeeping_telemetry.hpp"
#include "fsw/cmdtlm/rover_mode.hpp"
#include "fsw/cmdtlm/service_commands.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/cmdtlm/telemetry_task.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/deliberative_task.hpp"
#include "fsw/deliberative/plan_telemetry.hpp"
#include "fsw/estimator/drive_mode_task.hpp"
#include "fsw/estimator/estimator_telemetry.hpp"
#include "fsw/estimator/health_task.hpp"
#include "fsw/estimator/pose_estimator_task.hpp"
#include "fsw/fault_protection/fault_protection_task.hpp"
#include "fsw/fault_protection/fault_protection_telemetry.hpp"
#include "fsw/habitual/habitual_task.hpp"
#include "fsw/habitual/hazards_telemetry.hpp"
#include "fsw/io/can_io_task.hpp"
#include "fsw/io/io_telemetry.hpp"
#include "fsw/io/watchdog_task.hpp"
#include "fsw/plan_executive/goal_commands.hpp"
#include "fsw/plan_executive/plan_commands.hpp"
#include "fsw/plan_executive/plan_exec_telemetry.hpp"
#include "fsw/plan_executive/plan_executive_task.hpp"
#include "fsw/reflexive/manual_drive.hpp"
#include "fsw/reflexive/mobility_commands.hpp"
#include "fsw/reflexive/trajectory_task.hpp"
#include "fsw/site_map/site_map_commands.hpp"
#include "fsw/site_map/site_map_service.hpp"
#include "fsw/site_map/site_map_telemetry.hpp"
#include "fsw/tables/table_commands.hpp"
#include "fsw/tables/table_service.hpp"
#include "fsw/tables/table_telemetry.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::app {

// 100 Hz minor frames, 1 s major frame.
constexpr core::TimeNs kMinorFramePeriod = 10 * core::kNsPerMs;
constexpr std::uint16_t kMinorFramesPerMajor = 100;

class FswApp {
public:
    // can: the rover's CAN bus (SocketCAN, or an in-memory bus in lockstep).
    FswApp(core::Clock& clock, hal::CanBus& can);

    // Before init: ground links besides ISO-TP on the rover CAN bus (UDP, or an
    // in-memory link in tests); each carries commands in and telemetry out, and
    // the command task calls its service() once a frame.
    core::Status addGroundLink(hal::PacketLink* link);
    // The computer's watchdog, fed while every task is live (before init; none: not fed).
    void attachWatchdog(hal::Watchdog* watchdog) { watchdog_.attach(watchdog); }
    // Before init: keys that authenticate commands (cmdtlm::loadKeyFile), and the
    // lab setting that accepts unauthenticated commands. init() refuses to start
    // with no key: the public lab key is loaded only when asked for, by useLabKey()
    // (rse-fsw --lab-key, the lockstep rig), under key id 1.
    cmdtlm::KeyStore& keys() { return commands_.keys(); }
    core::Status useLabKey() { return commands_.keys().add(cmdtlm::kLabKeyId, cmdtlm::kLabKey); }
    void setAuthRequired(bool required) { commands_.setAuthRequired(required); }
    // Before init: the persisted anti-replay store (none: RAM only, for in-process
    // runs that never restart) and whether init may create it (first boot), and
    // the AUTH_RESYNC nonce's random start (none: AUTH_RESYNC refused).
    void attachAuthStore(hal::RecordStore* store, bool provision, hal::RecordWriter* writer = nullptr) {
        commands_.attachAuthStore(store, provision, writer);
    }
    void setAuthChallengeSeed(std::uint64_t seed) { commands_.setAuthChallengeSeed(seed); }
    // Before init: the clock runs `factor` times slower than real time
    // (rse-fsw --time-scale, core::ScaledMonotonicClock; lab only): init events
    // it (226) and HK.time_scale reports it. 1 (the default): real time.
    void setTimeScale(std::uint8_t factor) { timeScale_ = factor < 1 ? 1 : factor; }

    // console: where the console task writes (nullptr: quiet).
    core::Status init(std::FILE* console);
    std::uint64_t run(const volatile std::sig_atomic_t* stop, std::uint64_t maxFrames) {
        return executive_.run(stop, maxFrames);
    }
    // Events the stop and drains the console so the last events are written.
    void shutdown(const char* reason);
    // What ran: per-task timing, frame, bus and event counters.
    void printSummary(std::FILE* out) const;

    core::Executive& executive() { return executive_; }
    core::SoftwareBus& bus() { return bus_; }
    core::EventLog& events() { return events_; }
    const cmdtlm::HousekeepingTask& housekeeping() const { return housekeeping_; }
    const cmdtlm::ConsoleTask& console() const { return console_; }
    const io::CanIoTask& canIo() const { return canIo_; }
    io::CanIoTask& canIo() { return canIo_; }
    const tables::TableService& tables() const { return tables_; }
    const site_map::SiteMapService& siteMap() const { return siteMap_; }
    const cmdtlm::CommandTask& commands() const { return commands_; }
    const cmdtlm::CommandRouter& commandRouter() const { return router_; }
    const cmdtlm::RoverMode& roverMode() const { return mode_; }
    const cmdtlm::ExecutiveCommands& executiveCommands() const { return executiveCommands_; }
    const cmdtlm::TelemetryOutput& telemetryOutput() const { return telemetryOutput_; }
    const cmdtlm::TelemetryTask& telemetry() const { return telemetry_; }
    const deliberative::PlanTelemetry& planTelemetry() const { return planTelemetry_; }
    const habitual::HazardsTelemetry& hazardsTelemetry() const { return hazardsTelemetry_; }
    const reflexive::ManualDrive& manualDrive() const { return manualDrive_; }
    const estimator::PoseEstimatorTask& poseEstimator() const { return poseEstimator_; }
    const estimator::DriveModeTask& driveModes() const { return driveModes_; }
    const estimator::HealthTask& health() const { return health_; }
    const fault_protection::FaultProtectionTask& faultProtection() const { return faultProtection_; }
    const io::WatchdogTask& watchdog() const { return watchdog_; }
    const reflexive::TrajectoryTask& follower() const { return follower_; }
    const habitual::HabitualTask& habitual() const { return habitual_; }
    const deliberative::DeliberativeTask& deliberative() const { return deliberative_; }
    const plan_executive::PlanExecutiveTask& planExecutive() const { return planExecutive_; }

private:
    core::Status initStep(core::Status status, const char* what);
    core::Status checkKeys() const;           // no key, no commanding
    core::Status initTelemetry();             // the packers and HK's owners, then the telemetry task
    core::Status initCommandOwners();         // each APID's owner with the router, the boot mode and goals announced
    core::Status startExecutive();            // the rate-group table
    core::Status protectEssentialRows();      // the rows ground may not disable (EXEC_SET_TASK)
    void reportTimeAndLinks();                // start-up events: the time scale, the ground links

    core::Clock& clock_;
    std::uint8_t timeScale_ = 1;
    core::EventLog events_;
    core::SoftwareBus bus_;
    core::Executive executive_;
    tables::TableService tables_;
    cmdtlm::GroundLinks groundLinks_;
    cmdtlm::TelemetryOutput telemetryOutput_;
    // The command service and the owners of the commands, one per APID.
    cmdtlm::RoverMode mode_;
    cmdtlm::CommandRouter router_;
    cmdtlm::CommandTask commands_;
    cmdtlm::HousekeepingTask housekeeping_;
    cmdtlm::HousekeepingTelemetry housekeepingTelemetry_;
    cmdtlm::ServiceCommands serviceCommands_;
    cmdtlm::ExecutiveCommands executiveCommands_;
    plan_executive::GoalCommands goalCommands_;
    reflexive::MobilityCommands mobilityCommands_;
    tables::TableTelemetry tableTelemetry_;
    tables::TableCommands tableCommands_;
    // The site map in force, the one a commit stages beside it, and the upload (6.0 MB; docs/site_map.md).
    site_map::SiteMapService siteMap_;
    site_map::SiteMapTelemetry siteMapTelemetry_;
    site_map::SiteMapCommands siteMapCommands_;
    plan_executive::PlanCommands planCommands_;
    // The packers of the packet families the telemetry task schedules.
    io::DrivesTelemetry drivesTelemetry_;
    estimator::EstimatorTelemetry estimatorTelemetry_;
    fault_protection::FaultProtectionTelemetry faultProtectionTelemetry_;
    io::InstrumentsTelemetry instrumentsTelemetry_;
    plan_executive::PlanExecTelemetry planExecTelemetry_;
    io::PowerTelemetry powerTelemetry_;
    habitual::HazardsTelemetry hazardsTelemetry_;
    deliberative::PlanTelemetry planTelemetry_;
    // The tasks.
    io::CanIoTask canIo_;
    estimator::PoseEstimatorTask poseEstimator_;
    estimator::DriveModeTask driveModes_;
    estimator::HealthTask health_;
    fault_protection::FaultProtectionTask faultProtection_;
    io::WatchdogTask watchdog_;
    cmdtlm::TelemetryTask telemetry_;
    reflexive::ManualDrive manualDrive_;
    reflexive::TrajectoryTask follower_;
    cmdtlm::ConsoleTask console_;
    // About 1 MB (the RRT* node pool) and 0.5 MB (the chance-constrained
    // planner): an FswApp belongs in static storage.
    habitual::HabitualTask habitual_;
    deliberative::DeliberativeTask deliberative_;
    plan_executive::PlanExecutiveTask planExecutive_;
};

}  // namespace rse::app

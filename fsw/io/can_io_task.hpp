// The hal I/O task (every minor frame): runs the CANopen master cycle on the
// rover's CAN bus and bridges the devices to the software bus.
//   in:  WheelCommandMsg (latest valid one wins; non-finite or
//        beyond the rover geometry table's max_wheel_speed_rad_s: refused
//        whole, counted and evented)
//        ModeMsg: while the software e-stop is set every drive is commanded to
//        zero (in the frame the e-stop arrives) and wheel commands are ignored,
//        counted and evented, until it is cleared; the drives then stay at zero
//        until the next command arrives. A change of rover mode also commands
//        every drive to zero (event 212 if one was turning): the new mode's
//        layer commands afresh.
//        DriveRecoveryMsg (fault protection): kFaultReset starts a fresh round
//        of fault resets on a faulted or failed drive, kResetNode sends NMT
//        reset node (0x81) to it (it reboots and is configured from the start),
//        kResetInterlock releases the interlock if every drive is healthy.
//        Unknown action, wheel out of range, or a drive with nothing to
//        reset: refused, counted, event 216. Taken: event 217.
//        MissionHoldMsg (fault protection): while its estop is 1 every drive is
//        commanded to zero and wheel commands are ignored and counted, like the
//        operator's e-stop but on a flag of its own, so neither releases the
//        other's hold (event 218 on each change).
//        InstrumentCommandMsg (the plan executive): sent at once to the
//        instrument it names (hal/devices/instrument.hpp checks it first; one
//        that cannot be sent is counted and named in that instrument's status).
//        One that names no instrument: dropped, counted, event 211.
//   Any input that does not decode as its id's type is refused whole by the
//   task's input pipe (core::InputPipe): counted (malformed()), event 211.
//   Node ids (drives and devices), the heartbeat and boot timeouts, and the
//   drives' SDO retries / timeout and fault-reset count / wait come from the
//   CAN_NODE_MAP and FAULT_RESPONSE tables at init (a changed table applies at
//   the next start). Device data frames keep the ICD's fixed COB-IDs.
//   out: DriveStatusMsg and NodeStatusMsg (heartbeat liveness of every node) every frame; ImuMsg, PowerMsg, PositionFixMsg per fresh
//        sample; HazardMsg at 10 Hz; InstrumentStatusMsg for each science
//        instrument on every change and at 1 Hz.
// It also services the ISO-TP ground link on CAN (CanGroundLink).
// The reflexive drive interlock is applied here, in the same frame the drive
// status arrives, until the reflexive task exists to own it.
#pragma once

#include "fsw/cmdtlm/housekeeping_contributor.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/io/can_ground_link.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/node_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/io/drive_interlock.hpp"
#include "fsw/tables/table_service.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/can/can_link_monitor.hpp"
#include "hal/canopen/canopen_master.hpp"
#include "hal/devices/hazard_detector.hpp"
#include "hal/devices/imu.hpp"
#include "hal/devices/instrument.hpp"
#include "hal/devices/position_fix.hpp"
#include "hal/devices/power_monitor.hpp"
#include "hal/devices/wheel_drive.hpp"

namespace rse::io {

// Inputs one frame may bring: a DriveRecoveryMsg per wheel (fault protection
// may reset every drive at once), a hold, a mode change, an interlock reset and
// the two wheel commanders (follower, manual drive), and a command and a
// cancel for each science instrument. A deeper pipe than that would only hide
// a producer that floods; a full pipe is counted by the bus.
constexpr std::uint16_t kCanIoPipeDepth = msg::kWheelCount + 6 + 2 * msg::kInstrumentCount;

// Below this reported speed a wheel counts as stopped for the e-stop watch.
constexpr double kEstopStoppedRadS = 0.05;

// Also the CAN I/O application's face in housekeeping: HK's can_* counters,
// the rover CAN bus's own (hal::CanBusStats).
class CanIoTask final : public core::Task, public cmdtlm::HousekeepingContributor {
public:
    CanIoTask(hal::CanBus& can, const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
              const tables::TableService& tables);

    core::Status init();
    void run(const core::FrameContext& frame) override;
    void fillHousekeeping(cmdtlm::HK_Tlm& hk) const override;

    const hal::canopen::CanOpenMaster& master() const { return master_; }
    const hal::WheelDrive& drive(std::size_t wheel) const { return drives_[wheel]; }
    const hal::Instrument& instrument(std::size_t i) const { return instruments_[i < msg::kInstrumentCount ? i : 0]; }
    std::uint32_t instrumentCommandsDropped() const { return instrumentCommandsDropped_; }
    const DriveInterlock& interlock() const { return interlock_; }
    const CanGroundLink& groundLink() const { return groundLink_; }
    CanGroundLink& groundLink() { return groundLink_; }  // command ingest and telemetry output use it
    void resetInterlock() { interlock_.reset(); }
    std::uint32_t commandsRejected() const { return commandsRejected_; }
    std::uint32_t malformed() const { return input_.malformed(); }  // inputs that did not decode
    bool estopHeld() const { return estop_; }
    std::uint32_t commandsHeldByEstop() const { return heldByEstop_; }
    bool holdEstopHeld() const { return holdEstop_; }                // fault protection's MissionHoldMsg estop
    std::uint32_t commandsHeldByHold() const { return heldByHold_; }  // ignored while only that hold was set
    std::uint32_t recoveriesTaken() const { return recoveriesTaken_; }
    std::uint32_t recoveriesRefused() const { return recoveriesRefused_; }
    // Node id of NodeStatusMsg entry i (drives 0..5, then IMU, power, hazard, fix), from the node map.
    std::uint8_t monitoredNodeId(std::size_t i) const;
    // The e-stop watch: from the frame an e-stop is taken until every drive
    // reports below kEstopStoppedRadS. The time it took (event 213), or an
    // overrun of FAULT_RESPONSE.estop_stop_time_ms (event 214, critical, once per
    // e-stop) while a wheel still turns.
    core::TimeNs lastEstopStopTime() const { return lastEstopStopTime_; }
    std::uint32_t estopOverruns() const { return estopOverruns_; }

private:
    core::Status initNodes();
    core::Status routeInputs();
    // The inputs, in the order they arrive (input_ routes each to its handler).
    void takeWheelCommand(const msg::WheelCommandMsg& cmd);
    void takeInterlockReset(const msg::InterlockResetMsg& reset);
    void takeMode(const msg::ModeMsg& mode);
    void takeRecovery(const msg::DriveRecoveryMsg& r);
    void takeHold(const msg::MissionHoldMsg& hold);
    void takeInstrumentCommand(const msg::InstrumentCommandMsg& c);
    void refuseRecovery(const char* why, unsigned wheel);
    bool anyWheelCommanded() const;
    void refuse(const char* why);  // counts and events a bus input that was not applied
    void publishStatus(core::TimeNs now);
    void publishNodes(core::TimeNs now);
    void publishSensors(const core::FrameContext& frame);
    void publishInstruments(const core::FrameContext& frame);
    void watchEstopStop(core::TimeNs now);

    hal::CanBus& can_;
    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    hal::canopen::CanOpenMaster master_;
    hal::CanLinkMonitor link_;
    hal::WheelDrive drives_[msg::kWheelCount];
    hal::Imu imu_;
    hal::PowerMonitor power_;
    hal::HazardDetector hazard_;
    hal::PositionFixSource fix_;
    hal::Instrument instruments_[msg::kInstrumentCount];  // msg::Instrument order: grinder, camera
    DriveInterlock interlock_;
    CanGroundLink groundLink_;
    core::InputPipe input_;
    core::TimeNs now_ = 0;  // this run's frame start, for the inputs it takes
    double commanded_[msg::kWheelCount] = {};
    std::uint32_t commandsRejected_ = 0;
    bool estop_ = false;
    std::uint8_t mode_ = 0;  // SAFE until the first ModeMsg
    std::uint32_t heldByEstop_ = 0;
    bool holdEstop_ = false;
    std::uint32_t heldByHold_ = 0;
    std::uint32_t recoveriesTaken_ = 0;
    std::uint32_t recoveriesRefused_ = 0;
    std::uint8_t deviceNodes_[msg::kDeviceNodeCount] = {};  // IMU, power, hazard, fix (node map order)
    bool estopWatching_ = false;        // an e-stop is set and some wheel has not yet stopped
    bool estopOverrunReported_ = false;
    core::TimeNs estopSince_ = -1;      // -1: set this frame, timed from this run
    core::TimeNs lastEstopStopTime_ = -1;
    std::uint32_t estopOverruns_ = 0;
    std::uint32_t imuSeen_ = 0, powerSeen_ = 0, fixSeen_ = 0;
    std::uint32_t instrumentCommandsDropped_ = 0;
    std::uint32_t instrumentPublished_[msg::kInstrumentCount] = {};   // InstrumentStatus::changes last published
    std::uint32_t instrumentBadFrames_[msg::kInstrumentCount] = {};   // framesBad last published
    msg::InstrumentStatusMsg instrumentMsg_{};
    msg::DriveStatusMsg status_{};
    msg::NodeStatusMsg nodes_{};
    core::TimeNs heartbeatTimeout_ = 0;  // from the CAN node map table at init
};

}  // namespace rse::io

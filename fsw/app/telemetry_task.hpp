// What goes to the ground when (every minor frame; docs/icd.md "Telemetry"):
//   every frame  EVENT packets for events not yet sent (at most kEventsPerFrame a frame;
//                the event log is this task's to drain, so the rest wait there)
//   1 Hz         HK in slot 0, TASK_TIMING for task i in slot 10 + i, DRIVES in
//                slot 50, ROVER_STATE in slot 60, HEALTH in slot 70,
//                FAULT_PROTECTION in slot 80, INSTRUMENTS in slot 90, PLAN_EXEC
//                in slot 40, POWER in slot 30: spread over
//                the second so the slow CAN downlink never gets them in one burst
//   0.2 Hz       HAZARDS in slot 45 of every fifth second, and in slot 45 of a
//                second in which the hazard map's revision changed (so at most
//                1 Hz: the map may change at every habitual run, 10 Hz, and a
//                HAZARDS packet is 433 bytes, about 62 ISO-TP frames on CAN)
//   on change    PLAN (goal list), and every 5 s; HEALTH when the active faults
//                or a declared drive mode change; FAULT_PROTECTION with every
//                status; INSTRUMENTS when an instrument's state, command,
//                result, fault code or last refusal changes (not its progress);
//                PLAN_EXEC when the plan executive's state, counters,
//                selection or activities change (not its slack or time)
//   on event     PLAN_PATH, one per PlanPathMsg received (one per plan the
//                deliberative layer makes), in the frame it is taken off the bus
//   on request   HK and TASK_TIMING (REQUEST_HK), TABLE_STATUS and TABLE_DUMP
//                (table commands) through the send helpers below
#pragma once

#include "fsw/app/can_io_task.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/cmdtlm/command_task.hpp"
#include "fsw/cmdtlm/housekeeping_task.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::app {

constexpr std::size_t kEventsPerFrame = 8;  // 800 events/s downlink at most
constexpr std::uint16_t kPlanPeriodFrames = 500;  // PLAN repeats every 5 s
constexpr std::uint32_t kTaskTimingSlot = 10;     // TASK_TIMING of task i in slot 10 + i
constexpr std::uint32_t kDrivesSlot = 50;
constexpr std::uint32_t kRoverStateSlot = 60;
constexpr std::uint32_t kHealthSlot = 70;
constexpr std::uint32_t kFaultProtectionSlot = 80;
constexpr std::uint32_t kInstrumentsSlot = 90;
constexpr std::uint32_t kPlanExecSlot = 40;
constexpr std::uint32_t kPowerSlot = 30;
constexpr std::uint32_t kHazardsSlot = 45;            // HAZARDS: in this slot, on change or ...
constexpr std::uint32_t kHazardsPeriodFrames = 500;   // ... every 5 s
// The task drains its pipe every frame, so the pipe holds one frame's inputs:
// each of its 15 message ids at most once a frame, the instrument status twice
// (one per instrument), the wheel command once (the follower commands in
// AUTONOMOUS, manual drive in MANUAL, never both): 16, two more than before
// POWER (PowerMsg) and HAZARDS (KnownHazardsMsg). A copy lost to a full pipe is
// counted and evented by the bus (event 101). The flight's pipes take 208 of
// the bus's 256 slots (kBusTotalQueueSlots), so that constant stays.
constexpr std::uint16_t kTelemetryPipeDepth = 16;

// What the task reads besides the bus. All references, all owned by FswApp.
struct TelemetrySources {
    const core::Executive& executive;
    const cmdtlm::HousekeepingTask& housekeeping;
    const cmdtlm::CommandTask& commands;
    const tables::TableService& tables;
    const hal::CanBus& can;
    double utcAtMetZero;  // time correlation, fixed at start-up
    std::uint8_t timeScale = 1;  // HK.time_scale: 1 real time, N the timeline slowed N times (lab)
};

class TelemetryTask final : public core::Task {
public:
    TelemetryTask(core::SoftwareBus& bus, core::EventLog& events, cmdtlm::TelemetryOutput& output,
                  const TelemetrySources& sources)
        : bus_(bus), events_(events), output_(output), sources_(sources) {}

    core::Status init();
    void run(const core::FrameContext& frame) override;

    void setUtcAtMetZero(double utc) { sources_.utcAtMetZero = utc; }
    void setTimeScale(std::uint8_t factor) { sources_.timeScale = factor; }
    // REQUEST_HK: HK and TASK_TIMING on the next run.
    void requestHousekeeping() { hkRequested_ = true; }
    void sendHousekeeping(core::TimeNs now);
    void sendTaskTiming(std::size_t index);
    // Table commands report through these.
    void sendTableStatus(tables::TableId id, const tables::TableCheck& check);
    core::Status sendTableDump(tables::TableId id, bool inactive);

    std::uint32_t eventsSent() const { return eventsSent_; }
    std::uint32_t housekeepingSent() const { return housekeepingSent_; }
    std::uint32_t malformed() const { return malformed_; }
    std::uint32_t planPathsSent() const { return planPathsSent_; }
    std::uint32_t hazardsSent() const { return hazardsSent_; }

private:
    void takeBusMessages();
    void sendEvents();
    void sendDrives();
    void sendRoverState();
    void sendHealth();
    void sendPlan();
    void sendFaultProtection();
    void sendInstruments();
    void sendPlanExec();
    void sendPlanPath(const msg::PlanPathMsg& m);
    void sendPower();
    void sendHazards();

    core::SoftwareBus& bus_;
    core::EventLog& events_;
    cmdtlm::TelemetryOutput& output_;
    TelemetrySources sources_;
    core::PipeId pipe_ = 0;
    core::Message inbox_{};
    bool hkRequested_ = false;
    bool planChanged_ = true;
    std::uint32_t eventsSent_ = 0;
    std::uint32_t housekeepingSent_ = 0;
    std::uint32_t malformed_ = 0;
    // Latest of each input (what the 1 Hz packets report).
    msg::DriveStatusMsg drives_{};
    msg::WheelCommandMsg wheelCommand_{};
    msg::PoseEstimateMsg pose_{};
    msg::FaultStatusMsg faults_{};
    msg::DriveModesMsg driveModes_{};
    bool healthChanged_ = false;
    msg::ModeMsg mode_{};
    msg::GoalListMsg goals_{};
    msg::PlanStatusMsg planStatus_{};
    msg::PlanPathMsg planPath_{};
    std::uint32_t planPathsSent_ = 0;
    msg::FaultProtectionStatusMsg protection_{};
    msg::MissionHoldMsg hold_{};
    bool protectionChanged_ = false;
    msg::InstrumentStatusMsg instruments_[msg::kInstrumentCount] = {};
    bool instrumentsChanged_ = false;
    msg::PlanExecutiveStatusMsg planExec_{};
    bool planExecChanged_ = false;
    msg::PowerMsg power_{};
    msg::KnownHazardsMsg hazards_{};
    bool hazardsChanged_ = false;  // a revision not yet sent
    std::uint32_t hazardsSent_ = 0;
    // Packet structs kept out of the task's stack.
    msg::HousekeepingMsg hkMsg_{};
    cmdtlm::HK_Tlm hk_{};
    cmdtlm::PLAN_Tlm plan_{};
    cmdtlm::PLAN_PATH_Tlm planPathTlm_{};
    cmdtlm::HAZARDS_Tlm hazardsTlm_{};
    cmdtlm::TABLE_DUMP_Tlm dump_{};
    std::uint8_t image_[tables::kMaxTableImageSize] = {};
};

}  // namespace rse::app

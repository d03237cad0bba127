// The software-bus message catalogue: every message id in one place.
// Each id's payload type lives in its own header in fsw/msg/; the table with
// producers and consumers is in docs/architecture.md ("Bus message catalogue").
//
// Ranges: 0x08xx telemetry-bound (one day one CCSDS APID each, 0x0800 | APID),
//         0x18xx commands from ground, 0x01xx-0x07xx internal between layers.
#pragma once

#include "fsw/core/software_bus.hpp"

namespace rse::msg::ids {

constexpr core::MsgId kHousekeeping = 0x0801;  // HousekeepingMsg, 1 Hz, cmdtlm -> telemetry

// hal I/O <-> layers (drive_msgs.hpp, sensor_msgs.hpp, node_msgs.hpp)
constexpr core::MsgId kDriveStatus = 0x0110;   // DriveStatusMsg, 100 Hz, can_io -> estimator, reflexive, telemetry
constexpr core::MsgId kWheelCommand = 0x0111;  // WheelCommandMsg, on change, reflexive -> can_io
constexpr core::MsgId kImu = 0x0120;           // ImuMsg, per sample (100 Hz), can_io -> estimator
constexpr core::MsgId kPower = 0x0121;         // PowerMsg, per sample (10 Hz), can_io -> estimator, health, telemetry (POWER)
constexpr core::MsgId kPositionFix = 0x0122;   // PositionFixMsg, per fix (1 Hz), can_io -> estimator
constexpr core::MsgId kHazards = 0x0123;       // HazardMsg, 10 Hz, can_io -> habitual
constexpr core::MsgId kNodeStatus = 0x0124;    // NodeStatusMsg, 100 Hz, can_io -> health

// science instruments <-> hal I/O (instrument_msgs.hpp)
constexpr core::MsgId kInstrumentStatus = 0x0125;   // InstrumentStatusMsg per instrument, on change and 1 Hz, can_io -> plan executive, telemetry
constexpr core::MsgId kInstrumentCommand = 0x0126;  // InstrumentCommandMsg, per command, plan executive -> can_io

// estimator and health -> layers, executive, telemetry (estimator_msgs.hpp, health_msgs.hpp)
constexpr core::MsgId kPoseEstimate = 0x0150;  // PoseEstimateMsg, 100 Hz, estimator -> layers, health, telemetry
constexpr core::MsgId kFaultStatus = 0x0151;   // FaultStatusMsg, on change and 1 Hz, health -> executive, telemetry
constexpr core::MsgId kDriveModes = 0x0152;    // DriveModesMsg, 10 Hz, drive_modes -> habitual, deliberative, telemetry

// deliberative <-> habitual (habitual_msgs.hpp)
constexpr core::MsgId kLegCommand = 0x0160;    // LegCommandMsg, per leg, deliberative -> habitual
constexpr core::MsgId kLegReport = 0x0161;     // LegReportMsg, on change and 1 Hz, habitual -> deliberative, telemetry
constexpr core::MsgId kKnownHazards = 0x0162;  // KnownHazardsMsg, on change and 1 Hz, habitual -> deliberative, telemetry (HAZARDS)

// habitual <-> reflexive (trajectory_msgs.hpp)
constexpr core::MsgId kTrajectory = 0x0170;      // TrajectoryMsg, per plan or repair, habitual -> reflexive
constexpr core::MsgId kFollowerStatus = 0x0171;  // FollowerStatusMsg, on change and 10 Hz, reflexive -> habitual, telemetry
constexpr core::MsgId kContact = 0x0172;         // ContactMsg, per contact seen, reflexive -> habitual, telemetry (DRIVES)

// commands from ground -> layers (mode_msgs.hpp, goal_msgs.hpp)
constexpr core::MsgId kMode = 0x0130;          // ModeMsg, on change, the mode owner (cmdtlm) -> can_io, manual_drive, layers
constexpr core::MsgId kInterlockReset = 0x0133;  // InterlockResetMsg, per RESET_INTERLOCK, mobility commands -> can_io
constexpr core::MsgId kManualDrive = 0x0131;   // ManualDriveMsg, per DRIVE command, mobility commands -> manual_drive
constexpr core::MsgId kGoalList = 0x0140;      // GoalListMsg, on change, goal commands -> plan executive, telemetry

// deliberative -> telemetry, the mode owner (deliberative_msgs.hpp)
constexpr core::MsgId kPlanStatus = 0x0141;    // PlanStatusMsg, on change and 1 Hz, deliberative -> telemetry
constexpr core::MsgId kSafeRequest = 0x0142;   // SafeRequestMsg, on a call home, deliberative -> the mode owner (cmdtlm)
constexpr core::MsgId kPlanPath = 0x0143;      // PlanPathMsg, per plan made (plansMade), deliberative -> telemetry (PLAN_PATH)
constexpr core::MsgId kRouteChunk = 0x0144;    // RouteChunkMsg, per chunk of a site-mode route found, deliberative -> telemetry (ROUTE)

// fault protection -> CAN I/O and the layers (fault_protection_msgs.hpp)
constexpr core::MsgId kMissionHold = 0x0180;    // MissionHoldMsg, on change and 1 Hz, fault protection -> can_io, habitual, deliberative, telemetry
constexpr core::MsgId kDriveRecovery = 0x0181;  // DriveRecoveryMsg, per action, fault protection -> can_io
constexpr core::MsgId kTaskRestart = 0x0182;    // TaskRestartMsg, per action, fault protection -> the executive's commands (cmdtlm)
constexpr core::MsgId kFaultProtectionStatus = 0x0183;  // FaultProtectionStatusMsg, on change and 1 Hz, fault protection -> telemetry
constexpr core::MsgId kReplanRequest = 0x0184;  // ReplanRequestMsg, per try, fault protection -> deliberative

// plan commands <-> plan executive -> telemetry (plan_executive_msgs.hpp)
constexpr core::MsgId kPlanCommand = 0x0190;         // PlanCommandMsg, per PLAN_* command, plan commands -> plan executive
constexpr core::MsgId kPlanExecutiveStatus = 0x0191; // PlanExecutiveStatusMsg, on change and 1 Hz, plan executive -> telemetry
constexpr core::MsgId kPlanGoal = 0x0192;            // PlanGoalMsg, per drive activity started or cancelled (GOTO and goal lists too), plan executive -> deliberative

}  // namespace rse::msg::ids

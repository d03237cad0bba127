// Fault protection <-> the rest of the rover (fsw/fault_protection/): the
// mission hold it puts on the planning layers and the wheels, the recovery
// actions it asks the CAN I/O task to take on one drive, the task restarts and
// the replans it asks for. Fault protection reads FaultStatusMsg,
// DriveStatusMsg and ModeMsg and answers only through these messages (and
// SafeRequestMsg for a call home).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

// Why the mission is held: bit (1u << reason) of MissionHoldMsg::reasons.
namespace hold {
constexpr std::uint32_t kDriveRecovery = 0;   // a drive is being reset / restarted
constexpr std::uint32_t kPoseUncertain = 1;   // waiting for the pose uncertainty to clear
constexpr std::uint32_t kBatteryLow = 2;      // waiting for the battery to recharge
constexpr std::uint32_t kSensorLost = 3;      // a sensor that safety rests on is silent
constexpr std::uint32_t kTaskRestart = 4;     // a stalled flight task is being restarted
constexpr std::uint32_t kDriveOvertemp = 5;   // a drive is cooling
constexpr std::uint32_t kOffMap = 6;          // off the map with a response set to hold (not the default: it replans)
constexpr std::uint32_t kCount = 7;
}  // namespace hold

// Published on every change and at 1 Hz. While reasons != 0:
//  - CAN I/O commands every drive to zero when estop is 1 (a software e-stop
//    that fault protection owns, apart from the operator's ESTOP_SET);
//  - the habitual layer stops the rover and keeps its leg (it does not fail up
//    because of the hold); the deliberative layer sends no new leg.
// When reasons returns to 0, resumeCount has grown by one: the deliberative
// layer re-sends the current leg from the current pose and driving resumes.
struct MissionHoldMsg {
    static constexpr core::MsgId kMsgId = ids::kMissionHold;
    std::int64_t timeNs;
    std::uint32_t reasons;      // bit per hold:: reason; 0: not held
    std::uint32_t resumeCount;  // holds released since start
    std::uint8_t estop;         // 1: every drive to zero until released
    std::uint8_t pad[7];
};

// A hold every consumer may act on: only known reason bits, estop 0 or 1.
inline bool holdUsable(const MissionHoldMsg& h) { return (h.reasons >> hold::kCount) == 0U && h.estop <= 1; }

// What fault protection asks CAN I/O to do to one drive.
enum class DriveRecoveryAction : std::uint8_t {
    kFaultReset = 1,      // CiA 402 fault reset (controlword edge; by SDO while pre-operational)
    kResetNode = 2,       // NMT reset node: the drive reboots and is configured from the start
    kResetInterlock = 3,  // release the reflexive drive interlock if every drive is healthy (wheel ignored)
};

struct DriveRecoveryMsg {
    static constexpr core::MsgId kMsgId = ids::kDriveRecovery;
    std::int64_t timeNs;
    std::uint8_t wheel;            // 0..5 (ignored for kResetInterlock)
    DriveRecoveryAction action;
    std::uint8_t pad[6];
};

// Fault protection -> the executive's owner (cmdtlm's executive commands): run a stalled
// rate-group row again (it was disabled, or stopped running).
struct TaskRestartMsg {
    static constexpr core::MsgId kMsgId = ids::kTaskRestart;
    std::int64_t timeNs;
    std::uint8_t row;  // rate-group row 0..kMaxTasks-1
    std::uint8_t pad[7];
};

// Fault protection -> the deliberative layer: the leg in progress cannot be
// kept (the rover is off the map): cancel it and replan the unfinished goals
// from the current pose, now. One per try of a kReplanFromPose response.
struct ReplanRequestMsg {
    static constexpr core::MsgId kMsgId = ids::kReplanRequest;
    std::int64_t timeNs;
    std::uint8_t faultId;   // the fault answered (msg::fault::kOffMap)
    std::uint8_t attempt;   // try 1..attempts of this occurrence
    std::uint8_t pad[6];
};

// The fault classes fault protection answers, one row each of FAULT_PROTECTION.
enum class FaultClass : std::uint8_t {
    kDriveLost = 0,        // drive heartbeat lost (fault ids 1..6)
    kDriveFaulted = 1,     // a drive reports faulted or failed (drive status)
    kDriveOvercurrent = 2, // fault ids 11..16
    kSensorLost = 3,       // device heartbeat lost (7..10) or its data stale (36..39)
    kBatteryLow = 4,       // 17
    kBusOvercurrent = 5,   // 18
    kPoseUncertain = 6,    // 19
    kTaskStalled = 7,      // 20..35
    kDriveOvertemp = 8,    // 40..45
    kOffMap = 9,           // 46
};
constexpr std::size_t kFaultClassCount = 10;

// What fault protection does about one class (FAULT_PROTECTION.response).
enum class FaultResponseKind : std::uint8_t {
    kEventOnly = 0,
    kHoldUntilClear = 1,
    kRecoverDrive = 2,
    kRestartTask = 3,
    kSafeAndCallHome = 4,
    kReplanFromPose = 5,   // cancel the waypoint, replan the unfinished goals from where the rover stands
};

// Where one response stands.
enum class ResponseState : std::uint8_t {
    kIdle = 0,        // nothing active
    kSettling = 1,    // a drive fault seen: held, giving the drive its own recovery time first
    kWaiting = 2,     // action taken (or holding): waiting for the fault to clear
    kRecovered = 3,   // cleared after a response: attempts remembered for attempt_memory_ms
    kGaveUp = 4,      // attempts used: called home (or a drive declared failed)
};

// One response in progress: per wheel for the drive classes, per fault id otherwise.
struct ResponseTlm {
    std::uint8_t faultId;      // the fault it answers (drive classes: 1 + wheel), 0: slot unused
    FaultClass faultClass;
    ResponseState state;
    std::uint8_t attemptsUsed;
    std::uint8_t lastAction;   // DriveRecoveryAction for drives, 1 hold, 2 restart, 3 replan; 0 none yet
    std::uint8_t pad[3];
    std::int64_t sinceNs;      // when the current state was entered
};
constexpr std::size_t kResponseSlots = 8;

// Published on every change and at 1 Hz (FAULT_PROTECTION telemetry).
struct FaultProtectionStatusMsg {
    static constexpr core::MsgId kMsgId = ids::kFaultProtectionStatus;
    std::int64_t timeNs;
    std::uint32_t holdReasons;    // MissionHoldMsg::reasons now
    std::uint32_t responsesStarted;
    std::uint32_t recoveries;     // responses that ended with the fault cleared
    std::uint32_t gaveUp;         // responses that ended in a call home or a failed drive
    std::uint32_t actionsSent;    // drive recovery and task restart requests
    std::uint8_t activeCount;     // responses[0..activeCount) in use
    std::uint8_t pad[3];
    ResponseTlm responses[kResponseSlots];
};

}  // namespace rse::msg

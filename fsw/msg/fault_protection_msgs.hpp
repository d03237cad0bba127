// Fault protection <-> the rest of the rover (fsw/fault_protection/): the
// mission hold it puts on the planning layers and the wheels, and the recovery
// actions it asks the CAN I/O task to take on one drive. Fault protection
// reads FaultStatusMsg, DriveStatusMsg, DriveModesMsg, LegReportMsg and answers
// only through these messages (and SafeRequestMsg for a call home).
#pragma once

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
constexpr std::uint32_t kCount = 6;
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

}  // namespace rse::msg

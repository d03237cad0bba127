// One CiA 402 wheel drive, as the master sees it (docs/icd.md §1.4).
//
// Life cycle:  waiting for boot-up -> configuring (SDO steps of the ICD, each
// verified; a failed step is tried again DriveConfig::sdoRetries times) ->
// starting (NMT start, wait for the operational heartbeat) -> enabling
// (controlword walk to operation enabled) -> operational (target velocity sent
// every cycle).
// Faults: an EMCY with a non-zero code or a fault statusword -> faulted; up to
// DriveConfig::faultResets fault resets (rising edge of controlword bit 7), each
// given faultResetWait; still faulted -> failed (out of service, commanded to
// zero). The edge goes by RPDO1 when the node is NMT operational, and by SDO
// writes of 0x6040 (then a read of 0x6041) when it is not: a pre-operational node
// ignores PDOs, so a fault taken while configuring or starting would otherwise
// never clear. A fault cleared that way restarts configuration from the top.
// requestFaultReset() (fault protection) starts a fresh round from faulted or failed.
// Heartbeat lost (or never heard within the boot timeout) -> lost; heard again
// (or rebooted) -> configured again from the start.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/canopen/canopen_master.hpp"
#include "hal/canopen/cia402.hpp"
#include "hal/canopen/sdo_client.hpp"

namespace rse::hal {

enum class DriveState : std::uint8_t {
    kWaitingBootUp,
    kConfiguring,
    kStarting,
    kEnabling,
    kOperational,
    kFaulted,
    kFailed,
    kLost,
};
const char* toString(DriveState state);

// Set from the FAULT_RESPONSE table by the owner (hal/ cannot read tables);
// the defaults are the table's shipped values.
struct DriveConfig {
    std::uint32_t sdoRetries = 3;                               // tries of a failed config step after the first
    core::TimeNs sdoTimeout = canopen::kSdoDefaultTimeout;      // SDO server answer time
    std::uint32_t faultResets = 3;                              // before the drive is declared failed
    core::TimeNs faultResetWait = 100 * core::kNsPerMs;         // after a reset, before it is judged
};
constexpr core::TimeNs kStartTimeout = 500 * core::kNsPerMs;
constexpr core::TimeNs kEnableTimeout = 1000 * core::kNsPerMs;
constexpr core::TimeNs kDriveHeartbeatTimeout = 250 * core::kNsPerMs;  // 2.5 x 100 ms

struct DriveFeedback {
    std::uint16_t statusword = 0;
    cia402::PowerState power = cia402::PowerState::kNotReadyToSwitchOn;
    std::int32_t velocityMradS = 0;  // wheel angular velocity actual
    std::int16_t currentMa = 0;      // motor current actual
    core::TimeNs time = 0;           // when the TPDO arrived
    std::uint32_t count = 0;         // TPDOs received
    std::int16_t temperatureDeciC = 0;  // motor temperature (TPDO2), 0.1 degC
    core::TimeNs temperatureTime = 0;
    std::uint32_t temperatureCount = 0;  // TPDO2s received; 0: temperature unknown
};

struct DriveStats {
    std::uint32_t badPdo = 0;          // TPDO1 with a DLC other than 8, TPDO2 other than 2, EMCY other than 8
    std::uint32_t emcyCount = 0;
    std::uint32_t configAttempts = 0;
    std::uint32_t configFailures = 0;  // configuration given up
    std::uint32_t faults = 0;
    std::uint32_t faultResets = 0;     // resets sent, by RPDO or SDO
    std::uint32_t sdoFaultResets = 0;  // of which by SDO (node not operational)
    std::uint32_t resetRequests = 0;   // requestFaultReset() accepted
    std::uint32_t losses = 0;
};

class WheelDrive final : public canopen::CanOpenNode {
public:
    WheelDrive(CanBus& bus, core::EventLog& events, const canopen::HeartbeatConsumer& heartbeats,
               std::uint8_t nodeId, const char* name);

    // Start-up only, before the master learns of the node: the node id and
    // limits from the tables. kInvalidArgument for id 0 or > 127, or a timeout
    // or wait <= 0 (nothing changed then).
    core::Status configure(std::uint8_t nodeId, const DriveConfig& config);
    // From faulted or failed: a fresh round of config().faultResets resets
    // (event 437). kUnavailable in any other state (nothing to reset).
    core::Status requestFaultReset(core::TimeNs now);

    std::uint8_t nodeId() const override { return nodeId_; }
    const DriveConfig& config() const { return config_; }
    void onFrame(const CanFrame& frame, core::TimeNs now) override;
    void step(core::TimeNs now) override;
    void sendCyclic(core::TimeNs now) override;

    // Applied only while operational; zero otherwise.
    void setTargetVelocity(std::int32_t mradPerSec) { target_ = mradPerSec; }
    std::int32_t targetVelocityMradS() const { return target_; }

    DriveState state() const { return state_; }
    const DriveFeedback& feedback() const { return feedback_; }
    std::uint16_t lastEmcyCode() const { return lastEmcyCode_; }
    std::uint8_t errorRegister() const { return errorRegister_; }
    const DriveStats& stats() const { return stats_; }
    const canopen::SdoClient& sdo() const { return sdo_; }
    const char* name() const { return name_; }
    std::uint16_t lastControlword() const { return controlword_; }

private:
    void enter(DriveState next, core::TimeNs now);
    void enterFaulted(core::TimeNs now);
    void stepConfiguring(core::TimeNs now);
    void stepFaulted(core::TimeNs now);
    void stepFaultedBySdo(core::TimeNs now);
    void declareFailed(core::TimeNs now);
    void fault(const char* why, std::uint16_t code, core::TimeNs now);
    bool checkHeartbeat(core::TimeNs now);
    void sendNmt(canopen::NmtCommand command);

    CanBus& bus_;
    core::EventLog& events_;
    const canopen::HeartbeatConsumer& heartbeats_;
    std::uint8_t nodeId_;
    const char* name_;
    DriveConfig config_;
    canopen::SdoClient sdo_;
    DriveState state_ = DriveState::kWaitingBootUp;
    core::TimeNs enteredAt_ = 0;
    std::uint32_t seenBootUps_ = 0;
    std::uint32_t configStep_ = 0;
    std::uint32_t stepAttempts_ = 0;
    bool stepRequested_ = false;
    std::uint32_t resetsTried_ = 0;
    bool resetEdge_ = false;  // send 0x0080 after a cycle of 0x0000
    // The SDO fault reset (node not operational): 0x6040 = 0x0000, = 0x0080,
    // the wait, then 0x6041 read back.
    enum class SdoReset : std::uint8_t { kIdle, kBitLow, kBitHigh, kSettle, kReadStatus };
    bool resetBySdo_ = false;
    SdoReset sdoReset_ = SdoReset::kIdle;
    core::TimeNs settleUntil_ = 0;
    std::int32_t target_ = 0;
    std::uint16_t controlword_ = 0;
    std::uint16_t lastEmcyCode_ = 0;
    std::uint8_t errorRegister_ = 0;
    DriveFeedback feedback_;
    DriveStats stats_;
};

}  // namespace rse::hal

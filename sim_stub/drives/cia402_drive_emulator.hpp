// rse-sim: one CiA 301 / CiA 402 wheel drive (profile velocity mode) on the CAN
// bus, as docs/icd.md §1.3-1.4 describes it. The flight software must not be able
// to tell it from a real drive.
//
// The simulator owns one emulator per wheel, each on its own CanBus endpoint, and
// calls step(now) with its (virtual) time. All time comes from `now`: the same
// frames at the same times give the same answers. Nothing is allocated after
// construction and nothing throws.
//
// One class, its definitions in a file per concept: cia402_drive_emulator.cpp
// (the node: hooks, the step, CiA 301 NMT, SYNC, PDOs, heartbeat, EMCY),
// cia402_drive_power.cpp (the CiA 402 power state machine, faults, the
// statusword), cia402_drive_motor.cpp (the motor and thermal models, the noisy
// reports), cia402_drive_objects.cpp (the object dictionary); the codes they
// share in cia402_drive_codes.hpp.
//
// ---- CANopen (CiA 301) ---------------------------------------------------------
// NMT slave. powerOn()/restart() boot the node at the next step(): the frames that
// were waiting are discarded (the controller was not listening yet), the boot-up
// message 0x700+n [0x00] is sent and the node is pre-operational. NMT reset node
// and reset communication (to node n or to 0 = all) do the same at once. Heartbeat
// producer: period 0x1017 in ms, DEFAULT 0 (off) until the master writes it; each
// heartbeat carries the NMT state (0x04 stopped, 0x05 operational, 0x7F
// pre-operational). The first heartbeat comes one period after 0x1017 is written;
// later ones keep a fixed cadence (due += period; a step that comes more than a
// period late sends one heartbeat, not a burst).
// SDO server on 0x600+n / 0x580+n in pre-operational and operational (not in
// stopped): see sdo_server.hpp and the object table in the .cpp.
// PDOs in operational only. RPDO1 (0x200+n, DLC 6: controlword u16, target
// velocity i32 mrad/s) is latched; on SYNC (0x080, DLC 0) the latched RPDO1 is
// applied (only if a new one arrived since the last SYNC) and TPDO1 (0x180+n,
// DLC 8: statusword u16, velocity actual i32 mrad/s, current actual i16 mA) is sent
// on every n-th SYNC, n = 0x1800:02 (default 1). An RPDO1 with DLC != 6 is not
// processed and raises EMCY 0x8210 (once per episode, error register bit 4); the
// next good RPDO1 clears it with EMCY 0x0000. The power state is not changed.
// EMCY (0x080+n, DLC 8: code u16, error register u8, 5 zero bytes) is sent when an
// error is detected (that is, on entering fault reaction active, then fault) and
// code 0x0000 with the remaining error register (0 unless a PDO length error is
// still pending) when a fault reset succeeds. No EMCY in NMT stopped (CiA 301).
// Leaving operational (NMT stop / enter pre-operational) and reset communication
// act like CiA 402 abort connection option 0x6007 = 2: "disable voltage".
//
// ---- CiA 402 power state machine -------------------------------------------------
// Controlword commands (CiA 402 masks): shutdown 0x06/0x87, switch on 0x07/0x8F,
// enable operation 0x0F/0x8F (from ready to switch on: transitions 3 + 4 at once),
// disable voltage 0x00/0x82, quick stop 0x02/0x86, disable operation 0x07/0x8F,
// fault reset = rising edge of bit 7 (only in fault, refused while the cause is
// still there: a failed motor). Quick stop active brakes to 0 and stays there until
// disable voltage (transition 12) or enable operation (16) (option code 6 style).
// A controlword is evaluated when it is applied (RPDO1 on SYNC, or SDO write of
// 0x6040); not ready to switch on -> switch on disabled and fault reaction active
// -> fault are automatic, at the next step (fault reaction lasts
// faultReactionTime, default 10 ms).
// Statusword (0x6041):
//   not ready to switch on 0x0000, switch on disabled 0x0040, ready to switch on
//   0x0021, switched on 0x0033, operation enabled 0x0037, quick stop active 0x0017,
//   fault reaction active 0x001F, fault 0x0008 (bit 4 "voltage enabled" while the
//   power stage is switched on: switched on, operation enabled, quick stop, fault
//   reaction), plus
//   bit 7  warning: current above the over-current limit, trip timer running
//   bit 9  remote: in every state but not ready to switch on (the controlword is obeyed)
//   bit 10 target reached: operation enabled and |velocity - target| <= velocity
//          window, or quick stop active and |velocity| <= window; else 0
//   bit 11 internal limit active: operation enabled and |target| > speed limit
//   bit 12 (pv mode) speed = 0: operation enabled or quick stop, |velocity| <=
//          speed-zero threshold
//
// ---- Motor model ------------------------------------------------------------------
// Integrated in sub-steps of at most modelStep (1 ms):
//   torque on  = operation enabled (tracks the target) or quick stop active (brakes to
//                0), motor not failed, node alive
//   target     = 0x60FF clamped to +-speedLimit in operation enabled with mode 3, else 0
//   velocity   : first-order lag, v <- t + (v - t) e^(-h/tau), tau = velocityTimeConstant
//                (50 ms). With torque off the wheel coasts to 0 with the same lag.
//   current mA = degradation x (noLoadCurrent + currentPerTorque x |load torque|
//                + currentPerAcceleration x |dv/dt|) with torque on, 0 with torque off;
//                while braking (|v| more than kBrakingMarginRadS above |t|, or v
//                and t of opposite signs) without the block share of the load
//                (setBlockTorque: a wheel slipping under a blocked rover is
//                stopped by the slip's friction once the drive stops pushing).
// Defaults: tau 50 ms, speed limit 5000 mrad/s, no-load 150 mA, 2000 mA per N m,
// 20 mA per rad/s^2, load torque 0.3 N m (a constant rolling resistance until the
// simulator calls setLoadTorque), degradation 1.0. So a wheel holding any steady
// speed draws 750 mA, and 1125 mA at degradation 1.5.
// Over-current: a current above overCurrentLimit (3000 mA) for more than
// overCurrentTime (100 ms) -> EMCY 0x2310, fault (resettable).
//
// ---- Thermal model ------------------------------------------------------------
// One lumped motor temperature T, integrated in the same sub-steps:
//   dT/dt = heatGain x overheat x (I / 1 A)^2 - (T - ambient) / thermalTimeConstant
// (I the physical current above, 0 with torque off), starting at ambient.
// Defaults: ambient 20 degC, heat gain 0.2 degC/s per A^2, time constant 60 s, so a
// wheel holding 750 mA settles 7 degC above ambient; the rover's wheels in
// lockstep driving (about 1.4 A) settle 23 degC above, and 1.3x wear (1.8 A) 39
// degC above: 20 degC of margin to the 80 degC limit. setOverheat(factor) multiplies the heat gain (the scenario's
// motor_overheat fault); a power cycle does not cool the motor. The drive does
// not protect itself: it only reports T.
// TPDO2 (0x280+n, DLC 2: motor temperature i16 in 0.1 degC) is sent in
// operational on every tpdo2EverySyncs-th SYNC (default 10: 10 Hz), after TPDO1.
//
// ---- Measurement noise -------------------------------------------------------------
// What the drive REPORTS (TPDO1, and SDO uploads of 0x606C velocity actual and
// 0x6078 current actual) carries Gaussian white noise: one independent draw per
// report, standard deviation currentSigmaMa / velocitySigmaMradS (default 0 = off:
// nothing is drawn and the reports are exactly the quantised model values). Each
// quantity has its own SimRng stream per drive, from (noiseSeed, noiseChannel),
// so the same seed gives the same reports. Everything physical stays noise-free:
// currentMa() (what the battery sees), wheelSpeedRadS(), the over-current
// detection and the statusword bits.
// The body physics is not modelled here: the simulator reads wheelSpeedRadS() and
// feeds back setLoadTorque().
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/canopen/cia402.hpp"
#include "sim_stub/drives/sdo_server.hpp"
#include "sim_stub/world/random.hpp"

namespace rse::sim {

// NMT state as the heartbeat reports it.
enum class NmtState : std::uint8_t {
    kInitialising = 0x00,  // powered off, booting or resetting (boot-up byte)
    kStopped = 0x04,
    kOperational = 0x05,
    kPreOperational = 0x7F,
};
const char* toString(NmtState state);

// Whether the node's processor runs at all (not a CANopen notion).
enum class NodeLife : std::uint8_t {
    kOff,      // never powered on
    kBooting,  // powerOn()/restart() called; boots at the next step()
    kRunning,
    kCrashed,  // crash(): silent until restart()
};
const char* toString(NodeLife life);

// The CiA 402 power states: the one definition in hal/canopen (toString there too).
using PowerState = hal::cia402::PowerState;
using hal::cia402::toString;

namespace emcy {
constexpr std::uint16_t kNoError = 0x0000;
constexpr std::uint16_t kOverCurrent = 0x2310;
constexpr std::uint16_t kOverVoltage = 0x3210;
constexpr std::uint16_t kOverTemperature = 0x4310;
constexpr std::uint16_t kMotorFailed = 0x5000;
constexpr std::uint16_t kPdoLength = 0x8210;
}  // namespace emcy

// How much faster than its target a wheel must turn to count as braking
// (the lag's tail: closer than this it is holding its speed).
constexpr double kBrakingMarginRadS = 0.05;

struct DriveEmulatorConfig {
    core::TimeNs velocityTimeConstant = 50 * core::kNsPerMs;
    std::int32_t speedLimitMradS = 5000;
    double noLoadCurrentMa = 150.0;
    double currentPerTorqueMaPerNm = 2000.0;
    double currentPerAccelMaPerRadS2 = 20.0;
    double loadTorqueNm = 0.3;  // initial load torque (rolling resistance)
    std::int32_t overCurrentLimitMa = 3000;
    core::TimeNs overCurrentTime = 100 * core::kNsPerMs;
    core::TimeNs faultReactionTime = 10 * core::kNsPerMs;
    std::int32_t velocityWindowMradS = 20;      // statusword bit 10
    std::int32_t speedZeroThresholdMradS = 10;  // statusword bit 12
    core::TimeNs modelStep = 1 * core::kNsPerMs;
    core::TimeNs sdoServerTimeout = kSdoServerDefaultTimeout;
    // Install acceptance filters on the bus endpoint (NMT, SYNC, own RPDO1 and SDO
    // request), as a real controller would. Leave on unless the endpoint is shared.
    bool installFilters = true;
    // Measurement noise on the reported values (see "Measurement noise" above).
    // Negative or non-finite sigmas count as 0.
    double currentSigmaMa = 0.0;      // on the current actual, mA
    double velocitySigmaMradS = 0.0;  // on the velocity actual, mrad/s
    std::uint64_t noiseSeed = 1;      // the scenario seed
    std::size_t noiseChannel = 0;     // whose streams: the wheel index 0..5 (DriveBank sets it)
    // Thermal model (see "Thermal model" above).
    double ambientC = 20.0;
    double heatGainCPerA2S = 0.2;
    core::TimeNs thermalTimeConstant = 60 * core::kNsPerSec;
    std::uint8_t tpdo2EverySyncs = 10;  // 0: no TPDO2
};

struct DriveEmulatorStats {
    std::uint32_t framesHandled = 0;       // frames read from the bus while running
    std::uint32_t framesIgnored = 0;       // not ours (other ids, RTR, extended)
    std::uint32_t framesDiscarded = 0;     // read while off/crashed, or waiting at boot
    std::uint32_t frameBudgetHits = 0;     // steps that used the whole kMaxFramesPerStep budget
    std::uint32_t bootUps = 0;
    std::uint32_t heartbeatsSent = 0;
    std::uint32_t heartbeatsSuppressed = 0;  // setHeartbeatSuppressed(true)
    std::uint32_t nmtCommands = 0;         // obeyed (addressed to us or to all)
    std::uint32_t nmtOtherNode = 0;        // well-formed, for another node
    std::uint32_t nmtMalformed = 0;        // DLC != 2
    std::uint32_t nmtUnknownCommand = 0;
    std::uint32_t syncs = 0;               // SYNCs acted on (operational)
    std::uint32_t syncMalformed = 0;       // DLC != 0
    std::uint32_t rpdoReceived = 0;        // latched
    std::uint32_t rpdoApplied = 0;
    std::uint32_t rpdoMalformed = 0;       // DLC != 6 in operational (EMCY 0x8210)
    std::uint32_t rpdoNotOperational = 0;  // RPDO1 outside operational: ignored
    std::uint32_t tpdoSent = 0;
    std::uint32_t tpdo2Sent = 0;
    std::uint32_t sdoNotAllowed = 0;       // SDO requests in stopped: ignored
    std::uint32_t emcySent = 0;
    std::uint32_t emcySuppressed = 0;      // EMCY due in stopped: not sent
    std::uint32_t faults = 0;              // entries into fault reaction active
    std::uint32_t faultResets = 0;         // successful (fault -> switch on disabled)
    std::uint32_t faultResetsRefused = 0;  // rising edge while the cause remains
    std::uint32_t sendFailures = 0;        // frames the bus refused (SDO ones: sdoStats())
    std::uint32_t timeWentBack = 0;        // step() with an earlier time than the last
};

class Cia402DriveEmulator final : private SdoObjectDictionary {
public:
    static constexpr std::size_t kMaxFramesPerStep = 64;
    static constexpr std::size_t kMaxDiscardPerStep = 1024;
    static constexpr char kDeviceName[] = "RSE-SIM wheel drive";  // 0x1008 (19 bytes: segmented)
    static constexpr std::uint32_t kDeviceType = 0x00020192;           // 0x1000: CiA 402 servo drive

    // nodeId 1..127; any other id makes an emulator that never boots (valid() false).
    Cia402DriveEmulator(hal::CanBus& bus, std::uint8_t nodeId, const DriveEmulatorConfig& config = {});
    Cia402DriveEmulator(const Cia402DriveEmulator&) = delete;
    Cia402DriveEmulator& operator=(const Cia402DriveEmulator&) = delete;

    // ---- lifecycle (scenario hooks) ----
    void powerOn();   // off -> boots at the next step() (no effect unless off)
    void crash();     // silent at once: no heartbeat, no answers, power stage off
    void restart();   // power cycle: boots at the next step(), every object back to default
    void setHeartbeatSuppressed(bool suppressed) { heartbeatSuppressed_ = suppressed; }

    // ---- the simulator's time step ----
    void step(core::TimeNs now);

    // ---- physics and fault hooks ----
    void setLoadTorque(double torqueNm) { loadTorqueNm_ = torqueNm; }
    // Of the load, the share from pushing a blocked rover (WheelModel::setBlockTorqueNm).
    void setBlockTorque(double torqueNm) { blockTorqueNm_ = torqueNm; }
    void setDegradation(double currentFactor);  // 1.0 nominal; values <= 0 are ignored
    void failMotor();                           // EMCY 0x5000, fault; survives resets and power cycles
    void injectFault(std::uint16_t emcyCode);   // a one-shot, resettable fault with this code (non-zero)
    void setOverCurrentLimit(std::int32_t currentMa) { config_.overCurrentLimitMa = currentMa; }
    // Thermal hooks: the ambient the motor cools to (also its temperature when
    // set before the first step), and the heat gain factor (1 nominal; values
    // <= 0 or not finite are ignored).
    void setAmbientTemperature(double celsius);
    void setOverheat(double heatGainFactor);
    // Replaces the measurement noise settings and restarts both noise streams
    // from (seed, channel), as if constructed with them.
    void setMeasurementNoise(double currentSigmaMa, double velocitySigmaMradS, std::uint64_t seed,
                             std::size_t channel);

    // ---- truth for the simulator and tests ----
    bool valid() const { return valid_; }
    std::uint8_t nodeId() const { return nodeId_; }
    NodeLife life() const { return life_; }
    NmtState nmtState() const { return nmt_; }
    PowerState powerState() const { return power_; }
    std::uint16_t statusword() const;
    std::uint16_t controlword() const { return controlword_; }
    std::int32_t targetVelocityMradS() const { return targetVelocity_; }
    std::int8_t modeOfOperation() const { return mode_; }
    double wheelSpeedRadS() const { return velocity_; }
    double currentMa() const { return current_; }
    // The model's values quantised as TPDO1 / 0x606C / 0x6078 carry them, WITHOUT
    // the measurement noise (identical to the reports when the sigmas are 0).
    std::int32_t velocityActualMradS() const;
    std::int16_t currentActualMa() const;
    // The values in the last report (TPDO1 or SDO upload), noise included; 0
    // before the first report.
    std::int32_t lastReportedVelocityMradS() const { return reportedVelocity_; }
    std::int16_t lastReportedCurrentMa() const { return reportedCurrent_; }
    double loadTorqueNm() const { return loadTorqueNm_; }
    double degradation() const { return degradation_; }
    double temperatureC() const { return temperatureC_; }
    double overheat() const { return overheat_; }
    bool motorFailed() const { return motorFailed_; }
    std::uint8_t errorRegister() const;        // 0x1001
    std::uint16_t lastEmcyCode() const { return lastEmcyCode_; }
    std::uint16_t heartbeatPeriodMs() const { return heartbeatMs_; }
    std::uint8_t tpdoTransmissionType() const { return tpdoType_; }
    bool filtersInstalled() const { return filtersInstalled_; }
    const DriveEmulatorStats& stats() const { return stats_; }
    const SdoServerStats& sdoStats() const { return sdo_.stats(); }
    std::uint32_t lastSdoAbortCode() const { return sdo_.lastAbortCode(); }
    const DriveEmulatorConfig& config() const { return config_; }

private:
    // Active error conditions (each adds error register bits and one EMCY).
    static constexpr std::uint8_t kErrMotor = 0x01;
    static constexpr std::uint8_t kErrOverCurrent = 0x02;
    static constexpr std::uint8_t kErrInjected = 0x04;
    static constexpr std::uint8_t kErrPdoLength = 0x08;

    // SdoObjectDictionary
    std::uint32_t describe(std::uint16_t index, std::uint8_t subIndex, SdoObjectInfo* info) const override;
    std::uint32_t read(std::uint16_t index, std::uint8_t subIndex, std::uint8_t* out,
                       std::size_t capacity) override;
    std::uint32_t write(std::uint16_t index, std::uint8_t subIndex, const std::uint8_t* data, std::size_t size,
                        core::TimeNs now) override;

    void discardWaitingFrames();
    void resetCommunication();
    void resetApplication();
    void sendBootUp();
    void handleFrame(const hal::CanFrame& frame, core::TimeNs now);
    void handleNmt(const hal::CanFrame& frame, core::TimeNs now);
    void handleSync(const hal::CanFrame& frame, core::TimeNs now);
    void handleRpdo(const hal::CanFrame& frame, core::TimeNs now);
    void enterNmt(NmtState next);
    void abortConnection();
    void applyControlword(std::uint16_t controlword, core::TimeNs now);
    void detectFaults(core::TimeNs now);
    void raiseError(std::uint8_t kind, std::uint16_t code, core::TimeNs now);
    void sendEmcy(std::uint16_t code);
    void sendTpdo();
    void sendTpdo2();
    void sendHeartbeatIfDue(core::TimeNs now);
    std::int32_t reportVelocityMradS();  // one report: the value plus one noise draw
    std::int16_t reportCurrentMa();
    void advanceModel(core::TimeNs now);
    void advanceTemperature(double dts);
    bool torqueOn() const;
    double effectiveTargetRadS() const;
    bool send(const hal::CanFrame& frame);

    hal::CanBus& bus_;
    DriveEmulatorConfig config_;
    std::uint8_t nodeId_;
    bool valid_;
    bool filtersInstalled_ = false;
    SdoServer sdo_;

    // Node and NMT
    NodeLife life_ = NodeLife::kOff;
    NmtState nmt_ = NmtState::kInitialising;
    bool heartbeatSuppressed_ = false;
    std::uint16_t heartbeatMs_ = 0;  // 0x1017
    core::TimeNs nextHeartbeat_ = 0;
    std::uint8_t tpdoType_ = 1;  // 0x1800:02
    std::uint8_t syncsSinceTpdo_ = 0;
    std::uint8_t syncsSinceTpdo2_ = 0;

    // PDO latch
    bool rpdoLatched_ = false;
    std::uint16_t latchedControlword_ = 0;
    std::int32_t latchedTarget_ = 0;

    // CiA 402
    PowerState power_ = PowerState::kNotReadyToSwitchOn;
    core::TimeNs bootedAt_ = 0;
    core::TimeNs faultAt_ = 0;
    std::uint16_t controlword_ = 0;   // 0x6040
    std::int32_t targetVelocity_ = 0;  // 0x60FF
    std::int8_t mode_ = 0;            // 0x6060 / 0x6061 (0 = no mode until the master sets 3)

    // Errors
    std::uint8_t errors_ = 0;
    std::uint16_t injectedCode_ = 0;
    bool injectPending_ = false;
    bool motorFailed_ = false;
    bool overCurrentTripped_ = false;
    std::uint16_t lastEmcyCode_ = 0;

    // Motor model
    bool haveTime_ = false;
    core::TimeNs time_ = 0;  // the model's time (last step)
    double velocity_ = 0.0;  // rad/s
    double current_ = 0.0;   // mA
    double loadTorqueNm_;
    double blockTorqueNm_ = 0.0;
    double degradation_ = 1.0;
    double temperatureC_;
    double overheat_ = 1.0;
    bool overCurrentTiming_ = false;
    core::TimeNs overCurrentSince_ = 0;

    // Measurement noise
    SimRng currentRng_;
    SimRng velocityRng_;
    std::int16_t reportedCurrent_ = 0;
    std::int32_t reportedVelocity_ = 0;

    DriveEmulatorStats stats_;
};

}  // namespace rse::sim

#include "sim_stub/drives/cia402_drive_emulator.hpp"

#include <cmath>

#include "sim_stub/drives/canopen_le.hpp"

namespace rse::sim {

namespace {

// COB-ID function codes (docs/icd.md §1.2).
constexpr std::uint32_t kCobNmt = 0x000;
constexpr std::uint32_t kCobSync = 0x080;
constexpr std::uint32_t kCobEmcy = 0x080;
constexpr std::uint32_t kCobTpdo1 = 0x180;
constexpr std::uint32_t kCobTpdo2 = 0x280;
constexpr std::uint32_t kCobRpdo1 = 0x200;
constexpr std::uint32_t kCobSdoRequest = 0x600;
constexpr std::uint32_t kCobHeartbeat = 0x700;

constexpr std::uint8_t kNmtStart = 0x01;
constexpr std::uint8_t kNmtStop = 0x02;
constexpr std::uint8_t kNmtEnterPreOperational = 0x80;
constexpr std::uint8_t kNmtResetNode = 0x81;
constexpr std::uint8_t kNmtResetCommunication = 0x82;

constexpr std::uint8_t kRpdo1Dlc = 6;
constexpr std::uint8_t kProfileVelocityMode = 3;

// Statusword bits.
constexpr std::uint16_t kSwVoltageEnabled = 0x0010;
constexpr std::uint16_t kSwWarning = 0x0080;
constexpr std::uint16_t kSwRemote = 0x0200;
constexpr std::uint16_t kSwTargetReached = 0x0400;
constexpr std::uint16_t kSwInternalLimit = 0x0800;
constexpr std::uint16_t kSwSpeedZero = 0x1000;  // profile velocity mode: speed = 0

constexpr std::uint16_t kCwFaultReset = 0x0080;

constexpr std::size_t kMaxModelSubsteps = 100000;  // bounds one step's integration loop

// The object dictionary (docs/icd.md §1.4 and CiA 301/402). Size 0 = the device
// name string. PDO mappings and COB-IDs are static (read-only), as CiA 301 allows;
// a write answers 0x06010002.
enum class Access : std::uint8_t { kReadOnly, kReadWrite };
struct ObjectEntry {
    std::uint16_t index;
    std::uint8_t subIndex;
    std::uint8_t size;
    Access access;
};
constexpr ObjectEntry kObjects[] = {
    {0x1000, 0, 4, Access::kReadOnly},   // device type
    {0x1001, 0, 1, Access::kReadOnly},   // error register
    {0x1008, 0, 0, Access::kReadOnly},   // manufacturer device name (string)
    {0x1017, 0, 2, Access::kReadWrite},  // producer heartbeat time, ms
    {0x1018, 0, 1, Access::kReadOnly},   // identity: highest sub-index
    {0x1018, 1, 4, Access::kReadOnly},   //   vendor id (0: none registered)
    {0x1018, 2, 4, Access::kReadOnly},   //   product code
    {0x1018, 3, 4, Access::kReadOnly},   //   revision
    {0x1018, 4, 4, Access::kReadOnly},   //   serial number (= node id)
    {0x1400, 0, 1, Access::kReadOnly},   // RPDO1 communication: highest sub-index
    {0x1400, 1, 4, Access::kReadOnly},   //   COB-ID
    {0x1400, 2, 1, Access::kReadOnly},   //   transmission type (synchronous)
    {0x1600, 0, 1, Access::kReadOnly},   // RPDO1 mapping
    {0x1600, 1, 4, Access::kReadOnly},
    {0x1600, 2, 4, Access::kReadOnly},
    {0x1800, 0, 1, Access::kReadOnly},   // TPDO1 communication: highest sub-index
    {0x1800, 1, 4, Access::kReadOnly},   //   COB-ID
    {0x1800, 2, 1, Access::kReadWrite},  //   transmission type: 1..240 = every n-th SYNC
    {0x1A00, 0, 1, Access::kReadOnly},   // TPDO1 mapping
    {0x1A00, 1, 4, Access::kReadOnly},
    {0x1A00, 2, 4, Access::kReadOnly},
    {0x1A00, 3, 4, Access::kReadOnly},
    {0x6007, 0, 2, Access::kReadOnly},   // abort connection option code (2: disable voltage)
    {0x6040, 0, 2, Access::kReadWrite},  // controlword
    {0x6041, 0, 2, Access::kReadOnly},   // statusword
    {0x6060, 0, 1, Access::kReadWrite},  // modes of operation (3 only)
    {0x6061, 0, 1, Access::kReadOnly},   // modes of operation display
    {0x606C, 0, 4, Access::kReadOnly},   // velocity actual value, mrad/s
    {0x6078, 0, 2, Access::kReadOnly},   // current actual value, mA (ICD deviation from per mille)
    {0x60FF, 0, 4, Access::kReadWrite},  // target velocity, mrad/s
    {0x6502, 0, 4, Access::kReadOnly},   // supported drive modes: pv
};

constexpr std::size_t kDeviceNameLength = sizeof Cia402DriveEmulator::kDeviceName - 1;

constexpr std::uint32_t key(std::uint16_t index, std::uint8_t subIndex) {
    return (static_cast<std::uint32_t>(index) << 8U) | subIndex;
}

template <typename T>
T clampTo(long long v, long long lo, long long hi) {
    return static_cast<T>(v < lo ? lo : (v > hi ? hi : v));
}

double seconds(core::TimeNs t) { return static_cast<double>(t) / static_cast<double>(core::kNsPerSec); }

double noiseSigma(double sigma) { return std::isfinite(sigma) && sigma > 0.0 ? sigma : 0.0; }

}  // namespace

const char* toString(NmtState state) {
    switch (state) {
        case NmtState::kInitialising: return "initialising";
        case NmtState::kStopped: return "stopped";
        case NmtState::kOperational: return "operational";
        case NmtState::kPreOperational: return "pre-operational";
    }
    return "?";
}

const char* toString(NodeLife life) {
    switch (life) {
        case NodeLife::kOff: return "off";
        case NodeLife::kBooting: return "booting";
        case NodeLife::kRunning: return "running";
        case NodeLife::kCrashed: return "crashed";
    }
    return "?";
}

Cia402DriveEmulator::Cia402DriveEmulator(hal::CanBus& bus, std::uint8_t nodeId, const DriveEmulatorConfig& config)
    : bus_(bus), config_(config), nodeId_(nodeId), valid_(nodeId >= 1 && nodeId <= 127),
      sdo_(bus, static_cast<SdoObjectDictionary&>(*this), nodeId, config.sdoServerTimeout),
      loadTorqueNm_(config.loadTorqueNm),
      temperatureC_(std::isfinite(config.ambientC) ? config.ambientC : 20.0),
      currentRng_(config.noiseSeed, driveCurrentStream(config.noiseChannel)),
      velocityRng_(config.noiseSeed, driveVelocityStream(config.noiseChannel)) {
    config_.currentSigmaMa = noiseSigma(config_.currentSigmaMa);
    config_.velocitySigmaMradS = noiseSigma(config_.velocitySigmaMradS);
    if (valid_ && config_.installFilters) {
        const hal::CanFilter filters[] = {
            {kCobNmt, 0x7FF, false},
            {kCobSync, 0x7FF, false},
            {kCobRpdo1 + nodeId_, 0x7FF, false},
            {kCobSdoRequest + nodeId_, 0x7FF, false},
        };
        filtersInstalled_ = core::isOk(bus_.setFilters(filters, sizeof filters / sizeof filters[0]));
    }
}

// ---------------------------------------------------------------------------
// Hooks

void Cia402DriveEmulator::powerOn() {
    if (life_ == NodeLife::kOff) {
        life_ = NodeLife::kBooting;
    }
}

void Cia402DriveEmulator::crash() {
    if (life_ == NodeLife::kRunning || life_ == NodeLife::kBooting) {
        life_ = NodeLife::kCrashed;
    }
}

void Cia402DriveEmulator::restart() { life_ = NodeLife::kBooting; }

void Cia402DriveEmulator::setDegradation(double currentFactor) {
    if (currentFactor > 0.0) {
        degradation_ = currentFactor;
    }
}

void Cia402DriveEmulator::failMotor() { motorFailed_ = true; }

void Cia402DriveEmulator::setMeasurementNoise(double currentSigmaMa, double velocitySigmaMradS, std::uint64_t seed,
                                              std::size_t channel) {
    config_.currentSigmaMa = noiseSigma(currentSigmaMa);
    config_.velocitySigmaMradS = noiseSigma(velocitySigmaMradS);
    config_.noiseSeed = seed;
    config_.noiseChannel = channel;
    currentRng_ = SimRng(seed, driveCurrentStream(channel));
    velocityRng_ = SimRng(seed, driveVelocityStream(channel));
}

void Cia402DriveEmulator::setAmbientTemperature(double celsius) {
    if (!std::isfinite(celsius)) {
        return;
    }
    config_.ambientC = celsius;
    if (!haveTime_) {
        temperatureC_ = celsius;  // a motor that has not run yet sits at ambient
    }
}

void Cia402DriveEmulator::setOverheat(double heatGainFactor) {
    if (std::isfinite(heatGainFactor) && heatGainFactor > 0.0) {
        overheat_ = heatGainFactor;
    }
}

void Cia402DriveEmulator::injectFault(std::uint16_t emcyCode) {
    if (emcyCode != emcy::kNoError) {
        injectPending_ = true;
        injectedCode_ = emcyCode;
    }
}

// ---------------------------------------------------------------------------
// Step

void Cia402DriveEmulator::step(core::TimeNs now) {
    if (!valid_) {
        return;
    }
    if (haveTime_ && now < time_) {
        ++stats_.timeWentBack;
        now = time_;
    }
    advanceModel(now);  // the interval up to now belongs to the state before this step's frames
    if (life_ == NodeLife::kBooting) {
        discardWaitingFrames();  // sent while the controller was not yet listening
        life_ = NodeLife::kRunning;
        resetCommunication();
        resetApplication();
        bootedAt_ = now;
        sendBootUp();
    }
    if (life_ != NodeLife::kRunning) {
        discardWaitingFrames();
        return;
    }
    detectFaults(now);
    std::size_t handled = 0;
    hal::CanFrame frame;
    while (handled < kMaxFramesPerStep && core::isOk(bus_.receive(&frame))) {
        ++handled;
        handleFrame(frame, now);
        if (life_ != NodeLife::kRunning) {
            break;
        }
    }
    if (handled == kMaxFramesPerStep) {
        ++stats_.frameBudgetHits;
    }
    sdo_.poll(now);
    sendHeartbeatIfDue(now);
}

void Cia402DriveEmulator::discardWaitingFrames() {
    hal::CanFrame frame;
    for (std::size_t i = 0; i < kMaxDiscardPerStep && core::isOk(bus_.receive(&frame)); ++i) {
        ++stats_.framesDiscarded;
    }
}

// Reset communication: CiA 301 communication objects back to their defaults.
void Cia402DriveEmulator::resetCommunication() {
    nmt_ = NmtState::kInitialising;
    heartbeatMs_ = 0;
    nextHeartbeat_ = 0;
    tpdoType_ = 1;
    syncsSinceTpdo_ = 0;
    rpdoLatched_ = false;
    sdo_.reset();
    errors_ = static_cast<std::uint8_t>(errors_ & ~kErrPdoLength);
}

// Reset application: the drive's own objects and power state, as after power-on.
// What is physical (wheel speed, a failed motor, degradation, load) stays.
void Cia402DriveEmulator::resetApplication() {
    power_ = PowerState::kNotReadyToSwitchOn;
    controlword_ = 0;
    targetVelocity_ = 0;
    mode_ = 0;
    errors_ = 0;
    lastEmcyCode_ = emcy::kNoError;
    overCurrentTiming_ = false;
    current_ = 0.0;
}

void Cia402DriveEmulator::sendBootUp() {
    hal::CanFrame f;
    f.id = kCobHeartbeat + nodeId_;
    f.dlc = 1;
    f.data[0] = static_cast<std::uint8_t>(NmtState::kInitialising);
    if (send(f)) {
        ++stats_.bootUps;
    }
    nmt_ = NmtState::kPreOperational;
}

void Cia402DriveEmulator::handleFrame(const hal::CanFrame& frame, core::TimeNs now) {
    ++stats_.framesHandled;
    if (frame.extended() || frame.remote()) {
        ++stats_.framesIgnored;
        return;
    }
    if (frame.id == kCobNmt) {
        handleNmt(frame, now);
    } else if (frame.id == kCobSync) {
        handleSync(frame, now);
    } else if (frame.id == kCobRpdo1 + nodeId_) {
        handleRpdo(frame, now);
    } else if (frame.id == kCobSdoRequest + nodeId_) {
        if (nmt_ == NmtState::kStopped) {
            ++stats_.sdoNotAllowed;  // CiA 301: no SDO in stopped
        } else {
            sdo_.onRequest(frame, now);
        }
    } else {
        ++stats_.framesIgnored;
    }
}

void Cia402DriveEmulator::handleNmt(const hal::CanFrame& frame, core::TimeNs now) {
    if (frame.dlc != 2) {
        ++stats_.nmtMalformed;
        return;
    }
    const std::uint8_t target = frame.data[1];
    if (target != 0 && target != nodeId_) {
        ++stats_.nmtOtherNode;
        return;
    }
    switch (frame.data[0]) {
        case kNmtStart:
            enterNmt(NmtState::kOperational);
            break;
        case kNmtStop:
            enterNmt(NmtState::kStopped);
            break;
        case kNmtEnterPreOperational:
            enterNmt(NmtState::kPreOperational);
            break;
        case kNmtResetNode:
            resetCommunication();
            resetApplication();
            bootedAt_ = now;
            sendBootUp();
            break;
        case kNmtResetCommunication:
            abortConnection();
            resetCommunication();
            sendBootUp();
            break;
        default:
            ++stats_.nmtUnknownCommand;
            return;
    }
    ++stats_.nmtCommands;
}

void Cia402DriveEmulator::enterNmt(NmtState next) {
    if (next == nmt_) {
        return;
    }
    const bool leavingOperational = nmt_ == NmtState::kOperational;
    nmt_ = next;
    rpdoLatched_ = false;
    syncsSinceTpdo_ = 0;
    if (next == NmtState::kStopped) {
        sdo_.reset();
    }
    if (leavingOperational || next == NmtState::kStopped) {
        abortConnection();
    }
}

// CiA 402 0x6007 = 2: the connection to the master is gone: "disable voltage".
void Cia402DriveEmulator::abortConnection() {
    switch (power_) {
        case PowerState::kReadyToSwitchOn:
        case PowerState::kSwitchedOn:
        case PowerState::kOperationEnabled:
        case PowerState::kQuickStopActive:
            power_ = PowerState::kSwitchOnDisabled;
            break;
        default:
            break;
    }
}

void Cia402DriveEmulator::handleSync(const hal::CanFrame& frame, core::TimeNs now) {
    if (frame.dlc != 0) {
        ++stats_.syncMalformed;  // no SYNC counter configured (0x1019 absent): DLC must be 0
        return;
    }
    if (nmt_ != NmtState::kOperational) {
        return;  // SYNC is heard in pre-operational, but there are no PDOs to act on
    }
    ++stats_.syncs;
    if (rpdoLatched_) {
        rpdoLatched_ = false;
        ++stats_.rpdoApplied;
        targetVelocity_ = latchedTarget_;
        applyControlword(latchedControlword_, now);
    }
    ++syncsSinceTpdo_;
    if (syncsSinceTpdo_ >= tpdoType_) {
        syncsSinceTpdo_ = 0;
        sendTpdo();
    }
    if (config_.tpdo2EverySyncs != 0 && ++syncsSinceTpdo2_ >= config_.tpdo2EverySyncs) {
        syncsSinceTpdo2_ = 0;
        sendTpdo2();
    }
}

void Cia402DriveEmulator::handleRpdo(const hal::CanFrame& frame, core::TimeNs now) {
    if (nmt_ != NmtState::kOperational) {
        ++stats_.rpdoNotOperational;
        return;
    }
    if (frame.dlc != kRpdo1Dlc) {
        ++stats_.rpdoMalformed;
        raiseError(kErrPdoLength, emcy::kPdoLength, now);
        return;
    }
    ++stats_.rpdoReceived;
    rpdoLatched_ = true;
    latchedControlword_ = le::u16(&frame.data[0]);
    latchedTarget_ = le::i32(&frame.data[2]);
    if ((errors_ & kErrPdoLength) != 0) {
        errors_ = static_cast<std::uint8_t>(errors_ & ~kErrPdoLength);
        sendEmcy(emcy::kNoError);  // the length error is gone
    }
}

// ---------------------------------------------------------------------------
// CiA 402 power state machine

void Cia402DriveEmulator::applyControlword(std::uint16_t controlword, core::TimeNs) {
    const bool resetEdge = (controlword_ & kCwFaultReset) == 0 && (controlword & kCwFaultReset) != 0;
    controlword_ = controlword;
    switch (power_) {
        case PowerState::kNotReadyToSwitchOn:
        case PowerState::kFaultReactionActive:
            return;
        case PowerState::kFault:
            if (!resetEdge) {
                return;
            }
            if (motorFailed_) {
                ++stats_.faultResetsRefused;  // the cause is still there
                return;
            }
            errors_ = static_cast<std::uint8_t>(errors_ & kErrPdoLength);
            overCurrentTiming_ = false;
            power_ = PowerState::kSwitchOnDisabled;
            ++stats_.faultResets;
            sendEmcy(emcy::kNoError);
            return;
        default:
            break;
    }
    const bool disableVoltage = (controlword & 0x82U) == 0x00U;
    const bool quickStop = (controlword & 0x86U) == 0x02U;
    const bool shutdown = (controlword & 0x87U) == 0x06U;
    const bool switchOn = (controlword & 0x8FU) == 0x07U;  // also "disable operation"
    const bool enableOperation = (controlword & 0x8FU) == 0x0FU;
    switch (power_) {
        case PowerState::kSwitchOnDisabled:
            if (shutdown) {
                power_ = PowerState::kReadyToSwitchOn;  // 2
            }
            break;
        case PowerState::kReadyToSwitchOn:
            if (switchOn) {
                power_ = PowerState::kSwitchedOn;  // 3
            } else if (enableOperation) {
                power_ = PowerState::kOperationEnabled;  // 3 + 4
            } else if (disableVoltage || quickStop) {
                power_ = PowerState::kSwitchOnDisabled;  // 7
            }
            break;
        case PowerState::kSwitchedOn:
            if (enableOperation) {
                power_ = PowerState::kOperationEnabled;  // 4
            } else if (shutdown) {
                power_ = PowerState::kReadyToSwitchOn;  // 6
            } else if (disableVoltage || quickStop) {
                power_ = PowerState::kSwitchOnDisabled;  // 10
            }
            break;
        case PowerState::kOperationEnabled:
            if (switchOn) {
                power_ = PowerState::kSwitchedOn;  // 5
            } else if (shutdown) {
                power_ = PowerState::kReadyToSwitchOn;  // 8
            } else if (disableVoltage) {
                power_ = PowerState::kSwitchOnDisabled;  // 9
            } else if (quickStop) {
                power_ = PowerState::kQuickStopActive;  // 11
            }
            break;
        case PowerState::kQuickStopActive:
            if (disableVoltage) {
                power_ = PowerState::kSwitchOnDisabled;  // 12
            } else if (enableOperation) {
                power_ = PowerState::kOperationEnabled;  // 16
            }
            break;
        default:
            break;
    }
}

void Cia402DriveEmulator::detectFaults(core::TimeNs now) {
    if (motorFailed_ && (errors_ & kErrMotor) == 0) {
        raiseError(kErrMotor, emcy::kMotorFailed, now);
    }
    if (injectPending_) {
        injectPending_ = false;
        raiseError(kErrInjected, injectedCode_, now);
    }
    if (power_ == PowerState::kNotReadyToSwitchOn && now > bootedAt_) {
        power_ = PowerState::kSwitchOnDisabled;  // 1: self-test done
    }
    if (power_ == PowerState::kFaultReactionActive && now - faultAt_ >= config_.faultReactionTime) {
        power_ = PowerState::kFault;  // 14
    }
}

void Cia402DriveEmulator::raiseError(std::uint8_t kind, std::uint16_t code, core::TimeNs now) {
    if ((errors_ & kind) != 0 && (kind != kErrInjected || injectedCode_ == code)) {
        return;  // already active and reported
    }
    errors_ = static_cast<std::uint8_t>(errors_ | kind);
    if (kind != kErrPdoLength && power_ != PowerState::kFaultReactionActive && power_ != PowerState::kFault) {
        power_ = PowerState::kFaultReactionActive;  // 13
        faultAt_ = now;
        ++stats_.faults;
    }
    sendEmcy(code);
}

std::uint8_t Cia402DriveEmulator::errorRegister() const {
    std::uint8_t r = 0;
    if (errors_ != 0) {
        r |= 0x01;  // generic
    }
    if ((errors_ & kErrOverCurrent) != 0) {
        r |= 0x02;  // current
    }
    if ((errors_ & kErrInjected) != 0) {
        switch (injectedCode_ >> 12U) {
            case 0x2: r |= 0x02; break;  // current
            case 0x3: r |= 0x04; break;  // voltage
            case 0x4: r |= 0x08; break;  // temperature
            case 0x8: r |= 0x10; break;  // communication
            default: break;
        }
    }
    if ((errors_ & kErrPdoLength) != 0) {
        r |= 0x10;  // communication
    }
    return r;
}

std::uint16_t Cia402DriveEmulator::statusword() const {
    std::uint16_t sw = 0;
    switch (power_) {
        case PowerState::kNotReadyToSwitchOn: return 0x0000;
        case PowerState::kSwitchOnDisabled: sw = 0x0040; break;
        case PowerState::kReadyToSwitchOn: sw = 0x0021; break;
        case PowerState::kSwitchedOn: sw = 0x0023 | kSwVoltageEnabled; break;
        case PowerState::kOperationEnabled: sw = 0x0027 | kSwVoltageEnabled; break;
        case PowerState::kQuickStopActive: sw = 0x0007 | kSwVoltageEnabled; break;
        case PowerState::kFaultReactionActive: sw = 0x000F | kSwVoltageEnabled; break;
        case PowerState::kFault: sw = 0x0008; break;
    }
    sw |= kSwRemote;
    if (overCurrentTiming_) {
        sw |= kSwWarning;
    }
    const std::int32_t v = velocityActualMradS();
    const auto absDiff = [](std::int64_t a, std::int64_t b) { return a > b ? a - b : b - a; };
    if (power_ == PowerState::kOperationEnabled) {
        const std::int64_t target = std::llround(effectiveTargetRadS() * 1000.0);
        if (absDiff(v, target) <= config_.velocityWindowMradS) {
            sw |= kSwTargetReached;
        }
        if (mode_ == kProfileVelocityMode &&
            (targetVelocity_ > config_.speedLimitMradS || targetVelocity_ < -config_.speedLimitMradS)) {
            sw |= kSwInternalLimit;
        }
    }
    if (power_ == PowerState::kQuickStopActive && absDiff(v, 0) <= config_.velocityWindowMradS) {
        sw |= kSwTargetReached;
    }
    if ((power_ == PowerState::kOperationEnabled || power_ == PowerState::kQuickStopActive) &&
        absDiff(v, 0) <= config_.speedZeroThresholdMradS) {
        sw |= kSwSpeedZero;
    }
    return sw;
}

// ---------------------------------------------------------------------------
// Frames out

bool Cia402DriveEmulator::send(const hal::CanFrame& frame) {
    if (core::isOk(bus_.send(frame))) {
        return true;
    }
    ++stats_.sendFailures;
    return false;
}

void Cia402DriveEmulator::sendEmcy(std::uint16_t code) {
    lastEmcyCode_ = code;
    if (life_ != NodeLife::kRunning) {
        return;
    }
    if (nmt_ == NmtState::kStopped) {
        ++stats_.emcySuppressed;  // CiA 301: no EMCY in stopped
        return;
    }
    hal::CanFrame f;
    f.id = kCobEmcy + nodeId_;
    f.dlc = 8;
    le::put16(&f.data[0], code);
    f.data[2] = errorRegister();
    if (send(f)) {
        ++stats_.emcySent;
    }
}

void Cia402DriveEmulator::sendTpdo() {
    hal::CanFrame f;
    f.id = kCobTpdo1 + nodeId_;
    f.dlc = 8;
    le::put16(&f.data[0], statusword());
    le::putI32(&f.data[2], reportVelocityMradS());
    le::putI16(&f.data[6], reportCurrentMa());
    if (send(f)) {
        ++stats_.tpdoSent;
    }
}

void Cia402DriveEmulator::sendTpdo2() {
    hal::CanFrame f;
    f.id = kCobTpdo2 + nodeId_;
    f.dlc = 2;
    le::putI16(&f.data[0], clampTo<std::int16_t>(std::llround(temperatureC_ * 10.0), INT16_MIN, INT16_MAX));
    if (send(f)) {
        ++stats_.tpdo2Sent;
    }
}

void Cia402DriveEmulator::sendHeartbeatIfDue(core::TimeNs now) {
    if (heartbeatMs_ == 0 || now < nextHeartbeat_) {
        return;
    }
    const core::TimeNs period = static_cast<core::TimeNs>(heartbeatMs_) * core::kNsPerMs;
    nextHeartbeat_ += period;
    if (nextHeartbeat_ <= now) {
        nextHeartbeat_ = now + period;  // a step came more than a period late: no burst
    }
    if (heartbeatSuppressed_) {
        ++stats_.heartbeatsSuppressed;
        return;
    }
    hal::CanFrame f;
    f.id = kCobHeartbeat + nodeId_;
    f.dlc = 1;
    f.data[0] = static_cast<std::uint8_t>(nmt_);
    if (send(f)) {
        ++stats_.heartbeatsSent;
    }
}

// ---------------------------------------------------------------------------
// Motor model

bool Cia402DriveEmulator::torqueOn() const {
    return life_ == NodeLife::kRunning && !motorFailed_ &&
           (power_ == PowerState::kOperationEnabled || power_ == PowerState::kQuickStopActive);
}

double Cia402DriveEmulator::effectiveTargetRadS() const {
    if (power_ != PowerState::kOperationEnabled || mode_ != kProfileVelocityMode) {
        return 0.0;
    }
    std::int32_t t = targetVelocity_;
    const std::int32_t limit = config_.speedLimitMradS > 0 ? config_.speedLimitMradS : 0;
    if (t > limit) {
        t = limit;
    } else if (t < -limit) {
        t = -limit;
    }
    return static_cast<double>(t) / 1000.0;
}

void Cia402DriveEmulator::advanceTemperature(double dts) {
    const double amps = current_ * 1e-3;
    const double tau = seconds(config_.thermalTimeConstant);
    const double cooling = tau > 0.0 ? (temperatureC_ - config_.ambientC) / tau : 0.0;
    temperatureC_ += dts * (config_.heatGainCPerA2S * overheat_ * amps * amps - cooling);
}

void Cia402DriveEmulator::advanceModel(core::TimeNs now) {
    if (!haveTime_) {
        haveTime_ = true;
        time_ = now;
        return;
    }
    const core::TimeNs h = config_.modelStep > 0 ? config_.modelStep : core::kNsPerMs;
    const double tau = seconds(config_.velocityTimeConstant);
    for (std::size_t n = 0; time_ < now && n < kMaxModelSubsteps; ++n) {
        const core::TimeNs remaining = now - time_;
        const core::TimeNs dt = (remaining > h && n + 1 < kMaxModelSubsteps) ? h : remaining;
        const double dts = seconds(dt);
        const double decay = tau > 0.0 ? std::exp(-dts / tau) : 0.0;
        const bool on = torqueOn();
        const double target = on ? effectiveTargetRadS() : 0.0;
        const double before = velocity_;
        velocity_ = target + (before - target) * decay;
        if (std::fabs(velocity_) < 1e-9 && target == 0.0) {
            velocity_ = 0.0;  // no denormal tail
        }
        time_ += dt;
        if (!on) {
            current_ = 0.0;
            overCurrentTiming_ = false;
            advanceTemperature(dts);
            continue;
        }
        const double acceleration = (velocity_ - before) / dts;
        current_ = degradation_ * (config_.noLoadCurrentMa + config_.currentPerTorqueMaPerNm * std::fabs(loadTorqueNm_) +
                                   config_.currentPerAccelMaPerRadS2 * std::fabs(acceleration));
        advanceTemperature(dts);
        if (current_ <= static_cast<double>(config_.overCurrentLimitMa)) {
            overCurrentTiming_ = false;
            continue;
        }
        if (!overCurrentTiming_) {
            overCurrentTiming_ = true;
            overCurrentSince_ = time_;
        } else if (time_ - overCurrentSince_ > config_.overCurrentTime) {
            overCurrentTiming_ = false;
            raiseError(kErrOverCurrent, emcy::kOverCurrent, time_);  // power stage off from here on
        }
    }
}

std::int32_t Cia402DriveEmulator::velocityActualMradS() const {
    return clampTo<std::int32_t>(std::llround(velocity_ * 1000.0), INT32_MIN, INT32_MAX);
}

std::int16_t Cia402DriveEmulator::currentActualMa() const {
    return clampTo<std::int16_t>(std::llround(current_), INT16_MIN, INT16_MAX);
}

// One report: the model value plus one noise draw, then quantised and saturated
// like the noise-free value. With sigma 0 nothing is drawn.
std::int32_t Cia402DriveEmulator::reportVelocityMradS() {
    if (config_.velocitySigmaMradS > 0.0) {
        const double v = velocity_ * 1000.0 + config_.velocitySigmaMradS * velocityRng_.gaussian();
        reportedVelocity_ = clampTo<std::int32_t>(std::llround(v), INT32_MIN, INT32_MAX);
    } else {
        reportedVelocity_ = velocityActualMradS();
    }
    return reportedVelocity_;
}

std::int16_t Cia402DriveEmulator::reportCurrentMa() {
    if (config_.currentSigmaMa > 0.0) {
        const double c = current_ + config_.currentSigmaMa * currentRng_.gaussian();
        reportedCurrent_ = clampTo<std::int16_t>(std::llround(c), INT16_MIN, INT16_MAX);
    } else {
        reportedCurrent_ = currentActualMa();
    }
    return reportedCurrent_;
}

// ---------------------------------------------------------------------------
// Object dictionary

std::uint32_t Cia402DriveEmulator::describe(std::uint16_t index, std::uint8_t subIndex, SdoObjectInfo* info) const {
    bool indexFound = false;
    for (const ObjectEntry& e : kObjects) {
        if (e.index != index) {
            continue;
        }
        indexFound = true;
        if (e.subIndex == subIndex) {
            info->size = e.size == 0 ? kDeviceNameLength : e.size;
            info->readable = true;
            info->writable = e.access == Access::kReadWrite;
            return sdo_abort::kNone;
        }
    }
    return indexFound ? sdo_abort::kSubIndexDoesNotExist : sdo_abort::kObjectDoesNotExist;
}

std::uint32_t Cia402DriveEmulator::read(std::uint16_t index, std::uint8_t subIndex, std::uint8_t* out,
                                        std::size_t capacity) {
    if (index == 0x1008 && subIndex == 0) {
        if (capacity < kDeviceNameLength) {
            return sdo_abort::kGeneralError;
        }
        for (std::size_t i = 0; i < kDeviceNameLength; ++i) {
            out[i] = static_cast<std::uint8_t>(kDeviceName[i]);
        }
        return sdo_abort::kNone;
    }
    std::uint32_t v = 0;
    switch (key(index, subIndex)) {
        case key(0x1000, 0): v = kDeviceType; break;
        case key(0x1001, 0): v = errorRegister(); break;
        case key(0x1017, 0): v = heartbeatMs_; break;
        case key(0x1018, 0): v = 4; break;
        case key(0x1018, 1): v = 0; break;
        case key(0x1018, 2): v = 0x00000402; break;
        case key(0x1018, 3): v = 0x00010000; break;
        case key(0x1018, 4): v = nodeId_; break;
        case key(0x1400, 0): v = 2; break;
        case key(0x1400, 1): v = kCobRpdo1 + nodeId_; break;
        case key(0x1400, 2): v = 1; break;
        case key(0x1600, 0): v = 2; break;
        case key(0x1600, 1): v = 0x60400010; break;
        case key(0x1600, 2): v = 0x60FF0020; break;
        case key(0x1800, 0): v = 2; break;
        case key(0x1800, 1): v = kCobTpdo1 + nodeId_; break;
        case key(0x1800, 2): v = tpdoType_; break;
        case key(0x1A00, 0): v = 3; break;
        case key(0x1A00, 1): v = 0x60410010; break;
        case key(0x1A00, 2): v = 0x606C0020; break;
        case key(0x1A00, 3): v = 0x60780010; break;
        case key(0x6007, 0): v = 2; break;
        case key(0x6040, 0): v = controlword_; break;
        case key(0x6041, 0): v = statusword(); break;
        case key(0x6060, 0): v = static_cast<std::uint8_t>(mode_); break;
        case key(0x6061, 0): v = static_cast<std::uint8_t>(mode_); break;
        case key(0x606C, 0): v = static_cast<std::uint32_t>(reportVelocityMradS()); break;
        case key(0x6078, 0): v = static_cast<std::uint16_t>(reportCurrentMa()); break;
        case key(0x60FF, 0): v = static_cast<std::uint32_t>(targetVelocity_); break;
        case key(0x6502, 0): v = 0x00000004; break;  // bit 2: profile velocity
        default: return sdo_abort::kObjectDoesNotExist;
    }
    if (capacity < 4) {
        return sdo_abort::kGeneralError;
    }
    le::put32(out, v);  // the server sends the object's size of these bytes
    return sdo_abort::kNone;
}

std::uint32_t Cia402DriveEmulator::write(std::uint16_t index, std::uint8_t subIndex, const std::uint8_t* data,
                                         std::size_t size, core::TimeNs now) {
    std::uint8_t bytes[4] = {};
    for (std::size_t i = 0; i < size && i < 4; ++i) {
        bytes[i] = data[i];
    }
    const std::uint32_t v = le::u32(bytes);
    switch (key(index, subIndex)) {
        case key(0x1017, 0):
            heartbeatMs_ = static_cast<std::uint16_t>(v);
            nextHeartbeat_ = now + static_cast<core::TimeNs>(heartbeatMs_) * core::kNsPerMs;
            return sdo_abort::kNone;
        case key(0x1800, 2):
            if (v < 1 || v > 240) {
                return sdo_abort::kValueRangeExceeded;  // only synchronous cyclic types are supported
            }
            tpdoType_ = static_cast<std::uint8_t>(v);
            syncsSinceTpdo_ = 0;
            return sdo_abort::kNone;
        case key(0x6040, 0):
            applyControlword(static_cast<std::uint16_t>(v), now);
            return sdo_abort::kNone;
        case key(0x6060, 0):
            if (static_cast<std::int8_t>(bytes[0]) != static_cast<std::int8_t>(kProfileVelocityMode)) {
                return sdo_abort::kValueRangeExceeded;  // profile velocity is the only mode
            }
            mode_ = static_cast<std::int8_t>(kProfileVelocityMode);
            return sdo_abort::kNone;
        case key(0x60FF, 0):
            targetVelocity_ = static_cast<std::int32_t>(v);
            return sdo_abort::kNone;
        default:
            return sdo_abort::kWriteToReadOnly;
    }
}

}  // namespace rse::sim

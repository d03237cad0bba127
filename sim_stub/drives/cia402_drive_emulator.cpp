#include "sim_stub/drives/cia402_drive_emulator.hpp"

#include <cmath>

#include "sim_stub/drives/canopen_le.hpp"
#include "sim_stub/drives/cia402_drive_codes.hpp"

// The node: construction and the scenario's hooks, the step, and CiA 301 (NMT,
// SYNC, the PDOs, heartbeat and EMCY). The power state machine is in
// cia402_drive_power.cpp, the motor and thermal models in cia402_drive_motor.cpp,
// the object dictionary in cia402_drive_objects.cpp.

namespace rse::sim {

namespace {

using namespace drive_codes;

constexpr std::uint8_t kNmtStart = 0x01;
constexpr std::uint8_t kNmtStop = 0x02;
constexpr std::uint8_t kNmtEnterPreOperational = 0x80;
constexpr std::uint8_t kNmtResetNode = 0x81;
constexpr std::uint8_t kNmtResetCommunication = 0x82;

constexpr std::uint8_t kRpdo1Dlc = 6;

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

}  // namespace rse::sim

#include "sim_stub/lockstep/lockstep_rig.hpp"

#include <cstring>

namespace rse::sim {

LockstepRig::LockstepRig(const std::string& scenarioPath) : LockstepRig(loadScenarioFile(scenarioPath)) {}

LockstepRig::LockstepRig(const Scenario& scenario)
    : scenario_(scenario),
      fswCan_(wire_.attach("fsw")),
      simCan_(wire_.attach("sim")),
      drives_(attachDrives(), scenario_),
      rover_(scenario_, *simCan_, drives_.wheels(), RoverSimWiring{&wire_, &drives_, nullptr}),
      fsw_(clock_, *fswCan_) {}

LockstepRig::~LockstepRig() {
    if (memoryConsole_ != nullptr) {
        std::fclose(memoryConsole_);
    }
}

core::Status LockstepRig::init() {
    memoryConsole_ = fmemopen(consoleText_, sizeof consoleText_ - 1, "w");
    if (memoryConsole_ != nullptr) {
        std::setvbuf(memoryConsole_, consoleBuffer_, _IOFBF, sizeof consoleBuffer_);
    }
    return initWith(memoryConsole_);
}

core::Status LockstepRig::init(std::FILE* console) { return initWith(console); }

core::Status LockstepRig::initWith(std::FILE* console) {
    // The rig is a lab bench: its in-memory ground (MemoryGround) and the mission
    // runner sign with the public lab key, so the rig asks for it here, as
    // rse-fsw --lab-key does. A test that loaded its own keys before init keeps them.
    if (fsw_.keys().size() == 0 && !core::isOk(fsw_.useLabKey())) {
        return core::Status::kNotInitialized;
    }
    // The anti-replay store in memory, provisioned as on a rover's first boot
    // (rse-fsw --auth-store-create), so every lockstep run uses the persisted
    // path; the AUTH_RESYNC nonce from the scenario's seed keeps runs repeatable.
    fsw_.attachAuthStore(&authStore_, true);
    fsw_.setAuthChallengeSeed((0x52534541ULL << 32) ^ scenario_.seed);
    const core::Status s = fsw_.init(console);
    if (core::isOk(s)) {
        drives_.powerOn();
        // A frame brings one drive status, at most one status per instrument
        // and a few commands (the plan executive's, at 10 Hz).
        (void)fsw_.bus().createPipe("test-probe", 16, &probe_);
        (void)fsw_.bus().subscribe(probe_, msg::ids::kDriveStatus);
        (void)fsw_.bus().subscribe(probe_, msg::ids::kInstrumentStatus);
        (void)fsw_.bus().subscribe(probe_, msg::ids::kInstrumentCommand);
        (void)fsw_.bus().subscribe(probe_, msg::ids::kPlanGoal);
    }
    return s;
}

void LockstepRig::runFor(core::TimeNs duration) {
    const core::TimeNs end = clock_.now() + duration;
    while (clock_.now() < end) {
        const core::TimeNs frameStart =
            static_cast<core::TimeNs>(fsw_.executive().nextFrame()) * app::kMinorFramePeriod;
        clock_.sleepUntil(frameStart);
        rover_.step(frameStart);
        fsw_.executive().runFrame();
        drainProbe();
        if (onFrame_ != nullptr) {
            onFrame_(*this);
        }
    }
}

void LockstepRig::commandAllWheels(double radPerSec) {
    double speeds[msg::kWheelCount];
    for (double& v : speeds) {
        v = radPerSec;
    }
    commandWheels(speeds);
}

void LockstepRig::commandWheels(const double (&radPerSec)[msg::kWheelCount]) {
    msg::WheelCommandMsg cmd{};
    cmd.timeNs = clock_.now();
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        cmd.velocityRadS[w] = radPerSec[w];
    }
    (void)fsw_.bus().publish(cmd);
}

void LockstepRig::commandBody(double speedMS, double yawRateRadS) {
    const tables::RoverGeometryTable& g = fsw_.tables().roverGeometry();
    const double r = static_cast<double>(g.wheel_radius_m);
    const double halfTurn =
        0.5 * yawRateRadS * static_cast<double>(g.skid_factor) * static_cast<double>(g.track_width_m);
    double speeds[msg::kWheelCount];
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        speeds[w] = (w < msg::kWheelCount / 2 ? speedMS - halfTurn : speedMS + halfTurn) / r;
    }
    commandWheels(speeds);
}

void LockstepRig::commandInstrument(msg::Instrument instrument, msg::InstrumentAction action, std::uint8_t targetId,
                                    std::uint16_t commandId, double maxDurationS, std::uint16_t extendsCommandId) {
    msg::InstrumentCommandMsg cmd{};
    cmd.timeNs = clock_.now();
    cmd.instrument = instrument;
    cmd.action = action;
    cmd.targetId = targetId;
    cmd.commandId = commandId;
    cmd.maxDurationS = maxDurationS;
    cmd.extendsCommandId = extendsCommandId;
    (void)fsw_.bus().publish(cmd);
}

bool LockstepRig::allDrivesOperational() const {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (fsw_.canIo().drive(w).state() != hal::DriveState::kOperational) {
            return false;
        }
    }
    return true;
}

unsigned LockstepRig::consoleCount(const char* text) {
    if (memoryConsole_ == nullptr) {
        return 0;
    }
    std::fflush(memoryConsole_);
    unsigned n = 0;
    for (const char* p = std::strstr(consoleText_, text); p != nullptr; p = std::strstr(p + 1, text)) {
        ++n;
    }
    return n;
}

const char* LockstepRig::consoleText() {
    if (memoryConsole_ != nullptr) {
        std::fflush(memoryConsole_);
    }
    return consoleText_;
}

std::array<hal::CanBus*, kWheelCount> LockstepRig::attachDrives() {
    std::array<hal::CanBus*, kWheelCount> out{};
    for (std::size_t w = 0; w < kWheelCount; ++w) {
        out[w] = wire_.attach("drive");
    }
    return out;
}

void LockstepRig::drainProbe() {
    msg::InstrumentStatusMsg instrument{};
    msg::InstrumentCommandMsg command{};
    while (core::isOk(fsw_.bus().receive(probe_, &inbox_))) {
        if (core::isOk(inbox_.decode(&status_))) {
            ++statusCount_;
        } else if (core::isOk(inbox_.decode(&instrument)) &&
                   static_cast<std::size_t>(instrument.instrument) < msg::kInstrumentCount) {
            instruments_[static_cast<std::size_t>(instrument.instrument)] = instrument;
            ++instrumentCount_;
        } else if (core::isOk(inbox_.decode(&command)) &&
                   static_cast<std::size_t>(command.instrument) < msg::kInstrumentCount) {
            commands_[static_cast<std::size_t>(command.instrument)] = command;
            ++commandCount_[static_cast<std::size_t>(command.instrument)];
        } else if (core::isOk(inbox_.decode(&planGoal_))) {
            ++planGoalCount_;
        }
    }
}

}  // namespace rse::sim

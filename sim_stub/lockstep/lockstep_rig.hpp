// Software in the loop: rse-fsw (FswApp) and rse-sim (RoverSim + DriveBank) in
// one process on one virtual clock and one in-memory CAN bus. Only CAN frames
// pass between them; the program driving the rig (a lockstep test, rse-demo)
// alone reads the simulator's truth.
//
// Each minor frame the simulator is stepped to the frame's start (devices answer
// what the flight software sent last frame, as real ones would within a cycle),
// then the executive runs the frame.
//
// Host side (sim_stub/): the lockstep tests and rse-demo use it; rse-fsw never
// links it.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fsw/app/fsw_app.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/nvm/record_store.hpp"
#include "sim_stub/drives/drive_bank.hpp"
#include "sim_stub/rover_sim.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

namespace rse::sim {

class LockstepRig {
public:
    // Throws ScenarioError when the file cannot be used (loadScenarioFile).
    explicit LockstepRig(const std::string& scenarioPath);
    // A scenario already loaded (and perhaps changed, e.g. another seed).
    explicit LockstepRig(const Scenario& scenario);
    ~LockstepRig();
    LockstepRig(const LockstepRig&) = delete;
    LockstepRig& operator=(const LockstepRig&) = delete;

    // Initialises the flight software (with an in-memory anti-replay store,
    // provisioned) and powers the drives. The console
    // (housekeeping lines and every event) goes to a memory buffer with a fixed
    // stdio buffer, so writing it allocates nothing (consoleCount, consoleText).
    core::Status init();
    // The same with the console written to `console` (e.g. stdout; nullptr:
    // quiet), which the rig does not close; consoleCount and consoleText then
    // see nothing.
    core::Status init(std::FILE* console);

    // Runs whole minor frames for at least `duration` of rover time.
    void runFor(core::TimeNs duration);
    // Runs until pred() holds (checked once after every frame, so it may consume
    // something) or the limit passes; returns whether it held.
    template <typename Pred>
    bool runUntil(Pred pred, core::TimeNs limit) {
        const core::TimeNs end = clock_.now() + limit;
        bool held = pred();
        while (!held && clock_.now() < end) {
            runFor(app::kMinorFramePeriod);
            held = pred();
        }
        return held;
    }

    // What a higher layer would publish: the same velocity on every wheel.
    void commandAllWheels(double radPerSec);
    void commandWheels(const double (&radPerSec)[msg::kWheelCount]);
    // Skid-steer wheel speeds for a body speed and yaw rate, with the rover's
    // geometry from the flight tables (what a trajectory follower would send).
    void commandBody(double speedMS, double yawRateRadS);
    bool allDrivesOperational() const;
    // What the plan executive would publish: one command to a science instrument
    // (cancel: commandId names the command to stop; extend: commandId is the
    // follow-on's id, extendsCommandId the command it continues, maxDurationS the extra work).
    void commandInstrument(msg::Instrument instrument, msg::InstrumentAction action, std::uint8_t targetId,
                           std::uint16_t commandId, double maxDurationS = 0.0, std::uint16_t extendsCommandId = 0);

    // Occurrences of text in what the memory console has written so far (e.g. "EVT 434 ").
    unsigned consoleCount(const char* text);
    // Everything the memory console has written so far (for a failing test to print).
    const char* consoleText();

    core::VirtualClock& clock() { return clock_; }
    app::FswApp& fsw() { return fsw_; }
    RoverSim& rover() { return rover_; }
    DriveBank& drives() { return drives_; }
    hal::MemoryCanBus& wire() { return wire_; }
    const Scenario& scenario() const { return scenario_; }
    // The flight software's latest published drive status (what a layer sees).
    const msg::DriveStatusMsg& driveStatus() const { return status_; }
    std::uint32_t driveStatusCount() const { return statusCount_; }
    // The flight software's latest InstrumentStatusMsg of each instrument, and how many came.
    const msg::InstrumentStatusMsg& instrumentStatus(msg::Instrument instrument) const {
        return instruments_[static_cast<std::size_t>(instrument) % msg::kInstrumentCount];
    }
    std::uint32_t instrumentStatusCount() const { return instrumentCount_; }
    // What was commanded on the flight bus (by the plan executive, or by
    // commandInstrument above): the latest InstrumentCommandMsg to each
    // instrument and how many came, and the latest PlanGoalMsg (the plan
    // executive's drive goals to the deliberative layer) and how many came.
    // Taken after every frame, so a count that moved names the frame.
    const msg::InstrumentCommandMsg& instrumentCommand(msg::Instrument instrument) const {
        return commands_[static_cast<std::size_t>(instrument) % msg::kInstrumentCount];
    }
    std::uint32_t instrumentCommandCount(msg::Instrument instrument) const {
        return commandCount_[static_cast<std::size_t>(instrument) % msg::kInstrumentCount];
    }
    const msg::PlanGoalMsg& planGoal() const { return planGoal_; }
    std::uint32_t planGoalCount() const { return planGoalCount_; }
    void setOnFrame(void (*callback)(LockstepRig&)) { onFrame_ = callback; }

private:
    std::array<hal::CanBus*, kWheelCount> attachDrives();
    core::Status initWith(std::FILE* console);
    void drainProbe();

    core::VirtualClock clock_;
    hal::MemoryCanBus wire_{clock_};
    Scenario scenario_;
    hal::MemoryCanEndpoint* fswCan_;
    hal::MemoryCanEndpoint* simCan_;
    DriveBank drives_;
    RoverSim rover_;
    app::FswApp fsw_;
    hal::MemoryRecordStore authStore_;  // the anti-replay store (a rover's file, in memory)
    core::PipeId probe_ = 0;
    core::Message inbox_{};
    msg::DriveStatusMsg status_{};
    std::uint32_t statusCount_ = 0;
    msg::InstrumentStatusMsg instruments_[msg::kInstrumentCount] = {};
    std::uint32_t instrumentCount_ = 0;
    msg::InstrumentCommandMsg commands_[msg::kInstrumentCount] = {};
    std::uint32_t commandCount_[msg::kInstrumentCount] = {};
    msg::PlanGoalMsg planGoal_{};
    std::uint32_t planGoalCount_ = 0;
    void (*onFrame_)(LockstepRig&) = nullptr;
    std::FILE* memoryConsole_ = nullptr;  // owned: the fmemopen stream over consoleText_
    char consoleBuffer_[4096] = {};
    char consoleText_[512 * 1024] = {};
};

}  // namespace rse::sim

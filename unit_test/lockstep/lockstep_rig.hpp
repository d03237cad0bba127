// Software in the loop: rse-fsw (FswApp) and rse-sim (RoverSim + DriveBank) in
// one process on one virtual clock and one in-memory CAN bus. Only CAN frames
// pass between them; the test harness alone reads the simulator's truth.
//
// Each minor frame the simulator is stepped to the frame's start (devices answer
// what the flight software sent last frame, as real ones would within a cycle),
// then the executive runs the frame.
#pragma once

#include <array>
#include <cstdio>
#include <cstring>
#include <string>

#include "fsw/app/fsw_app.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "sim_stub/drives/drive_bank.hpp"
#include "sim_stub/rover_sim.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

namespace rse::test {

class LockstepRig {
public:
    explicit LockstepRig(const std::string& scenarioPath) : LockstepRig(sim::loadScenarioFile(scenarioPath)) {}
    // A scenario already loaded (and perhaps changed, e.g. another seed).
    explicit LockstepRig(const sim::Scenario& scenario)
        : scenario_(scenario),
          fswCan_(wire_.attach("fsw")),
          simCan_(wire_.attach("sim")),
          drives_(attachDrives(), scenario_),
          rover_(scenario_, *simCan_, drives_.wheels(), sim::RoverSimWiring{&wire_, &drives_, nullptr}),
          fsw_(clock_, *fswCan_) {}

    ~LockstepRig() {
        if (console_ != nullptr) {
            std::fclose(console_);
        }
    }

    // The console (housekeeping lines and every event) goes to a memory buffer,
    // with a fixed stdio buffer so writing it allocates nothing.
    core::Status init() {
        console_ = fmemopen(consoleText_, sizeof consoleText_ - 1, "w");
        if (console_ != nullptr) {
            std::setvbuf(console_, consoleBuffer_, _IOFBF, sizeof consoleBuffer_);
        }
        const core::Status s = fsw_.init(console_);
        if (core::isOk(s)) {
            drives_.powerOn();
            (void)fsw_.bus().createPipe("test-probe", 8, &probe_);
            (void)fsw_.bus().subscribe(probe_, msg::ids::kDriveStatus);
        }
        return s;
    }

    // Runs whole minor frames for at least `duration` of rover time.
    void runFor(core::TimeNs duration) {
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
    void commandAllWheels(double radPerSec) {
        double speeds[msg::kWheelCount];
        for (double& v : speeds) {
            v = radPerSec;
        }
        commandWheels(speeds);
    }
    void commandWheels(const double (&radPerSec)[msg::kWheelCount]) {
        msg::WheelCommandMsg cmd{};
        cmd.timeNs = clock_.now();
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            cmd.velocityRadS[w] = radPerSec[w];
        }
        (void)fsw_.bus().publish(cmd);
    }
    // Skid-steer wheel speeds for a body speed and yaw rate, with the rover's
    // geometry from the flight tables (what a trajectory follower would send).
    void commandBody(double speedMS, double yawRateRadS) {
        const tables::RoverGeometryTable& g = fsw_.tables().roverGeometry();
        const double r = static_cast<double>(g.wheel_radius_m);
        const double halfTurn = 0.5 * yawRateRadS * static_cast<double>(g.skid_factor) *
                                static_cast<double>(g.track_width_m);
        double speeds[msg::kWheelCount];
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            speeds[w] = (w < msg::kWheelCount / 2 ? speedMS - halfTurn : speedMS + halfTurn) / r;
        }
        commandWheels(speeds);
    }
    bool allDrivesOperational() const {
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            if (fsw_.canIo().drive(w).state() != hal::DriveState::kOperational) {
                return false;
            }
        }
        return true;
    }

    // Occurrences of text in what the console has written so far (e.g. "EVT 434 ").
    unsigned consoleCount(const char* text) {
        std::fflush(console_);
        unsigned n = 0;
        for (const char* p = std::strstr(consoleText_, text); p != nullptr; p = std::strstr(p + 1, text)) {
            ++n;
        }
        return n;
    }

    // Everything the console has written so far (for a failing test to print).
    const char* consoleText() {
        std::fflush(console_);
        return consoleText_;
    }

    core::VirtualClock& clock() { return clock_; }
    app::FswApp& fsw() { return fsw_; }
    sim::RoverSim& rover() { return rover_; }
    sim::DriveBank& drives() { return drives_; }
    hal::MemoryCanBus& wire() { return wire_; }
    const sim::Scenario& scenario() const { return scenario_; }
    // The flight software's latest published drive status (what a layer sees).
    const msg::DriveStatusMsg& driveStatus() const { return status_; }
    std::uint32_t driveStatusCount() const { return statusCount_; }
    void setOnFrame(void (*callback)(LockstepRig&)) { onFrame_ = callback; }

private:
    std::array<hal::CanBus*, sim::kWheelCount> attachDrives() {
        std::array<hal::CanBus*, sim::kWheelCount> out{};
        for (std::size_t w = 0; w < sim::kWheelCount; ++w) {
            out[w] = wire_.attach("drive");
        }
        return out;
    }
    void drainProbe() {
        while (core::isOk(fsw_.bus().receive(probe_, &inbox_))) {
            if (core::isOk(inbox_.decode(&status_))) {
                ++statusCount_;
            }
        }
    }

    core::VirtualClock clock_;
    hal::MemoryCanBus wire_{clock_};
    sim::Scenario scenario_;
    hal::MemoryCanEndpoint* fswCan_;
    hal::MemoryCanEndpoint* simCan_;
    sim::DriveBank drives_;
    sim::RoverSim rover_;
    app::FswApp fsw_;
    core::PipeId probe_ = 0;
    core::Message inbox_{};
    msg::DriveStatusMsg status_{};
    std::uint32_t statusCount_ = 0;
    void (*onFrame_)(LockstepRig&) = nullptr;
    std::FILE* console_ = nullptr;
    char consoleBuffer_[4096] = {};
    char consoleText_[512 * 1024] = {};
};

}  // namespace rse::test

// Test helpers for the simulator suite: a fake wheel that follows its commanded
// speed at once, and CAN capture helpers.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fsw/core/clock.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "sim_stub/devices/device_emulator.hpp"
#include "sim_stub/world/kinematics.hpp"
#include "sim_stub/world/wheel_model.hpp"
#include "sim_stub/world/world.hpp"

namespace rse::test {

// Follows the commanded speed at once. Current = k * (no-load + |load| / Kt)
// while turning, 0 when stopped: enough to see loads in the power budget.
class FakeWheel final : public sim::WheelModel {
public:
    static constexpr double kNoLoadA = 0.2;
    static constexpr double kTorquePerAmp = 0.5;  // N*m/A at the wheel

    void command(double radS) { target_ = radS; }
    void setFactor(double k) { factor_ = k; }
    double load() const { return load_; }

    double wheelSpeedRadS() const override { return speed_; }
    void setLoadTorqueNm(double torqueNm) override { load_ = torqueNm; }
    void setBlockTorqueNm(double) override {}  // follows its command at once: never braking
    void step(core::TimeNs) override {
        speed_ = target_;
        current_ = std::fabs(speed_) > 0.0 ? factor_ * (kNoLoadA + std::fabs(load_) / kTorquePerAmp) : 0.0;
    }
    double currentA() const override { return current_; }

private:
    double target_ = 0.0;
    double speed_ = 0.0;
    double load_ = 0.0;
    double current_ = 0.0;
    double factor_ = 1.0;
};

struct FakeWheels {
    std::array<FakeWheel, sim::kWheelCount> w;

    std::array<sim::WheelModel*, sim::kWheelCount> models() {
        std::array<sim::WheelModel*, sim::kWheelCount> p{};
        for (std::size_t i = 0; i < sim::kWheelCount; ++i) {
            p[i] = &w[i];
        }
        return p;
    }
    // Left wheels (0-2) at left rad/s, right wheels (3-5) at right rad/s.
    void drive(double left, double right) {
        for (std::size_t i = 0; i < 3; ++i) {
            w[i].command(left);
            w[i + 3].command(right);
        }
    }
};

// Wheel speed arrays for World tests.
inline sim::WheelArray sides(double left, double right) { return {left, left, left, right, right, right}; }

// Every frame waiting on an endpoint (test code: allocation allowed).
inline std::vector<hal::CanFrame> drain(hal::CanBus& bus) {
    std::vector<hal::CanFrame> frames;
    hal::CanFrame f;
    while (core::isOk(bus.receive(&f))) {
        frames.push_back(f);
    }
    return frames;
}

inline std::size_t countId(const std::vector<hal::CanFrame>& frames, std::uint32_t id) {
    std::size_t n = 0;
    for (const hal::CanFrame& f : frames) {
        n += f.id == id ? 1U : 0U;
    }
    return n;
}

// The smallest scenario: seed 1, an open 20 m x 20 m site, the rover at the
// origin heading +x. Tests append the tables they need.
inline const std::string kOpenSiteScenario = R"(
seed = 1
[map]
x_min_m = -10.0
x_max_m = 10.0
y_min_m = -10.0
y_max_m = 10.0
[start]
x_m = 0.0
y_m = 0.0
)";

// The bench a device emulator's test steps one device on: an in-memory bus
// with a flight endpoint and the device's, a world, the time, and every frame
// the flight endpoint received with the world's truth when it came. open() in
// the test group's setup() and close() in its teardown() (CppUTest counts
// leaks between the two). A group takes it as a base beside Utest
// (TEST_GROUP_BASE).
struct DeviceBench {
    core::VirtualClock clock;
    hal::MemoryCanBus wire{clock};
    hal::MemoryCanEndpoint* flight = nullptr;
    hal::MemoryCanEndpoint* simPort = nullptr;
    sim::World* world = nullptr;
    sim::WheelArray speeds{};
    core::TimeNs t = 0;
    std::vector<hal::CanFrame> frames;
    std::vector<sim::TruthRecord> truthAtFrame;  // the world's truth when each frame was captured

    void open(const sim::Pose2& start) {
        flight = wire.attach("flight");
        simPort = wire.attach("sim");
        sim::WorldConfig c;
        c.start = start;
        world = new sim::World(c);
    }
    void close() {
        delete world;
        world = nullptr;
    }
    // Steps world and device every 1 ms up to and including until, capturing frames.
    void runUntil(sim::DeviceEmulator& device, core::TimeNs until) {
        for (; t <= until; t += core::kNsPerMs) {
            clock.sleepUntil(t);
            world->advance(t, speeds, sim::WheelArray{});
            device.step(t);
            hal::CanFrame f;
            while (core::isOk(flight->receive(&f))) {
                frames.push_back(f);
                truthAtFrame.push_back(world->truth());
            }
        }
    }
    std::vector<hal::CanFrame> withId(std::uint32_t id) const {
        std::vector<hal::CanFrame> out;
        for (const hal::CanFrame& f : frames) {
            if (f.id == id) {
                out.push_back(f);
            }
        }
        return out;
    }
    void clear() {
        frames.clear();
        truthAtFrame.clear();
    }
};

inline hal::CanFrame nmt(std::uint8_t command, std::uint8_t node) {
    hal::CanFrame f;
    f.id = 0x000;
    f.dlc = 2;
    f.data[0] = command;
    f.data[1] = node;
    return f;
}

}  // namespace rse::test

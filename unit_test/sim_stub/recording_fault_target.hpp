// A FaultTarget that writes every hook call into a log line, with the time the
// test says it is.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "sim_stub/scenario/fault_target.hpp"

namespace rse::test {

class RecordingFaultTarget final : public sim::FaultTarget {
public:
    core::TimeNs now = 0;
    std::vector<std::string> log;

    void degradeMotor(std::size_t wheel, double k) override { add("degrade %zu %.2f", wheel, k); }
    void failMotor(std::size_t wheel) override { add("fail %zu", wheel); }
    void overheatMotor(std::size_t wheel, double k) override { add("overheat %zu %.2f", wheel, k); }
    void faultDrive(std::size_t wheel, std::uint16_t code) override { add("drive-fault %zu 0x%04X", wheel, code); }
    void suppressHeartbeat(std::size_t wheel, bool on) override { add("heartbeat-loss %zu %s", wheel, onOff(on)); }
    void crashDrive(std::size_t wheel) override { add("crash-drive %zu", wheel); }
    void restartDrive(std::size_t wheel) override { add("restart-drive %zu", wheel); }
    void setDeviceDropout(sim::SimDevice d, bool on) override { add("dropout %s %s", sim::toString(d), onOff(on)); }
    void crashDevice(sim::SimDevice d) override { add("crash-device %s", sim::toString(d)); }
    void restartDevice(sim::SimDevice d) override { add("restart-device %s", sim::toString(d)); }
    void failInstrument(sim::SimDevice d, std::uint8_t code, bool silent, bool on) override {
        add("instrument-failure %s %u%s %s", sim::toString(d), static_cast<unsigned>(code), silent ? " silent" : "",
            onOff(on));
    }
    void stepImuBias(double delta) override { add("imu-bias %.3f", delta); }
    void addBusFault(const hal::CanFaultRule& r) override {
        add("bus-fault %d 0x%03X/0x%03X x%u", static_cast<int>(r.kind), static_cast<unsigned>(r.id),
            static_cast<unsigned>(r.mask), static_cast<unsigned>(r.count));
    }
    void babble(std::uint32_t id, double rate, bool on) override {
        add("babble 0x%03X %.0f %s", static_cast<unsigned>(id), rate, onOff(on));
    }
    void positionFixOutlier(double offsetM, double bearingRad, std::uint32_t count) override {
        add("fix-outlier %.2f %.4f x%u", offsetM, bearingRad, static_cast<unsigned>(count));
    }
    void slideRover(double offsetM, double bearingRad, double durationS) override {
        add("slide %.2f %.4f %.2f s", offsetM, bearingRad, durationS);
    }
    void stallFlightTask(std::size_t row, const std::string& name, bool on) override {
        if (name.empty()) {
            add("task-stall row %zu %s", row, onOff(on));
        } else {
            add("task-stall %s %s", name.c_str(), onOff(on));
        }
    }

private:
    static const char* onOff(bool on) { return on ? "on" : "off"; }
    template <typename... Args>
    void add(const char* format, Args... args) {
        char body[96];
        std::snprintf(body, sizeof body, format, args...);
        char line[128];
        std::snprintf(line, sizeof line, "%.3f %s", static_cast<double>(now) * 1e-9, body);
        log.emplace_back(line);
    }
};

}  // namespace rse::test

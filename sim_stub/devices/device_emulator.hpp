// Common behaviour of the simulated RSE devices (docs/icd.md §1.1-1.3): node ids
// 0x20-0x25, CANopen-style NMT slave, boot-up and heartbeat, fixed-rate data.
//
// Life cycle:
//   off        until the first step(): that step is power-on.
//   boot       sends the boot-up message (0x700+n, byte 0x00), enters
//              pre-operational, restarts the heartbeat (every 100 ms from the boot)
//              and the data schedule. After power-on, restart(), and an NMT reset
//              node (0x81) or reset communication (0x82) addressed to the node or
//              to all (node 0). Reset node and restart() also reset the device's
//              counters; reset communication keeps them.
//   pre-operational / operational
//              data frames flow in both (the flight master never starts these
//              devices: ICD §1.3's "PDOs only in operational" is read as applying
//              to the drives' PDOs, not to RSE device frames).
//   stopped    (NMT 0x02) only heartbeats (state 0x04); NMT start 0x01 or enter
//              pre-operational 0x80 resumes data.
// Fault hooks: setDropout(true) silences data frames but not heartbeats;
// crash() silences everything and ignores NMT (and every other frame) until
// restart().
// Frames other than NMT go to onDataFrame() (a device that takes commands:
// the science instruments), while powered and not crashed.
//
// The device keeps sampling while silent (stopped, dropout), so its counters
// advance and the receiver sees the gap. Incoming frames are either read from
// the bus by step() itself (pollsBus, the default) or handed in with onFrame()
// by an owner that shares one bus endpoint among several devices (RoverSim).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/canopen/canopen_ids.hpp"

namespace rse::sim {

constexpr core::TimeNs kDeviceHeartbeatPeriodNs = 100 * core::kNsPerMs;
constexpr std::size_t kDeviceMaxRxPerStep = 64;   // frames read per step when polling
constexpr std::size_t kDeviceMaxCatchUp = 16;     // samples sent in one step after a long step

struct DeviceStats {
    std::uint32_t dataFrames = 0;      // data frames the bus accepted
    std::uint32_t heartbeats = 0;      // heartbeat frames the bus accepted (boot-ups not included)
    std::uint32_t bootUps = 0;
    std::uint32_t nmtCommands = 0;     // NMT commands addressed to this node or all
    std::uint32_t suppressed = 0;      // data frames withheld: stopped or dropout
    std::uint32_t sendFailures = 0;    // frames the bus refused
    std::uint32_t samplesSkipped = 0;  // sample instants dropped beyond kDeviceMaxCatchUp
};

// Fixed-rate instants on the absolute timeline: first, first + period, ...
class PeriodicSchedule {
public:
    void start(core::TimeNs first, core::TimeNs period) {
        next_ = first;
        period_ = period > 0 ? period : 1;
    }
    // How many instants are due at now (at most max); later ones beyond max are
    // skipped and counted in *skipped so the schedule never falls behind.
    std::size_t take(core::TimeNs now, std::size_t max, std::uint32_t* skipped);
    core::TimeNs next() const { return next_; }

private:
    core::TimeNs next_ = 0;
    core::TimeNs period_ = 1;
};

class DeviceEmulator {
public:
    // Power-on on the first call; then receive (when polling), boot if due,
    // data frames, heartbeat.
    void step(core::TimeNs now);
    // An incoming frame: NMT (COB-ID 0x000, DLC 2) is acted on here, any other
    // goes to onDataFrame().
    void onFrame(const hal::CanFrame& frame);

    void setDropout(bool on) { dropout_ = on; }
    void crash();
    void restart();

    std::uint8_t nodeId() const { return nodeId_; }
    hal::canopen::NmtState nmtState() const { return state_; }
    bool crashed() const { return crashed_; }
    bool dropout() const { return dropout_; }
    const DeviceStats& stats() const { return stats_; }

protected:
    DeviceEmulator(hal::CanBus& bus, std::uint8_t nodeId, bool pollsBus)
        : bus_(bus), nodeId_(nodeId), pollsBus_(pollsBus) {}
    ~DeviceEmulator() = default;
    DeviceEmulator(const DeviceEmulator&) = delete;
    DeviceEmulator& operator=(const DeviceEmulator&) = delete;

    // At every boot: restart the data schedule from now; reset counters when
    // resetApplication (power-on, restart, NMT reset node).
    virtual void onBoot(core::TimeNs now, bool resetApplication) = 0;
    // Sample and send whatever is due at now (via sendData).
    virtual void produce(core::TimeNs now) = 0;
    // A frame that is not NMT, received since the last step (the device acts on
    // it at its next produce()). Ignored unless a device takes commands.
    virtual void onDataFrame(const hal::CanFrame& /*frame*/) {}

    // Sends a data frame unless stopped or in dropout (then counted as suppressed).
    void sendData(const hal::CanFrame& frame);
    DeviceStats& mutableStats() { return stats_; }

private:
    void boot(core::TimeNs now);
    bool sendRaw(const hal::CanFrame& frame);
    void sendState(hal::canopen::NmtState state);

    hal::CanBus& bus_;
    const std::uint8_t nodeId_;
    const bool pollsBus_;
    bool poweredOn_ = false;
    bool crashed_ = false;
    bool dropout_ = false;
    bool bootPending_ = true;
    bool resetApplicationPending_ = true;
    hal::canopen::NmtState state_ = hal::canopen::NmtState::kUnknown;
    PeriodicSchedule heartbeat_;
    DeviceStats stats_;
};

// Conversions shared by the devices: round to nearest and saturate.
std::int32_t saturateI32(double value);
std::int16_t saturateI16(double value);
std::uint16_t saturateU16(double value);

}  // namespace rse::sim

// What a fault schedule acts on. FaultScheduler calls these hooks at the
// scheduled times; RoverSim implements them (devices, bus faults, babbling) and
// forwards the drive hooks to whoever owns the drive emulators. Tests use a
// recording fake.
//
// A flight task stall is the one fault the simulator cannot cause itself: it
// only exchanges CAN frames. Whoever owns the ground link stalls the task as an
// operator would, with the EXEC_SET_TASK command (FlightTaskCommander below);
// RoverSim forwards stallFlightTask there, and reports the fault as not applied
// when there is nobody.
//
// wheel: 0..5 in ICD node order (0 front-left, 1 middle-left, 2 rear-left,
// 3 front-right, 4 middle-right, 5 rear-right). Scenario files number the
// wheels 1..6; the parser subtracts one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "hal/can/memory_can_bus.hpp"

namespace rse::sim {

enum class SimDevice : std::uint8_t { kImu = 0, kPower, kHazard, kPositionFix, kGrinder, kCamera };
constexpr std::size_t kSimDeviceCount = 6;
// The names scenario files use: "imu", "power", "hazard", "position_fix",
// "grinder", "camera".
const char* toString(SimDevice device);
// The science instruments among the devices (instrument_failure acts on these only).
constexpr bool isInstrument(SimDevice device) { return device == SimDevice::kGrinder || device == SimDevice::kCamera; }

class FaultTarget {
public:
    // The motor draws currentFactor times the current for the same torque (k >= 1).
    virtual void degradeMotor(std::size_t wheel, double currentFactor) = 0;
    // The motor heats heatGainFactor times faster for the same current (k >= 1).
    // A target without a thermal model ignores it.
    virtual void overheatMotor(std::size_t /*wheel*/, double /*heatGainFactor*/) {}
    // The drive takes a fault with this EMCY code (non-zero) that a fault reset
    // clears: EMCY, fault reaction, fault. A target without drives ignores it.
    virtual void faultDrive(std::size_t /*wheel*/, std::uint16_t /*emcyCode*/) {}
    // The motor no longer turns (the wheel locks); the drive reports the failure.
    virtual void failMotor(std::size_t wheel) = 0;
    // The drive keeps working but its heartbeat is (on) or is no longer (off) sent.
    virtual void suppressHeartbeat(std::size_t wheel, bool on) = 0;
    // The drive goes silent entirely / powers up again (boot-up, pre-operational).
    virtual void crashDrive(std::size_t wheel) = 0;
    virtual void restartDrive(std::size_t wheel) = 0;
    // Device data frames stop (on) or resume (off); heartbeats continue.
    virtual void setDeviceDropout(SimDevice device, bool on) = 0;
    virtual void crashDevice(SimDevice device) = 0;
    virtual void restartDevice(SimDevice device) = 0;
    // A science instrument (grinder, camera) fails with faultCode (1..255): it
    // reports failed with the code and refuses every command, or when silent
    // sends no report and ignores commands (its heartbeat goes on); off: healthy
    // again (idle). A target without instruments ignores it.
    virtual void failInstrument(SimDevice device, std::uint8_t faultCode, bool silent, bool on) = 0;
    // Adds deltaRadS to the IMU's yaw-rate bias.
    virtual void stepImuBias(double deltaRadS) = 0;
    // A rule for the in-memory bus (drop / corrupt / delay the next N matching frames).
    virtual void addBusFault(const hal::CanFaultRule& rule) = 0;
    // A node floods the bus with frames at cobId, framesPerSecond, until switched off.
    virtual void babble(std::uint32_t cobId, double framesPerSecond, bool on) = 0;
    // The next `count` position fixes are displaced by offsetM towards bearingRad
    // (map frame, counter-clockwise from +x), on top of their normal noise.
    virtual void positionFixOutlier(double offsetM, double bearingRad, std::uint32_t count) = 0;
    // The ground gives way: the rover slides offsetM towards bearingRad (map
    // frame, CCW from +x) over durationS (World::startSlide).
    virtual void slideRover(double offsetM, double bearingRad, double durationS) = 0;
    // The flight software's rate-group row stops running (on) or runs again
    // (off): `row`, or the row of task `name` when name is not empty. No
    // default: a target that cannot act on it must say so.
    virtual void stallFlightTask(std::size_t row, const std::string& name, bool on) = 0;

protected:
    ~FaultTarget() = default;
};

// Who can act on the flight software's rate-group rows: the owner of a ground
// link, with the authenticated EXEC_SET_TASK command (sim_stub/lockstep/
// memory_ground.hpp). Returns false when the command was not sent (a name it
// does not know, the link full); the flight software's own refusals come back
// in CMD_ACK.
class FlightTaskCommander {
public:
    virtual bool setFlightTaskEnabled(std::size_t row, const std::string& name, bool enabled) = 0;

protected:
    ~FlightTaskCommander() = default;
};

}  // namespace rse::sim

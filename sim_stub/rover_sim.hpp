// rse-sim's rover: the world, the four RSE sensor emulators, the two science
// instruments (grinder/sampler, camera: the scenario's targets), six wheel
// models and the scenario's fault schedule, advanced together in lockstep.
//
// step(now) does, in this fixed order (deterministic for a given scenario, seed
// and sequence of step times):
//   0. reads the frames waiting on its bus (at most kRoverSimMaxRxPerStep) and
//      hands each to the device emulators (NMT; the instruments' commands) and
//      to the optional frame listener;
//   1. wheel models: setLoadTorqueNm(load from the world's last step), step(now);
//   2. kinematics, loads and battery: World::advance(now, wheel speeds, currents);
//   3. device emulators step(now) (they send their frames; the instruments act
//      on the commands of step 0 and on the world of step 2), then babbling nodes;
//   4. fault schedule: every fault due at now is applied through the FaultTarget
//      hooks below (so it takes effect from the next step).
// Nothing allocates and nothing throws after construction.
//
// RoverSim is itself the FaultTarget: device hooks act on its emulators, bus
// faults go to the in-memory bus (when one is given), babbling nodes send on
// its bus, and the drive hooks are forwarded to the drive emulators' owner
// (RoverSimWiring::driveFaults), position-fix outliers to its position-fix
// emulator, flight task stalls to the ground link's owner (attachFlightTasks:
// it sends EXEC_SET_TASK). A hook with nobody to act on it (or, for an outlier,
// with an invalid offset, bearing or count) is counted in
// stats().faultsUnhandled; a task stall that could not be commanded is also
// counted in stats().taskStallsUnhandled and written to stderr, because no
// flight state changed and a test reading only the flight side would not know.
//
// The scenario is read only by the constructor (a program may change a loaded
// Scenario first, e.g. its seed). The drive emulators' measurement noise comes
// from the scenario too, but through DriveBank(buses, scenario).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "sim_stub/devices/hazard_detector_emulator.hpp"
#include "sim_stub/devices/imu_emulator.hpp"
#include "sim_stub/devices/instrument_emulator.hpp"
#include "sim_stub/devices/position_fix_emulator.hpp"
#include "sim_stub/devices/power_monitor_emulator.hpp"
#include "sim_stub/scenario/fault_scheduler.hpp"
#include "sim_stub/scenario/fault_target.hpp"
#include "sim_stub/scenario/scenario.hpp"
#include "sim_stub/world/wheel_model.hpp"
#include "sim_stub/world/world.hpp"

namespace rse::sim {

constexpr std::size_t kRoverSimMaxRxPerStep = 512;
constexpr std::size_t kMaxBabblers = 4;
constexpr std::size_t kMaxBabbleFramesPerStep = 4096;

// Receives every frame RoverSim reads from its bus (for drive emulators that
// share RoverSim's bus endpoint).
class SimFrameListener {
public:
    virtual void onFrame(const hal::CanFrame& frame, core::TimeNs now) = 0;

protected:
    ~SimFrameListener() = default;
};

struct RoverSimWiring {
    hal::MemoryCanBus* wire = nullptr;          // where bus_fault rules go (lockstep runs)
    FaultTarget* driveFaults = nullptr;         // the drive emulators' fault hooks
    SimFrameListener* frameListener = nullptr;  // gets every frame read from the bus
    FlightTaskCommander* flightTasks = nullptr; // the ground link's owner (task_stall); also attachFlightTasks
};

struct RoverSimStats {
    std::uint32_t steps = 0;
    std::uint32_t framesReceived = 0;
    std::uint32_t rxBacklogSteps = 0;   // steps that left frames unread (limit hit)
    std::uint32_t faultsApplied = 0;    // hooks that acted on something
    std::uint32_t faultsUnhandled = 0;  // hooks with nothing to act on (no wire / no drive target / full)
    std::uint32_t taskStallsUnhandled = 0;  // task_stall starts / ends no ground link commanded (also in faultsUnhandled)
    std::uint32_t babbleFrames = 0;     // babble frames the bus accepted
    std::uint32_t babbleRefused = 0;    // babble frames the bus refused
};

class RoverSim final : public FaultTarget {
public:
    // wheels: index 0..5 in ICD node order; a null entry is a wheel that never turns.
    RoverSim(const Scenario& scenario, hal::CanBus& bus, const std::array<WheelModel*, kWheelCount>& wheels,
             const RoverSimWiring& wiring = RoverSimWiring{});
    RoverSim(const RoverSim&) = delete;
    RoverSim& operator=(const RoverSim&) = delete;

    // Advances everything to now (ignored when now is earlier than the last step).
    void step(core::TimeNs now);

    const TruthRecord& truth() const { return world_.truth(); }
    const World& world() const { return world_; }
    World& world() { return world_; }
    ImuEmulator& imu() { return imu_; }
    PowerMonitorEmulator& powerMonitor() { return power_; }
    HazardDetectorEmulator& hazardDetector() { return hazard_; }
    PositionFixEmulator& positionFix() { return fix_; }
    InstrumentEmulator& grinder() { return grinder_; }
    InstrumentEmulator& camera() { return camera_; }
    const FaultScheduler& faultSchedule() const { return scheduler_; }
    const RoverSimStats& stats() const { return stats_; }
    // The ground link's owner, for task stalls (a rig builds its ground after the rover; nullptr: none).
    void attachFlightTasks(FlightTaskCommander* commander) { wiring_.flightTasks = commander; }
    core::TimeNs time() const { return time_; }

    // FaultTarget (also callable directly, e.g. by a test or an operator console).
    void degradeMotor(std::size_t wheel, double currentFactor) override;
    void failMotor(std::size_t wheel) override;
    void overheatMotor(std::size_t wheel, double heatGainFactor) override;
    void faultDrive(std::size_t wheel, std::uint16_t emcyCode) override;
    void suppressHeartbeat(std::size_t wheel, bool on) override;
    void crashDrive(std::size_t wheel) override;
    void restartDrive(std::size_t wheel) override;
    void setDeviceDropout(SimDevice device, bool on) override;
    void crashDevice(SimDevice device) override;
    void restartDevice(SimDevice device) override;
    // The grinder or camera fails (on) or is healthy again (off); another device: unhandled.
    void failInstrument(SimDevice device, std::uint8_t faultCode, bool silent, bool on) override;
    void stepImuBias(double deltaRadS) override;
    void addBusFault(const hal::CanFaultRule& rule) override;
    void babble(std::uint32_t cobId, double framesPerSecond, bool on) override;
    // Displaces the next `count` fixes (see PositionFixEmulator::injectOutlier).
    void positionFixOutlier(double offsetM, double bearingRad, std::uint32_t count) override;
    void slideRover(double offsetM, double bearingRad, double durationS) override;
    // Forwarded to the ground link's owner as EXEC_SET_TASK (disable when on, enable when off).
    void stallFlightTask(std::size_t row, const std::string& name, bool on) override;

private:
    struct Babbler {
        bool active = false;
        std::uint32_t cobId = 0;
        double rateHz = 0.0;
        core::TimeNs since = 0;
        std::uint64_t sent = 0;
    };

    DeviceEmulator& deviceFor(SimDevice device);
    bool driveTargetFor(std::size_t wheel);
    void receive();
    void stepBabblers();

    hal::CanBus& bus_;
    std::array<WheelModel*, kWheelCount> wheels_;
    RoverSimWiring wiring_;
    World world_;
    ImuEmulator imu_;
    PowerMonitorEmulator power_;
    HazardDetectorEmulator hazard_;
    PositionFixEmulator fix_;
    InstrumentEmulator grinder_;
    InstrumentEmulator camera_;
    FaultScheduler scheduler_;
    std::array<Babbler, kMaxBabblers> babblers_{};
    core::TimeNs time_ = 0;
    bool started_ = false;
    RoverSimStats stats_;
};

}  // namespace rse::sim

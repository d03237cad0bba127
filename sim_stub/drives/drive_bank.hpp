// The rover's six simulated wheel drives, wired to the rest of the simulator:
// each Cia402DriveEmulator sits on its own CAN endpoint (as six controllers
// would), is seen by the World as a WheelModel, and takes the scenario's drive
// faults (FaultTarget's drive hooks; RoverSim handles the device hooks itself).
//
// Built from a Scenario, it takes the drive node ids and the measurement noise
// ([drives] current_sigma_a, velocity_sigma_rad_s) with the scenario seed: drive
// w reports with noise streams (seed, w), so the same seed gives the same run.
#pragma once

#include <array>
#include <cstdint>

#include "hal/can/can_bus.hpp"
#include "sim_stub/drives/cia402_drive_emulator.hpp"
#include "sim_stub/scenario/fault_target.hpp"
#include "sim_stub/scenario/scenario.hpp"
#include "sim_stub/world/kinematics.hpp"
#include "sim_stub/world/wheel_model.hpp"

namespace rse::sim {

class DriveBank final : public FaultTarget {
public:
    // buses[w]: the endpoint of wheel w's drive; nodeIds from the scenario's rover.
    // Every drive gets `config` except noiseChannel, which is its wheel index.
    DriveBank(const std::array<hal::CanBus*, kWheelCount>& buses,
              const std::array<std::uint8_t, kWheelCount>& nodeIds, const DriveEmulatorConfig& config = {});
    // Node ids, measurement noise and noise seed from the scenario, the rest from base.
    DriveBank(const std::array<hal::CanBus*, kWheelCount>& buses, const Scenario& scenario,
              const DriveEmulatorConfig& base = {});
    // base with the scenario's measurement noise (converted to mA, mrad/s) and seed.
    static DriveEmulatorConfig configFor(const Scenario& scenario, const DriveEmulatorConfig& base = {});

    // Sets every drive's measurement noise and restarts its noise streams from
    // (seed, wheel index): for a bank built without the scenario.
    void setMeasurementNoise(const DriveNoiseParams& noise, std::uint64_t seed);

    void powerOn();
    // WheelModels for RoverSim, in wheel order.
    std::array<WheelModel*, kWheelCount> wheels();
    Cia402DriveEmulator& drive(std::size_t wheel) { return slots_[wheel].drive; }
    const Cia402DriveEmulator& drive(std::size_t wheel) const { return slots_[wheel].drive; }

    // FaultTarget: the drive hooks.
    void degradeMotor(std::size_t wheel, double currentFactor) override;
    void failMotor(std::size_t wheel) override;
    void overheatMotor(std::size_t wheel, double heatGainFactor) override;
    void faultDrive(std::size_t wheel, std::uint16_t emcyCode) override;
    void suppressHeartbeat(std::size_t wheel, bool on) override;
    void crashDrive(std::size_t wheel) override;
    void restartDrive(std::size_t wheel) override;
    // Device, bus and flight-task hooks belong to RoverSim, which never forwards them here.
    void setDeviceDropout(SimDevice, bool) override {}
    void crashDevice(SimDevice) override {}
    void restartDevice(SimDevice) override {}
    void failInstrument(SimDevice, std::uint8_t, bool, bool) override {}
    void stepImuBias(double) override {}
    void addBusFault(const hal::CanFaultRule&) override {}
    void babble(std::uint32_t, double, bool) override {}
    void positionFixOutlier(double, double, std::uint32_t) override {}
    void slideRover(double, double, double) override {}
    void stallFlightTask(std::size_t, const std::string&, bool) override {}

private:
    // One drive seen as a wheel: the emulator's units converted to the world's.
    class Wheel final : public WheelModel {
    public:
        explicit Wheel(Cia402DriveEmulator& drive) : drive_(drive) {}
        double wheelSpeedRadS() const override { return drive_.wheelSpeedRadS(); }
        void setLoadTorqueNm(double torqueNm) override { drive_.setLoadTorque(torqueNm); }
        void setBlockTorqueNm(double torqueNm) override { drive_.setBlockTorque(torqueNm); }
        void step(core::TimeNs now) override { drive_.step(now); }
        double currentA() const override { return drive_.currentMa() * 1e-3; }

    private:
        Cia402DriveEmulator& drive_;
    };
    struct Slot {
        Slot(hal::CanBus& bus, std::uint8_t nodeId, const DriveEmulatorConfig& config)
            : drive(bus, nodeId, config), wheel(drive) {}
        Cia402DriveEmulator drive;
        Wheel wheel;
    };
    static std::array<Slot, kWheelCount> makeSlots(const std::array<hal::CanBus*, kWheelCount>& buses,
                                                   const std::array<std::uint8_t, kWheelCount>& nodeIds,
                                                   const DriveEmulatorConfig& config);
    bool valid(std::size_t wheel) const { return wheel < kWheelCount; }

    std::array<Slot, kWheelCount> slots_;
};

}  // namespace rse::sim

#include "sim_stub/drives/drive_bank.hpp"

namespace rse::sim {

namespace {

DriveEmulatorConfig channel(DriveEmulatorConfig c, std::size_t wheel) {
    c.noiseChannel = wheel;
    return c;
}

}  // namespace

std::array<DriveBank::Slot, kWheelCount> DriveBank::makeSlots(const std::array<hal::CanBus*, kWheelCount>& b,
                                                              const std::array<std::uint8_t, kWheelCount>& n,
                                                              const DriveEmulatorConfig& c) {
    return {{{*b[0], n[0], channel(c, 0)},
             {*b[1], n[1], channel(c, 1)},
             {*b[2], n[2], channel(c, 2)},
             {*b[3], n[3], channel(c, 3)},
             {*b[4], n[4], channel(c, 4)},
             {*b[5], n[5], channel(c, 5)}}};
}

DriveBank::DriveBank(const std::array<hal::CanBus*, kWheelCount>& buses,
                     const std::array<std::uint8_t, kWheelCount>& nodeIds, const DriveEmulatorConfig& config)
    : slots_(makeSlots(buses, nodeIds, config)) {}

DriveBank::DriveBank(const std::array<hal::CanBus*, kWheelCount>& buses, const Scenario& scenario,
                     const DriveEmulatorConfig& base)
    : slots_(makeSlots(buses, scenario.rover.driveNodes, configFor(scenario, base))) {}

DriveEmulatorConfig DriveBank::configFor(const Scenario& scenario, const DriveEmulatorConfig& base) {
    DriveEmulatorConfig c = base;
    c.currentSigmaMa = scenario.drives.currentSigmaA * 1e3;
    c.velocitySigmaMradS = scenario.drives.velocitySigmaRadS * 1e3;
    c.noiseSeed = scenario.seed;
    c.ambientC = scenario.drives.ambientC;
    return c;
}

void DriveBank::setMeasurementNoise(const DriveNoiseParams& noise, std::uint64_t seed) {
    for (std::size_t w = 0; w < kWheelCount; ++w) {
        slots_[w].drive.setMeasurementNoise(noise.currentSigmaA * 1e3, noise.velocitySigmaRadS * 1e3, seed, w);
    }
}

void DriveBank::powerOn() {
    for (Slot& s : slots_) {
        s.drive.powerOn();
    }
}

std::array<WheelModel*, kWheelCount> DriveBank::wheels() {
    std::array<WheelModel*, kWheelCount> out{};
    for (std::size_t w = 0; w < kWheelCount; ++w) {
        out[w] = &slots_[w].wheel;
    }
    return out;
}

void DriveBank::degradeMotor(std::size_t wheel, double currentFactor) {
    if (valid(wheel)) {
        slots_[wheel].drive.setDegradation(currentFactor);
    }
}

void DriveBank::overheatMotor(std::size_t wheel, double heatGainFactor) {
    if (valid(wheel)) {
        slots_[wheel].drive.setOverheat(heatGainFactor);
    }
}

void DriveBank::faultDrive(std::size_t wheel, std::uint16_t emcyCode) {
    if (valid(wheel)) {
        slots_[wheel].drive.injectFault(emcyCode);
    }
}

void DriveBank::failMotor(std::size_t wheel) {
    if (valid(wheel)) {
        slots_[wheel].drive.failMotor();
    }
}

void DriveBank::suppressHeartbeat(std::size_t wheel, bool on) {
    if (valid(wheel)) {
        slots_[wheel].drive.setHeartbeatSuppressed(on);
    }
}

void DriveBank::crashDrive(std::size_t wheel) {
    if (valid(wheel)) {
        slots_[wheel].drive.crash();
    }
}

void DriveBank::restartDrive(std::size_t wheel) {
    if (valid(wheel)) {
        slots_[wheel].drive.restart();
    }
}

}  // namespace rse::sim

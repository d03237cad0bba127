#include "sim_stub/drives/drive_bank.hpp"

namespace rse::sim {

std::array<DriveBank::Slot, kWheelCount> DriveBank::makeSlots(const std::array<hal::CanBus*, kWheelCount>& b,
                                                              const std::array<std::uint8_t, kWheelCount>& n,
                                                              const DriveEmulatorConfig& c) {
    return {{{*b[0], n[0], c}, {*b[1], n[1], c}, {*b[2], n[2], c},
             {*b[3], n[3], c}, {*b[4], n[4], c}, {*b[5], n[5], c}}};
}

DriveBank::DriveBank(const std::array<hal::CanBus*, kWheelCount>& buses,
                     const std::array<std::uint8_t, kWheelCount>& nodeIds, const DriveEmulatorConfig& config)
    : slots_(makeSlots(buses, nodeIds, config)) {}

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

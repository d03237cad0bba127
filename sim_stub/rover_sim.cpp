#include "sim_stub/rover_sim.hpp"

#include <cmath>
#include <cstdio>

namespace rse::sim {

RoverSim::RoverSim(const Scenario& scenario, hal::CanBus& bus, const std::array<WheelModel*, kWheelCount>& wheels,
                   const RoverSimWiring& wiring)
    : bus_(bus),
      wheels_(wheels),
      wiring_(wiring),
      world_(scenario.worldConfig()),
      imu_(bus, world_, scenario.devices.imu, scenario.seed, false),
      power_(bus, world_, scenario.devices.power, scenario.seed, false),
      hazard_(bus, world_, scenario.devices.hazard, scenario.seed, false),
      fix_(bus, world_, scenario.devices.positionFix, scenario.seed, false),
      grinder_(bus, world_, hal::instrument::Kind::kGrinder, scenario.devices.grinder, scenario.targets, scenario.seed,
               false),
      camera_(bus, world_, hal::instrument::Kind::kCamera, scenario.devices.camera, scenario.targets, scenario.seed,
              false),
      scheduler_(scenario.faults, *this),
      time_(world_.time()) {}

void RoverSim::step(core::TimeNs now) {
    if (started_ && now < time_) {
        return;
    }
    started_ = true;
    time_ = now;
    ++stats_.steps;
    receive();

    WheelArray speeds{};
    WheelArray currents{};
    for (std::size_t i = 0; i < kWheelCount; ++i) {
        WheelModel* w = wheels_[i];
        if (w == nullptr) {
            continue;
        }
        w->setLoadTorqueNm(world_.loadTorqueNm(i));
        w->setBlockTorqueNm(world_.blockTorqueNm(i));
        w->step(now);
        speeds[i] = w->wheelSpeedRadS();
        currents[i] = w->currentA();
    }
    world_.advance(now, speeds, currents);

    imu_.step(now);
    power_.step(now);
    hazard_.step(now);
    fix_.step(now);
    grinder_.step(now);
    camera_.step(now);
    stepBabblers();

    scheduler_.step(now);
}

void RoverSim::receive() {
    hal::CanFrame frame;
    std::size_t taken = 0;
    while (taken < kRoverSimMaxRxPerStep && core::isOk(bus_.receive(&frame))) {
        ++taken;
        ++stats_.framesReceived;
        imu_.onFrame(frame);
        power_.onFrame(frame);
        hazard_.onFrame(frame);
        fix_.onFrame(frame);
        grinder_.onFrame(frame);
        camera_.onFrame(frame);
        if (wiring_.frameListener != nullptr) {
            wiring_.frameListener->onFrame(frame, time_);
        }
    }
    if (taken == kRoverSimMaxRxPerStep) {
        ++stats_.rxBacklogSteps;
    }
}

void RoverSim::stepBabblers() {
    for (Babbler& b : babblers_) {
        if (!b.active) {
            continue;
        }
        const double elapsedS = static_cast<double>(time_ - b.since) * 1e-9;
        const auto due = static_cast<std::uint64_t>(std::floor(elapsedS * b.rateHz));
        std::uint64_t toSend = due > b.sent ? due - b.sent : 0;
        if (toSend > kMaxBabbleFramesPerStep) {
            b.sent += toSend - kMaxBabbleFramesPerStep;  // beyond what one step may send: lost
            toSend = kMaxBabbleFramesPerStep;
        }
        hal::CanFrame f;
        f.id = b.cobId;
        f.dlc = 8;
        for (std::uint8_t& byte : f.data) {
            byte = 0xAA;
        }
        for (std::uint64_t i = 0; i < toSend; ++i) {
            ++b.sent;
            if (core::isOk(bus_.send(f))) {
                ++stats_.babbleFrames;
            } else {
                ++stats_.babbleRefused;
            }
        }
    }
}

DeviceEmulator& RoverSim::deviceFor(SimDevice device) {
    switch (device) {
        case SimDevice::kImu:
            return imu_;
        case SimDevice::kPower:
            return power_;
        case SimDevice::kHazard:
            return hazard_;
        case SimDevice::kPositionFix:
            return fix_;
        case SimDevice::kGrinder:
            return grinder_;
        case SimDevice::kCamera:
            return camera_;
    }
    return imu_;
}

void RoverSim::failInstrument(SimDevice device, std::uint8_t faultCode, bool silent, bool on) {
    InstrumentEmulator* instrument =
        device == SimDevice::kGrinder ? &grinder_ : (device == SimDevice::kCamera ? &camera_ : nullptr);
    if (instrument == nullptr || (on && !instrument->fail(faultCode, silent))) {
        ++stats_.faultsUnhandled;
        return;
    }
    if (!on) {
        instrument->clearFault();
    }
    ++stats_.faultsApplied;
}

bool RoverSim::driveTargetFor(std::size_t wheel) {
    if (wiring_.driveFaults == nullptr || wheel >= kWheelCount) {
        ++stats_.faultsUnhandled;
        return false;
    }
    ++stats_.faultsApplied;
    return true;
}

void RoverSim::degradeMotor(std::size_t wheel, double currentFactor) {
    if (driveTargetFor(wheel)) {
        wiring_.driveFaults->degradeMotor(wheel, currentFactor);
    }
}

void RoverSim::overheatMotor(std::size_t wheel, double heatGainFactor) {
    if (driveTargetFor(wheel)) {
        wiring_.driveFaults->overheatMotor(wheel, heatGainFactor);
    }
}

void RoverSim::faultDrive(std::size_t wheel, std::uint16_t emcyCode) {
    if (driveTargetFor(wheel)) {
        wiring_.driveFaults->faultDrive(wheel, emcyCode);
    }
}

void RoverSim::failMotor(std::size_t wheel) {
    if (driveTargetFor(wheel)) {
        wiring_.driveFaults->failMotor(wheel);
    }
}

void RoverSim::suppressHeartbeat(std::size_t wheel, bool on) {
    if (driveTargetFor(wheel)) {
        wiring_.driveFaults->suppressHeartbeat(wheel, on);
    }
}

void RoverSim::crashDrive(std::size_t wheel) {
    if (driveTargetFor(wheel)) {
        wiring_.driveFaults->crashDrive(wheel);
    }
}

void RoverSim::restartDrive(std::size_t wheel) {
    if (driveTargetFor(wheel)) {
        wiring_.driveFaults->restartDrive(wheel);
    }
}

void RoverSim::setDeviceDropout(SimDevice device, bool on) {
    deviceFor(device).setDropout(on);
    ++stats_.faultsApplied;
}

void RoverSim::crashDevice(SimDevice device) {
    deviceFor(device).crash();
    ++stats_.faultsApplied;
}

void RoverSim::restartDevice(SimDevice device) {
    deviceFor(device).restart();
    ++stats_.faultsApplied;
}

void RoverSim::stepImuBias(double deltaRadS) {
    imu_.stepBias(deltaRadS);
    ++stats_.faultsApplied;
}

void RoverSim::addBusFault(const hal::CanFaultRule& rule) {
    if (wiring_.wire != nullptr && core::isOk(wiring_.wire->addFault(rule))) {
        ++stats_.faultsApplied;
    } else {
        ++stats_.faultsUnhandled;
    }
}

void RoverSim::babble(std::uint32_t cobId, double framesPerSecond, bool on) {
    Babbler* slot = nullptr;
    for (Babbler& b : babblers_) {
        if (b.active && b.cobId == cobId) {
            slot = &b;
        }
    }
    if (!on) {
        if (slot != nullptr) {
            slot->active = false;
            ++stats_.faultsApplied;
        } else {
            ++stats_.faultsUnhandled;
        }
        return;
    }
    if (slot == nullptr) {
        for (Babbler& b : babblers_) {
            if (!b.active && slot == nullptr) {
                slot = &b;
            }
        }
    }
    if (slot == nullptr || !(framesPerSecond > 0.0)) {
        ++stats_.faultsUnhandled;
        return;
    }
    slot->active = true;
    slot->cobId = cobId;
    slot->rateHz = framesPerSecond;
    slot->since = time_;
    slot->sent = 0;
    ++stats_.faultsApplied;
}

void RoverSim::slideRover(double offsetM, double bearingRad, double durationS) {
    if (!(offsetM > 0.0) || !std::isfinite(offsetM) || !(durationS > 0.0) || !std::isfinite(durationS) ||
        !std::isfinite(bearingRad)) {
        ++stats_.faultsUnhandled;
        return;
    }
    world_.startSlide(offsetM, bearingRad, durationS);
    ++stats_.faultsApplied;
}

void RoverSim::stallFlightTask(std::size_t row, const std::string& name, bool on) {
    if (wiring_.flightTasks != nullptr && wiring_.flightTasks->setFlightTaskEnabled(row, name, !on)) {
        ++stats_.faultsApplied;
        return;
    }
    ++stats_.faultsUnhandled;
    ++stats_.taskStallsUnhandled;
    char task[48];
    if (name.empty()) {
        std::snprintf(task, sizeof task, "row %zu", row);
    } else {
        std::snprintf(task, sizeof task, "task %s", name.c_str());
    }
    std::fprintf(stderr, "rse-sim: [%.3f s] task_stall %s (%s) NOT APPLIED: %s\n", static_cast<double>(time_) * 1e-9,
                 on ? "start" : "end", task,
                 wiring_.flightTasks == nullptr ? "no ground link to send EXEC_SET_TASK on"
                                                : "the ground could not send EXEC_SET_TASK (unknown task or link full)");
}

void RoverSim::positionFixOutlier(double offsetM, double bearingRad, std::uint32_t count) {
    if (fix_.injectOutlier(offsetM, bearingRad, count)) {
        ++stats_.faultsApplied;
    } else {
        ++stats_.faultsUnhandled;
    }
}

}  // namespace rse::sim

// What the world needs from a wheel drive: its wheel's speed and current, and a
// place to put the ground's load torque. The CiA 402 drive emulator
// (sim_stub/drives/) is adapted to this; tests use a trivial fake.
//
// Units and signs: speed in rad/s of the wheel, + drives the rover forward on
// either side. Load torque in N*m, signed like the speed it opposes (a positive
// torque resists positive rotation: the motor must produce it to hold speed).
// Current in A drawn by the motor (its magnitude is what the battery sees).
// step(now) advances the model to the absolute time now; RoverSim calls
// setLoadTorqueNm then step once per RoverSim::step.
#pragma once

#include "fsw/core/clock.hpp"

namespace rse::sim {

class WheelModel {
public:
    virtual double wheelSpeedRadS() const = 0;
    virtual void setLoadTorqueNm(double torqueNm) = 0;
    // Of that load, the share from pushing against an obstacle (the wheel
    // slipping under a blocked rover): it resists the wheel only while the
    // drive pushes; told to slow down, the slip's friction stops the wheel.
    virtual void setBlockTorqueNm(double torqueNm) = 0;
    virtual void step(core::TimeNs now) = 0;
    virtual double currentA() const = 0;

protected:
    ~WheelModel() = default;
};

}  // namespace rse::sim

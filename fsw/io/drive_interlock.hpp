// The last line of defence for the wheels (the reflexive layer's reflex, applied
// where the wheel commands leave for the drives: the CAN I/O task, every frame,
// so it needs no other task to run): if any drive is not
// healthy (faulted, failed, lost) while the rover is commanded to move, every
// drive is commanded to zero at once, so a rover with one dead or runaway wheel
// does not keep driving on the others. The trip latches until ground's
// RESET_INTERLOCK (resetIfHealthy: only once every drive is healthy again).
#pragma once

#include "fsw/core/event_log.hpp"
#include "fsw/msg/drive_msgs.hpp"

namespace rse::io {

class DriveInterlock {
public:
    explicit DriveInterlock(core::EventLog& events) : events_(events) {}

    // Writes the velocities to send: the command, or all zeros when tripped.
    void apply(const msg::DriveStatusMsg& status, const double (&command)[msg::kWheelCount],
               double (&out)[msg::kWheelCount]);
    void reset();
    // Ground's RESET_INTERLOCK: releases the hold only when every drive in
    // `status` is healthy (else event 606 naming the wheel, and false).
    bool resetIfHealthy(const msg::DriveStatusMsg& status);
    bool tripped() const { return tripped_; }
    std::uint32_t trips() const { return trips_; }

private:
    core::EventLog& events_;
    bool tripped_ = false;
    std::uint32_t trips_ = 0;
};

}  // namespace rse::io

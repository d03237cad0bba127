// Persistence (debounce) with hysteresis for one threshold fault.
//
// While the fault is clear, its raise condition must hold on consecutive samples
// spanning at least the persistence time before the fault is raised; once
// raised, its clear condition must hold the same way before it clears. A sample
// that meets neither condition restarts the wait, so a value between the two
// thresholds neither raises nor clears.
//
// Time is the samples' own: a condition first seen at sample time t0 takes
// effect at the first sample t with t - t0 >= persist. The sample rate therefore
// adds up to one sample period (100 ms for a 10 Hz source).
//
// Every change needs at least two samples at different times, even with a zero
// persistence time: a condition that toggles on every sample never changes the
// fault's state, so it cannot flood the event log with raise/clear pairs.
#pragma once

#include <cstdint>

#include "fsw/core/clock.hpp"

namespace rse::estimator {

class PersistenceFilter {
public:
    enum class Edge : std::uint8_t { kNone = 0, kRaised, kCleared };

    Edge update(core::TimeNs sampleTime, bool raiseCondition, bool clearCondition, core::TimeNs persist) {
        const bool condition = active_ ? clearCondition : raiseCondition;
        if (!condition) {
            pending_ = false;
            return Edge::kNone;
        }
        // A sample older than the start of the wait (a source restarted its clock)
        // cannot prove the condition held: the wait starts again from it.
        if (!pending_ || sampleTime < since_) {
            pending_ = true;
            since_ = sampleTime;
            return Edge::kNone;
        }
        if (sampleTime == since_ || sampleTime - since_ < persist) {
            return Edge::kNone;
        }
        pending_ = false;
        active_ = !active_;
        return active_ ? Edge::kRaised : Edge::kCleared;
    }

    bool active() const { return active_; }
    // Sample time at which the condition now waited for was first seen (valid
    // while pending()).
    bool pending() const { return pending_; }
    core::TimeNs pendingSince() const { return since_; }

private:
    bool active_ = false;
    bool pending_ = false;
    core::TimeNs since_ = 0;
};

}  // namespace rse::estimator

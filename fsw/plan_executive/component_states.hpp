// The components a plan's activities ask about, as the executive knows them
// (docs/plan_executive.md "Component states"): each wheel's drive from its
// declared mode (DriveModesMsg: nominal ok, degraded degraded, failed
// failed, unknown degraded: not known to be ok), the grinder and the camera
// from their status (offline, or failed with a fault code: failed; else ok).
// Each change is evented (972: INFO back to ok, WARN otherwise). They are the
// SelectionInput's components of every selection, and the executive's check
// of the Asks of the activities not yet done. No bus.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

class ComponentStates {
public:
    explicit ComponentStates(core::EventLog& events) : events_(events) {}

    // The drives' declared modes (each within msg::kDriveModeCount); true
    // when a state changed.
    bool takeDriveModes(const msg::DriveModesMsg& m);
    // An instrument's status (instrument within msg::kInstrumentCount); true
    // when its state changed.
    bool takeInstrument(const msg::InstrumentStatusMsg& m);

    ComponentState state(Component c) const { return states_[static_cast<std::size_t>(c)]; }
    // An Ask holds now. A plan variable's is the selector's (causal links): true.
    bool holds(const Condition& c) const;
    // The states into a selection's input.
    void fill(SelectionInput* input) const;

private:
    core::EventLog& events_;
    ComponentState states_[kComponentCount] = {};
};

}  // namespace rse::plan_executive

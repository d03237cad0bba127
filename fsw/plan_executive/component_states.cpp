#include "fsw/plan_executive/component_states.hpp"

#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

namespace {

core::Severity severityOf(ComponentState s) {
    return s == ComponentState::kOk ? core::Severity::kInfo : core::Severity::kWarning;
}

}  // namespace

bool ComponentStates::takeDriveModes(const msg::DriveModesMsg& m) {
    bool changed = false;
    for (std::size_t w = 0; w < msg::kWheelCount && w < kComponentCount; ++w) {
        ComponentState now = ComponentState::kDegraded;  // degraded, and unknown: not known to be ok
        if (m.drives[w].declared == msg::DriveMode::kNominal) {
            now = ComponentState::kOk;
        } else if (m.drives[w].declared == msg::DriveMode::kFailed) {
            now = ComponentState::kFailed;
        }
        if (states_[w] != now) {
            states_[w] = now;
            changed = true;
            events_.report(events::kComponentState, severityOf(now), "plan_exec: %s now %s (declared drive mode %u)",
                           toString(static_cast<Component>(w)), toString(now),
                           static_cast<unsigned>(m.drives[w].declared));
        }
    }
    return changed;
}

bool ComponentStates::takeInstrument(const msg::InstrumentStatusMsg& m) {
    const Component component = m.instrument == msg::Instrument::kGrinder ? Component::kGrinder : Component::kCamera;
    const bool unusable = m.state == msg::InstrumentState::kOffline ||
                          (m.state == msg::InstrumentState::kFailed && m.faultCode != 0);
    const ComponentState now = unusable ? ComponentState::kFailed : ComponentState::kOk;
    ComponentState& c = states_[static_cast<std::size_t>(component)];
    if (c == now) {
        return false;
    }
    c = now;
    events_.report(events::kComponentState, severityOf(now), "plan_exec: %s now %s (instrument state %u, fault %u)",
                   toString(component), toString(now), static_cast<unsigned>(m.state),
                   static_cast<unsigned>(m.faultCode));
    return true;
}

bool ComponentStates::holds(const Condition& c) const {
    if (c.planVariable || c.variable >= kComponentCount) {
        return true;  // plan variables are the selector's (causal links)
    }
    const bool equal = static_cast<std::uint8_t>(states_[c.variable]) == c.value;
    return c.negated ? !equal : equal;
}

void ComponentStates::fill(SelectionInput* input) const {
    for (std::size_t c = 0; c < kComponentCount; ++c) {
        input->components[c] = states_[c];
    }
}

}  // namespace rse::plan_executive

// The rover mode and the software e-stop: their one owner. Every change is
// evented and announced on the bus (ModeMsg; CAN I/O, the layers and telemetry
// read it), and once at start-up. Ground sets the mode (SET_MODE, the command
// service's commands) and the e-stop (ESTOP_SET / ESTOP_CLEAR, mobility's
// commands, which see only its EstopSwitch face: estop_switch.hpp); an onboard
// layer may call home (SafeRequestMsg on the command router's onboard-request
// pipe), which puts the rover in SAFE. The command service checks every
// command against mode() (the dictionary's mode preconditions), and HK shows
// both (fillHousekeeping). Not part of the application interface: only the
// command service and fsw/app include it.
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/estop_switch.hpp"
#include "fsw/cmdtlm/housekeeping_contributor.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/deliberative_msgs.hpp"

namespace rse::cmdtlm {

// The mode the rover boots in: nothing moves until ground says so.
constexpr Mode kBootMode = Mode::kSafe;

class RoverMode final : public HousekeepingContributor, public EstopSwitch {
public:
    RoverMode(const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events)
        : clock_(clock), bus_(bus), events_(events) {}
    RoverMode(const RoverMode&) = delete;
    RoverMode& operator=(const RoverMode&) = delete;

    // Start-up: call homes come on the command router's onboard-request pipe.
    core::Status routeRequests(core::InputPipe& requests) { return requests.route<&RoverMode::takeSafeRequest>(this); }
    // Start-up: announces the boot mode.
    void announce() { publish(); }

    Mode mode() const { return mode_; }
    bool estop() const override { return estop_; }
    // SET_MODE: evented (205) and announced, even when the mode does not change.
    void setMode(Mode mode);
    // ESTOP_SET / ESTOP_CLEAR: evented (206, 207) and announced.
    void setEstop(bool set) override;

    std::uint32_t safeRequests() const { return safeRequests_; }  // call homes taken
    void fillHousekeeping(HK_Tlm& hk) const override;              // mode, estop

private:
    // A call home: counted and evented (215); the mode goes to SAFE unless it is there.
    void takeSafeRequest(const msg::SafeRequestMsg& request);
    void publish();

    const core::Clock& clock_;
    core::SoftwareBus& bus_;
    core::EventLog& events_;
    Mode mode_ = kBootMode;
    bool estop_ = false;
    std::uint32_t safeRequests_ = 0;
};

}  // namespace rse::cmdtlm

#include "hal/can/can_link_monitor.hpp"

#include "hal/can/can_events.hpp"

namespace rse::hal {

using core::Severity;

void CanLinkMonitor::check() {
    const CanBusState state = bus_.state();
    const CanBusStats& now = bus_.stats();
    if (first_ || state != lastState_) {
        const bool healthy = state == CanBusState::kErrorActive;
        events_.report(events::kCanStateChanged, healthy ? Severity::kInfo : Severity::kWarning,
                       "can %s: %s (bus-off %u times, %u error frames)", name_, toString(state),
                       static_cast<unsigned>(now.busOffCount), static_cast<unsigned>(now.errorFrames));
        first_ = false;
        lastState_ = state;
    }
    if (now.rxOverruns != last_.rxOverruns && core::isReportableOccurrence(++overrunEpisodes_)) {
        events_.report(events::kCanRxOverrun, Severity::kWarning, "can %s: %u frames lost on receive (total %u)",
                       name_, static_cast<unsigned>(now.rxOverruns - last_.rxOverruns),
                       static_cast<unsigned>(now.rxOverruns));
    }
    const std::uint32_t refusedNow = now.txUnavailable + now.txBufferFull;
    const std::uint32_t refusedBefore = last_.txUnavailable + last_.txBufferFull;
    if (refusedNow != refusedBefore && core::isReportableOccurrence(++txRefusedEpisodes_)) {
        events_.report(events::kCanTxRefused, Severity::kWarning,
                       "can %s: %u sends refused (queue full %u, link down/bus-off %u in total)", name_,
                       static_cast<unsigned>(refusedNow - refusedBefore),
                       static_cast<unsigned>(now.txBufferFull), static_cast<unsigned>(now.txUnavailable));
    }
    if (now.txInvalid != last_.txInvalid && core::isReportableOccurrence(++txInvalidEpisodes_)) {
        events_.report(events::kCanTxInvalid, Severity::kError, "can %s: %u malformed frames refused (total %u)",
                       name_, static_cast<unsigned>(now.txInvalid - last_.txInvalid),
                       static_cast<unsigned>(now.txInvalid));
    }
    last_ = now;
}

}  // namespace rse::hal

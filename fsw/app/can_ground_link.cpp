#include "fsw/app/can_ground_link.hpp"

namespace rse::app {

hal::IsoTpConfig CanGroundLink::config() {
    hal::IsoTpConfig c;
    c.txId = kGroundDownlinkCobId;
    c.rxId = kGroundUplinkCobId;
    c.blockSize = 8;  // docs/icd.md §2
    c.stMin = 0;
    return c;
}

CanGroundLink::CanGroundLink(hal::CanBus& can, const core::Clock& clock, core::EventLog& events)
    : channel_(can, clock, events, config()) {}

void CanGroundLink::service() {
    channel_.poll();
    if (!pending_) {
        std::size_t length = 0;
        if (core::isOk(channel_.receive(packet_, sizeof packet_, &length))) {
            pending_ = true;
            pendingLength_ = length;
        }
    }
    if (pending_ && !channel_.txBusy()) {
        // Busy transmitter: the packet waits (received ones queue in the channel,
        // whose overflow is counted there).
        if (core::isOk(channel_.send(packet_, pendingLength_))) {
            ++echoed_;
        } else {
            ++echoRefused_;
        }
        pending_ = false;
    }
}

}  // namespace rse::app

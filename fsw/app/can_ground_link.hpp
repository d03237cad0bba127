// The ground link on CAN: ISO-TP (docs/icd.md §2), rover receives on 0x6F0 and
// sends on 0x6F1. Until command ingest exists (the ground-link issue), every
// packet received is sent straight back: a link-test service that lets the
// operator (and the integration test) prove the round trip end to end.
#pragma once

#include "fsw/core/event_log.hpp"
#include "hal/can/isotp.hpp"
#include "hal/canopen/canopen_master.hpp"

namespace rse::app {

constexpr std::uint32_t kGroundUplinkCobId = 0x6F0;
constexpr std::uint32_t kGroundDownlinkCobId = 0x6F1;

class CanGroundLink final : public hal::canopen::CanFrameSink {
public:
    CanGroundLink(hal::CanBus& can, const core::Clock& clock, core::EventLog& events);

    void onFrame(const hal::CanFrame& frame, core::TimeNs) override { channel_.onFrame(frame); }
    // Once per minor frame: advance ISO-TP, answer completed packets.
    void service();

    std::uint32_t echoed() const { return echoed_; }
    std::uint32_t echoRefused() const { return echoRefused_; }
    const hal::IsoTpChannel& channel() const { return channel_; }

private:
    static hal::IsoTpConfig config();

    hal::IsoTpChannel channel_;
    std::uint8_t packet_[hal::kIsoTpMaxMessage] = {};
    bool pending_ = false;       // a received packet waits for the transmitter
    std::size_t pendingLength_ = 0;
    std::uint32_t echoed_ = 0;
    std::uint32_t echoRefused_ = 0;
};

}  // namespace rse::app

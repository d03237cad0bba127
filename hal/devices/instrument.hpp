// Science instrument client: the grinder/sampler (status 0x6A5, commands 0x6B5)
// or the camera (0x6A6, 0x6B6), one class for both (the protocol is one:
// hal/devices/instrument_protocol.hpp, docs/icd.md §1.7).
//
// Reports (status and refusal) come in through the master as a frame sink;
// each is checked before it counts (DeviceFrameSink: wrong length or RTR ->
// event 452, a field out of range or the protocol's invariants broken -> 453;
// the last good status is kept). Commands go out with command(), checked first:
// one the instrument could not take (an action not its own, target 0, command
// id 0, a max duration out of range) or that could not reach it (offline, the
// CAN controller refused it) is not sent, and says why (event 460, counted in
// commandsNotSent, lastRefusal / lastRefusedCommandId).
//
// Liveness is the instrument's reports, sent every 100 ms: none for
// kInstrumentStatusTimeout makes it offline (event 455), as does never hearing
// it within kInstrumentBootTimeout of the first step(); the next good report
// brings it back (454). Its heartbeat is not monitored (the node map table
// lists only the drives and sensors).
//
// What changes in a report is evented: a command seen for the first time
// (accepted, 456), done (457), failed or the instrument faulted (458),
// cancelled (461), a fault cleared (462); a refusal report 459. Transition
// events are limited to kInstrumentEventsPerSecond per instrument (a babbling
// instrument cannot flood the log: the rest are counted, event 463 once a
// second). Static memory only; nothing allocates.
#pragma once

#include <cstdint>

#include "hal/can/can_bus.hpp"
#include "hal/devices/device_frame_sink.hpp"
#include "hal/devices/instrument_protocol.hpp"

namespace rse::hal {

constexpr core::TimeNs kInstrumentStatusTimeout = 500 * core::kNsPerMs;  // 5 report periods
constexpr core::TimeNs kInstrumentBootTimeout = 3 * core::kNsPerSec;
constexpr std::uint32_t kInstrumentEventsPerSecond = 10;

struct InstrumentStatus {
    bool online = false;            // a good report within kInstrumentStatusTimeout
    bool everHeard = false;
    core::TimeNs lastHeard = 0;     // time of the last good report (status or refusal)
    // As the last good status report gave them (kept while offline).
    instrument::State state = instrument::State::kIdle;
    instrument::Action action = instrument::Action::kNone;
    std::uint8_t target = 0;
    std::uint16_t commandId = 0;    // the command running or the last one (0: none since the instrument booted)
    std::uint8_t progressPct = 0;
    instrument::Result result = instrument::Result::kNone;
    std::uint8_t faultCode = 0;     // the instrument's own fault, 0 healthy
    // The latest command not taken: refused by the instrument or not sent.
    instrument::Refusal lastRefusal = instrument::Refusal::kNone;
    std::uint16_t lastRefusedCommandId = 0;
    std::uint32_t commandsSent = 0;      // command frames the CAN controller took
    std::uint32_t commandsAccepted = 0;  // new command ids seen in status reports
    std::uint32_t commandsRefused = 0;   // refusal reports
    std::uint32_t commandsNotSent = 0;   // refused here: invalid, offline, CAN refused
    std::uint32_t offlineCount = 0;      // times declared offline (never heard included)
    std::uint32_t eventsDropped = 0;     // transition events over the per-second limit
    std::uint32_t changes = 0;           // bumped on every change of the fields above (lastHeard aside)
};

class Instrument final : public DeviceFrameSink {
public:
    Instrument(CanBus& can, core::EventLog& events, instrument::Kind kind);

    // Checks and sends one command (cancel: commandId names the command to
    // cancel; target and maxDurationS are not sent. extend: commandId is the
    // follow-on's new id, extendsCommandId the command it continues (not 0,
    // not commandId), target that command's, maxDurationS the extra work, in
    // (0, 6553.5] s). Refusal::kNone when sent.
    instrument::Refusal command(instrument::Action action, std::uint8_t target, std::uint16_t commandId,
                                double maxDurationS, std::uint16_t extendsCommandId = 0);
    // Once per cycle, after the frames of the cycle: liveness.
    void step(core::TimeNs now);

    instrument::Kind kind() const { return kind_; }
    const InstrumentStatus& status() const { return status_; }

private:
    bool decode(const CanFrame& frame, core::TimeNs now, const char** reason) override;
    void takeStatus(const instrument::Report& report);
    void takeRefusal(const instrument::Report& report);
    instrument::Refusal notSent(instrument::Refusal why, instrument::Action action, std::uint16_t commandId);
    // A transition event within the per-second limit (at the time of the report being decoded).
    bool mayReport();

    CanBus& can_;
    core::EventLog& log_;
    const instrument::Kind kind_;
    InstrumentStatus status_;
    core::TimeNs firstStep_ = -1;
    bool neverHeardReported_ = false;
    core::TimeNs now_ = 0;             // of the frame being decoded
    core::TimeNs eventWindow_ = -1;    // start of the current second of transition events
    std::uint32_t eventsInWindow_ = 0;
    std::uint32_t droppedReported_ = 0;
};

}  // namespace rse::hal

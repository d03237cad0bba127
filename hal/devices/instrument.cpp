#include "hal/devices/instrument.hpp"

#include "hal/devices/device_events.hpp"

namespace rse::hal {

using core::Severity;
using instrument::Action;
using instrument::Refusal;
using instrument::Report;
using instrument::Result;
using instrument::State;

namespace {

bool sameStatus(const InstrumentStatus& a, const InstrumentStatus& b) {
    return a.state == b.state && a.action == b.action && a.target == b.target && a.commandId == b.commandId &&
           a.progressPct == b.progressPct && a.result == b.result && a.faultCode == b.faultCode;
}

}  // namespace

Instrument::Instrument(CanBus& can, core::EventLog& events, instrument::Kind kind)
    : DeviceFrameSink(events, instrument::toString(kind), events::kInstrumentBadFrame, events::kInstrumentBadValue),
      can_(can),
      log_(events),
      kind_(kind) {}

Refusal Instrument::notSent(Refusal why, Action action, std::uint16_t commandId) {
    ++status_.commandsNotSent;
    status_.lastRefusal = why;
    status_.lastRefusedCommandId = commandId;
    ++status_.changes;
    if (core::isReportableOccurrence(status_.commandsNotSent)) {
        log_.report(events::kInstrumentNotSent, Severity::kWarning, "%s: command %u (%s) not sent: %s (%u so far)",
                    deviceName(), static_cast<unsigned>(commandId), instrument::toString(action),
                    instrument::toString(why), static_cast<unsigned>(status_.commandsNotSent));
    }
    return why;
}

Refusal Instrument::command(Action action, std::uint8_t target, std::uint16_t commandId, double maxDurationS,
                            std::uint16_t extendsCommandId) {
    instrument::Command c;
    c.action = action;
    c.commandId = commandId;
    if (commandId == 0) {
        return notSent(Refusal::kMalformed, action, commandId);
    }
    if (action == Action::kExtend) {
        // A follow-on: a new id continuing another, with some extra work.
        if (extendsCommandId == 0 || extendsCommandId == commandId ||
            !instrument::durationField(maxDurationS, &c.maxDurationDs) || c.maxDurationDs == 0) {
            return notSent(Refusal::kMalformed, action, commandId);
        }
        if (target == 0) {
            return notSent(Refusal::kUnknownTarget, action, commandId);
        }
        c.target = target;
        c.extendsCommandId = extendsCommandId;
    } else if (action != Action::kCancel) {
        if (!instrument::doesWork(kind_, action)) {
            return notSent(Refusal::kUnsupportedAction, action, commandId);
        }
        if (target == 0) {
            return notSent(Refusal::kUnknownTarget, action, commandId);
        }
        if (!instrument::durationField(maxDurationS, &c.maxDurationDs)) {
            return notSent(Refusal::kMalformed, action, commandId);
        }
        c.target = target;
    }
    if (!status_.online) {
        return notSent(Refusal::kOffline, action, commandId);
    }
    CanFrame frame;
    instrument::encodeCommand(kind_, c, &frame);
    if (!core::isOk(can_.send(frame))) {
        return notSent(Refusal::kNotSent, action, commandId);
    }
    ++status_.commandsSent;
    ++status_.changes;
    return Refusal::kNone;
}

bool Instrument::decode(const CanFrame& frame, core::TimeNs now, const char** reason) {
    Report r;
    if (!instrument::decodeReport(kind_, frame.data, &r, reason)) {
        return false;
    }
    now_ = now;
    status_.lastHeard = now;
    status_.everHeard = true;
    if (!status_.online) {
        status_.online = true;
        ++status_.changes;
        log_.report(events::kInstrumentOnline, Severity::kInfo, "%s: online, %s", deviceName(),
                    instrument::toString(r.state));
    }
    if (r.kind == instrument::ReportKind::kRefusal) {
        takeRefusal(r);
    } else {
        takeStatus(r);
    }
    return true;
}

void Instrument::takeRefusal(const Report& r) {
    ++status_.commandsRefused;
    status_.lastRefusal = r.refusal;
    status_.lastRefusedCommandId = r.commandId;
    ++status_.changes;
    if (core::isReportableOccurrence(status_.commandsRefused)) {
        log_.report(events::kInstrumentRefused, Severity::kWarning, "%s: command %u (%s target %u) refused: %s (%u so far)",
                    deviceName(), static_cast<unsigned>(r.commandId), instrument::toString(r.action),
                    static_cast<unsigned>(r.target), instrument::toString(r.refusal),
                    static_cast<unsigned>(status_.commandsRefused));
    }
}

void Instrument::takeStatus(const Report& r) {
    const InstrumentStatus before = status_;
    InstrumentStatus& s = status_;
    s.state = r.state;
    s.action = r.action;
    s.target = r.target;
    s.commandId = r.commandId;
    s.progressPct = r.progressPct;
    s.result = r.result;
    s.faultCode = r.faultCode;
    if (sameStatus(before, s)) {
        return;
    }
    ++s.changes;
    const bool newCommand = s.commandId != 0 && s.commandId != before.commandId;
    const unsigned id = s.commandId;
    if (newCommand) {
        ++s.commandsAccepted;
        if (mayReport()) {
            log_.report(events::kInstrumentAccepted, Severity::kInfo, "%s: command %u accepted: %s target %u",
                        deviceName(), id, instrument::toString(s.action), static_cast<unsigned>(s.target));
        }
    }
    const bool entered = newCommand || s.state != before.state;
    if (s.state == State::kDone && entered && mayReport()) {
        log_.report(events::kInstrumentDone, Severity::kInfo, "%s: command %u done: %s target %u", deviceName(), id,
                    instrument::toString(s.action), static_cast<unsigned>(s.target));
    }
    if (s.state == State::kFailed && (entered || s.result != before.result || s.faultCode != before.faultCode) &&
        mayReport()) {
        log_.report(events::kInstrumentFailed, Severity::kWarning, "%s: failed: command %u (%s), fault code %u",
                    deviceName(), id, instrument::toString(s.result), static_cast<unsigned>(s.faultCode));
    }
    if (s.result == Result::kCancelled && (newCommand || before.result != Result::kCancelled) && mayReport()) {
        log_.report(events::kInstrumentCancelled, Severity::kInfo, "%s: command %u cancelled at %u %%", deviceName(), id,
                    static_cast<unsigned>(s.progressPct));
    }
    if (before.faultCode != 0 && s.faultCode == 0 && mayReport()) {
        log_.report(events::kInstrumentFaultCleared, Severity::kInfo, "%s: fault %u cleared, %s", deviceName(),
                    static_cast<unsigned>(before.faultCode), instrument::toString(s.state));
    }
}

bool Instrument::mayReport() {
    if (eventWindow_ < 0 || now_ - eventWindow_ >= core::kNsPerSec) {
        eventWindow_ = now_;
        eventsInWindow_ = 0;
    }
    if (eventsInWindow_ < kInstrumentEventsPerSecond) {
        ++eventsInWindow_;
        return true;
    }
    ++status_.eventsDropped;
    return false;
}

void Instrument::step(core::TimeNs now) {
    if (firstStep_ < 0) {
        firstStep_ = now;
    }
    if (status_.online && now - status_.lastHeard > kInstrumentStatusTimeout) {
        status_.online = false;
        ++status_.offlineCount;
        ++status_.changes;
        log_.report(events::kInstrumentOffline, Severity::kWarning, "%s: offline, no report for %lld ms (%u so far)",
                    deviceName(), static_cast<long long>((now - status_.lastHeard) / core::kNsPerMs),
                    static_cast<unsigned>(status_.offlineCount));
    } else if (!status_.everHeard && !neverHeardReported_ && now - firstStep_ > kInstrumentBootTimeout) {
        neverHeardReported_ = true;
        ++status_.offlineCount;
        ++status_.changes;
        log_.report(events::kInstrumentOffline, Severity::kWarning, "%s: offline, never heard in %lld ms since start",
                    deviceName(), static_cast<long long>((now - firstStep_) / core::kNsPerMs));
    }
    if (status_.eventsDropped != droppedReported_ && now - eventWindow_ >= core::kNsPerSec) {
        log_.report(events::kInstrumentEventsDropped, Severity::kWarning,
                    "%s: %u state-change events over %u a second not reported (%u so far)", deviceName(),
                    static_cast<unsigned>(status_.eventsDropped - droppedReported_),
                    static_cast<unsigned>(kInstrumentEventsPerSecond), static_cast<unsigned>(status_.eventsDropped));
        droppedReported_ = status_.eventsDropped;
    }
}

}  // namespace rse::hal

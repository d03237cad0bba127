#include "fsw/core/event_log.hpp"

#include <cstdarg>
#include <cstdio>

namespace rse::core {

const char* toString(Severity severity) {
    switch (severity) {
        case Severity::kDebug: return "DEBUG";
        case Severity::kInfo: return "INFO";
        case Severity::kWarning: return "WARN";
        case Severity::kError: return "ERROR";
        case Severity::kCritical: return "CRIT";
    }
    return "?";
}

void EventLog::report(EventId id, Severity severity, const char* format, ...) {
    va_list args;
    va_start(args, format);
    record(id, severity, nullptr, format, args);
    va_end(args);
}

void EventLog::report(EventId id, Severity severity, const EventData& data, const char* format, ...) {
    va_list args;
    va_start(args, format);
    record(id, severity, &data, format, args);
    va_end(args);
}

void EventLog::record(EventId id, Severity severity, const EventData* data, const char* format, va_list args) {
    Event event;
    event.time = clock_.now();
    event.sequence = written_;
    event.id = id;
    event.severity = severity;
    // Truncates to the fixed text size; never allocates for the formats we use
    // (integers, short strings, fixed-precision floats).
    std::vsnprintf(event.text, sizeof event.text, format, args);
    if (data != nullptr) {
        const std::size_t count = data->count < kEventDataValues ? data->count : kEventDataValues;
        event.data.count = static_cast<std::uint8_t>(count);
        for (std::size_t i = 0; i < count; ++i) {
            event.data.values[i] = data->values[i];
        }
    }

    ++total_;
    const auto index = static_cast<std::size_t>(severity);
    if (index < kSeverityCount) {
        ++bySeverity_[index];
    }
    history_[written_ % kEventRingDepth] = event;
    ++written_;
    if (written_ - primaryNext_ > kDepth) {
        ++primaryNext_;
        ++lost_;
    }
}

Status EventLog::pop(Event* out) {
    if (primaryNext_ == written_) {
        return Status::kEmpty;
    }
    if (out != nullptr) {
        *out = history_[primaryNext_ % kEventRingDepth];
    }
    ++primaryNext_;
    return Status::kOk;
}

Status EventLog::read(Cursor* cursor, Event* out) const {
    if (cursor == nullptr) {
        return Status::kInvalidArgument;
    }
    if (cursor->next == written_) {
        return Status::kEmpty;
    }
    if (written_ - cursor->next > kDepth) {
        cursor->lost += written_ - kDepth - cursor->next;
        cursor->next = written_ - kDepth;
    }
    if (out != nullptr) {
        *out = history_[cursor->next % kEventRingDepth];
    }
    ++cursor->next;
    return Status::kOk;
}

std::uint32_t EventLog::count(Severity severity) const {
    const auto index = static_cast<std::size_t>(severity);
    return index < kSeverityCount ? bySeverity_[index] : 0;
}

void EventLog::resetCounters() {
    total_ = 0;
    lost_ = 0;
    for (auto& c : bySeverity_) {
        c = 0;
    }
}

}  // namespace rse::core

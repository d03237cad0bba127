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
    Event event;
    event.time = clock_.now();
    event.sequence = total_;
    event.id = id;
    event.severity = severity;
    va_list args;
    va_start(args, format);
    // Truncates to the fixed text size; never allocates for the formats we use
    // (integers, short strings, fixed-precision floats).
    std::vsnprintf(event.text, sizeof event.text, format, args);
    va_end(args);

    ++total_;
    const auto index = static_cast<std::size_t>(severity);
    if (index < kSeverityCount) {
        ++bySeverity_[index];
    }
    if (ring_.pushOverwrite(event)) {
        ++lost_;
    }
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

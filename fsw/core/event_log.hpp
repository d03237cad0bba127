// Events: enumerated ids, a severity and a short formatted text, kept in a fixed
// ring until a reader (console now, telemetry output later) drains them.
//
// Nothing is lost silently: an unread event overwritten by a newer one is counted
// in lost(), and every report is counted per severity whether or not it is read.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/ring_buffer.hpp"

namespace rse::core {

// Ids are allotted in ranges per module; see docs/architecture.md ("Events").
using EventId = std::uint16_t;

enum class Severity : std::uint8_t { kDebug = 0, kInfo, kWarning, kError, kCritical };
constexpr std::size_t kSeverityCount = 5;
const char* toString(Severity severity);

constexpr std::size_t kEventTextSize = 96;  // including the terminating NUL
constexpr std::size_t kEventRingDepth = 128;

struct Event {
    TimeNs time = 0;
    std::uint32_t sequence = 0;  // counts every report, so a reader sees gaps
    EventId id = 0;
    Severity severity = Severity::kDebug;
    char text[kEventTextSize] = {};
};

// A repeated condition (e.g. a queue overflowing every frame) is evented on its
// 1st, 2nd, 4th, 8th... occurrence; its counter still counts every one.
inline bool isReportableOccurrence(std::uint32_t count) {
    return count != 0 && (count & (count - 1)) == 0;
}

class EventLog {
public:
    explicit EventLog(const Clock& clock) : clock_(clock) {}

    void report(EventId id, Severity severity, const char* format, ...)
        __attribute__((format(printf, 4, 5)));

    // Oldest unread event; Status::kEmpty when there is none.
    Status pop(Event* out) { return ring_.pop(out); }

    std::uint32_t total() const { return total_; }
    std::uint32_t count(Severity severity) const;
    std::uint32_t lost() const { return lost_; }
    std::size_t unread() const { return ring_.size(); }
    void resetCounters();

private:
    const Clock& clock_;
    RingBuffer<Event, kEventRingDepth> ring_;
    std::uint32_t total_ = 0;
    std::uint32_t lost_ = 0;
    std::uint32_t bySeverity_[kSeverityCount] = {};
};

}  // namespace rse::core

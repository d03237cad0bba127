// Events: enumerated ids, a severity and a short formatted text, kept in a fixed
// ring of the newest kEventRingDepth reports.
//
// The primary reader (telemetry output) takes events with pop(); an unread event
// overwritten by a newer one is counted in lost() at once, so housekeeping shows
// what never reached the ground. Other readers (the console) keep their own
// EventCursor and read() at their own pace; what they miss is counted in their
// cursor. Every report is counted per severity whether or not anyone reads it.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/status.hpp"

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
    std::uint32_t sequence = 0;  // counts every report since start (never reset), so a reader sees gaps
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

    // The primary reader's oldest unread event; Status::kEmpty when there is none.
    Status pop(Event* out);

    // A secondary reader: starts with the oldest event still held.
    struct Cursor {
        std::uint32_t next = 0;  // sequence of the next event to read
        std::uint32_t lost = 0;  // events overwritten before this reader got them
    };
    Status read(Cursor* cursor, Event* out) const;

    std::uint32_t total() const { return total_; }
    std::uint32_t count(Severity severity) const;
    std::uint32_t lost() const { return lost_; }
    std::size_t unread() const { return written_ - primaryNext_; }
    void resetCounters();

private:
    static constexpr std::uint32_t kDepth = static_cast<std::uint32_t>(kEventRingDepth);
    static_assert((kEventRingDepth & (kEventRingDepth - 1)) == 0,
                  "sequence % depth must stay continuous when the 32-bit sequence wraps");

    const Clock& clock_;
    Event history_[kEventRingDepth];
    std::uint32_t written_ = 0;      // reports ever made: the next sequence number
    std::uint32_t primaryNext_ = 0;  // pop()'s position
    std::uint32_t total_ = 0;
    std::uint32_t lost_ = 0;
    std::uint32_t bySeverity_[kSeverityCount] = {};
};

}  // namespace rse::core

// Events: enumerated ids, a severity and a short formatted text, kept in a fixed
// ring of the newest kEventRingDepth reports. An event may also carry typed
// numbers (EventData, F'-style event arguments): what a reader decides on, so
// the text stays words for people and may be reworded freely. The dictionary
// names each event's numbers (fsw/cmdtlm/dictionary.def, RSE_EVENT_DATA; call
// sites fill them by name through fsw/cmdtlm/event_data.hpp) and the ground
// gets them in an EVENT_DATA packet right after the event's EVENT packet.
//
// The primary reader (telemetry output) takes events with pop(); an unread event
// overwritten by a newer one is counted in lost() at once, so housekeeping shows
// what never reached the ground. Other readers (the console) keep their own
// EventCursor and read() at their own pace; what they miss is counted in their
// cursor. Every report is counted per severity whether or not anyone reads it.
#pragma once

#include <cstdarg>
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
// The most numbers one event carries (the EVENT_DATA packet's value[]; every
// RSE_EVENT_DATA of the dictionary is held to it at compile time). Each ring
// slot keeps them: 72 bytes a slot, 9216 bytes for the ring (docs/architecture.md,
// "Events"); one more value is 8 bytes a slot and 8 in the packet.
constexpr std::size_t kEventDataValues = 8;

// An event's numbers, in the order its RSE_EVENT_DATA lists them; count 0: the
// event carries none. Doubles hold every integer up to 2^53 exactly (ids,
// counts, codes, masks) and the figures at full precision.
struct EventData {
    std::uint8_t count = 0;
    double values[kEventDataValues] = {};
};

struct Event {
    TimeNs time = 0;
    std::uint32_t sequence = 0;  // counts every report since start (never reset), so a reader sees gaps
    EventId id = 0;
    Severity severity = Severity::kDebug;
    char text[kEventTextSize] = {};
    EventData data;              // the event's numbers (data.count 0: none)
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
    // The same with the event's numbers (at most kEventDataValues are kept).
    void report(EventId id, Severity severity, const EventData& data, const char* format, ...)
        __attribute__((format(printf, 5, 6)));

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

    void record(EventId id, Severity severity, const EventData* data, const char* format, va_list args)
        __attribute__((format(printf, 5, 0)));

    const Clock& clock_;
    Event history_[kEventRingDepth];
    std::uint32_t written_ = 0;      // reports ever made: the next sequence number
    std::uint32_t primaryNext_ = 0;  // pop()'s position
    std::uint32_t total_ = 0;
    std::uint32_t lost_ = 0;
    std::uint32_t bySeverity_[kSeverityCount] = {};
};

}  // namespace rse::core

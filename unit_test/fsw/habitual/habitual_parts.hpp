// Test-only helpers for the habitual task's parts (escape search, candidate
// evaluator, drive supervisor, ...): the default tables decoded from the
// built-in images (tables/*.toml), hazard sightings, and a reader of the
// events a part raised.
#pragma once

#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/habitual/map_builder.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"

namespace rse::test {

// The built-in image of Table decoded (a zeroed table if none decodes: the
// tests then fail on its figures).
template <typename Table>
Table defaultTable() {
    Table t{};
    for (std::size_t i = 0; i < tables::kDefaultTableImageCount; ++i) {
        const tables::TableImageRef& ref = tables::kDefaultTableImages[i];
        if (tables::decodeTable(ref.data, ref.length, &t).ok()) {
            return t;
        }
    }
    return Table{};
}

// A sighting whose disc centre lies (range + halfWidth) ahead of the rover along bearingRad.
inline msg::HazardSightingTlm sighting(std::uint8_t id, double rangeM, double bearingRad, double halfWidthM) {
    msg::HazardSightingTlm s{};
    s.obstacleId = id;
    s.rangeM = rangeM;
    s.bearingRad = bearingRad;
    s.halfWidthM = halfWidthM;
    return s;
}

// The events raised since the last take(): how many of an id, and the latest
// text, severity and numbers of each.
class EventReader {
public:
    explicit EventReader(core::EventLog& log) : log_(log) {}
    void take() {
        std::memset(count_, 0, sizeof count_);
        core::Event e;
        while (core::isOk(log_.pop(&e))) {
            const std::size_t slot = e.id % kSlots;
            ++count_[slot];
            std::memcpy(text_[slot], e.text, sizeof e.text);
            severity_[slot] = e.severity;
            data_[slot] = e.data;
        }
    }
    // The latest event's numbers by name (false: none of that layout).
    template <typename Layout>
    bool data(core::EventId id, Layout* out) const {
        return out->unpack(id, data_[id % kSlots]);
    }
    unsigned count(core::EventId id) const { return count_[id % kSlots]; }
    const char* text(core::EventId id) const { return text_[id % kSlots]; }
    core::Severity severity(core::EventId id) const { return severity_[id % kSlots]; }
    bool says(core::EventId id, const char* part) const {
        return count(id) > 0 && std::strstr(text(id), part) != nullptr;
    }

private:
    static constexpr std::size_t kSlots = 1000;
    core::EventLog& log_;
    unsigned count_[kSlots] = {};
    char text_[kSlots][core::kEventTextSize] = {};
    core::Severity severity_[kSlots] = {};
    core::EventData data_[kSlots] = {};
};

}  // namespace rse::test

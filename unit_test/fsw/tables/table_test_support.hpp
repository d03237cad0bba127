// Helpers shared by the table suites: the default images as vectors, and an
// event reader that keeps the text of the events it drains.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fsw/core/event_log.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"

namespace rse::test {

// The default image of one table (empty if kDefaultTableImages has none).
inline std::vector<std::uint8_t> defaultImage(tables::TableId id) {
    for (std::size_t i = 0; i < tables::kDefaultTableImageCount; ++i) {
        const tables::TableImageRef& ref = tables::kDefaultTableImages[i];
        tables::TableHeader header;
        if (tables::readTableHeader(ref.data, ref.length, &header) &&
            header.tableId == static_cast<std::uint16_t>(id)) {
            return std::vector<std::uint8_t>(ref.data, ref.data + ref.length);
        }
    }
    return {};
}

struct DrainedEvents {
    unsigned count = 0;  // events with the id asked for
    std::string text;    // the text of the last of them
    unsigned total = 0;  // events drained, any id
};

// Drains the log; counts the events with `id` and keeps the last one's text.
inline DrainedEvents drainEvents(core::EventLog& log, core::EventId id) {
    DrainedEvents d;
    core::Event e;
    while (core::isOk(log.pop(&e))) {
        ++d.total;
        if (e.id == id) {
            ++d.count;
            d.text = e.text;
        }
    }
    return d;
}

}  // namespace rse::test

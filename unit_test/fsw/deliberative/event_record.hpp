// Test-only: what a log holds, by event id: how many, the latest text and the
// latest numbers (pump() drains the log into the record). For the deliberative
// parts' tests.
#pragma once

#include <cstring>

#include "fsw/core/event_log.hpp"

namespace rse::test {

class EventRecord {
public:
    explicit EventRecord(core::EventLog& log) : log_(log) {}

    unsigned count(core::EventId id) {
        pump();
        return seen_[id % 1000];
    }
    const char* text(core::EventId id) {
        pump();
        return texts_[id % 1000];
    }
    // Every event so far, of any id.
    unsigned total() {
        pump();
        return total_;
    }
    void clear() {
        pump();
        std::memset(seen_, 0, sizeof seen_);
        total_ = 0;
    }
    bool textHas(core::EventId id, const char* what) { return std::strstr(text(id), what) != nullptr; }
    // The latest event's numbers, by name: false when it carried none of that layout.
    template <typename Layout>
    bool data(core::EventId id, Layout* out) {
        pump();
        return out->unpack(id, data_[id % 1000]);
    }

private:
    void pump() {
        core::Event e;
        while (core::isOk(log_.pop(&e))) {
            seen_[e.id % 1000] += 1;
            ++total_;
            std::memcpy(texts_[e.id % 1000], e.text, sizeof e.text);
            data_[e.id % 1000] = e.data;
        }
    }

    core::EventLog& log_;
    unsigned seen_[1000] = {};
    unsigned total_ = 0;
    char texts_[1000][core::kEventTextSize] = {};
    core::EventData data_[1000] = {};
};

}  // namespace rse::test

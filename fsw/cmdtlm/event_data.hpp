// The event data of the dictionary (fsw/cmdtlm/dictionary.def, RSE_EVENT_DATA)
// expanded for C++: one struct per layout, its values by name, so a flight
// call site fills the numbers an event carries by name and never by a bare
// index, and a ground reader gets them back the same way:
//
//   cmdtlm::event_data::LEG_SENT data;
//   data.leg_id = leg.legId;
//   data.x = leg.goalXM;
//   ...
//   events_.report(events::kLegSent, core::Severity::kInfo, data.pack(), "deliberative: leg %u ...", ...);
//
//   cmdtlm::event_data::LEG_SENT sent;
//   if (sent.unpack(event.id, event.data)) { ... sent.leg_id ... }
//
// pack() lists every value in the .def's order (core::EventData, count = the
// layout's value count); unpack() refuses an event outside the layout's ids or
// with fewer values (a newer flight may append values: the extra ones are
// ignored). The descriptors (names, units, descriptions per event id) are for
// the ground's displays and the exported dictionary.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"

namespace rse::cmdtlm {

namespace event_data {

// How many values each layout has: NAME_kValueCount, held to what an event carries.
#define RSE_CMD(NAME, apid, fc, modes, text)
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
#define RSE_TLM(NAME, apid, text)
#define RSE_FIELD(type, name, count, units, text)
#define RSE_TLM_END(NAME)
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why)
#define RSE_EVENT_DATA(first_id, last_id, NAME, text) constexpr std::size_t NAME##_kValueCount = 0
#define RSE_EVENT_VALUE(name, units, text) +1
#define RSE_EVENT_DATA_END(NAME)                                                  \
    ;                                                                             \
    static_assert(NAME##_kValueCount >= 1 && NAME##_kValueCount <= core::kEventDataValues, \
                  "RSE_EVENT_DATA " #NAME ": 1 to core::kEventDataValues values");
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END

// The structs: every value a double member named as in the .def.
#define RSE_EVENT_DATA(first_id, last_id, NAME, text)                                          \
    struct NAME {                                                                              \
        static constexpr core::EventId kFirstId = first_id;                                    \
        static constexpr core::EventId kLastId = last_id;                                      \
        static constexpr std::size_t kValueCount = NAME##_kValueCount;                         \
        static constexpr bool covers(core::EventId id) { return id >= kFirstId && id <= kLastId; } \
        core::EventData pack() const;                                                          \
        bool unpack(core::EventId id, const core::EventData& data);
#define RSE_EVENT_VALUE(name, units, text) double name = 0.0;
#define RSE_EVENT_DATA_END(NAME) };
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END

#define RSE_EVENT_DATA(first_id, last_id, NAME, text) \
    inline core::EventData NAME::pack() const {       \
        core::EventData d;
#define RSE_EVENT_VALUE(name, units, text) d.values[d.count++] = name;
#define RSE_EVENT_DATA_END(NAME) \
    return d;                    \
    }
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END

#define RSE_EVENT_DATA(first_id, last_id, NAME, text)                         \
    inline bool NAME::unpack(core::EventId id, const core::EventData& data) { \
        if (!covers(id) || data.count < kValueCount) {                        \
            return false;                                                     \
        }                                                                     \
        std::size_t i = 0;
#define RSE_EVENT_VALUE(name, units, text) name = data.values[i++];
#define RSE_EVENT_DATA_END(NAME) \
    (void)i;                     \
    return true;                 \
    }
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_CMD
#undef RSE_ARG
#undef RSE_BLOB
#undef RSE_CMD_END
#undef RSE_TLM
#undef RSE_FIELD
#undef RSE_TLM_END
#undef RSE_LIMIT
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END

}  // namespace event_data

// ---- Descriptors (the names per event id) --------------------------------------
struct EventValueDesc {
    const char* name;
    const char* units;
    const char* description;
};

struct EventDataDesc {
    const char* name;  // the layout's NAME
    core::EventId firstId;
    core::EventId lastId;
    const char* description;
    const EventValueDesc* values;
    std::uint8_t valueCount;
};

// Every RSE_EVENT_DATA, in .def order.
const EventDataDesc* eventDataDescs(std::size_t* count);
// The layout of an event id's data, or nullptr when that event carries none.
const EventDataDesc* findEventData(core::EventId id);

}  // namespace rse::cmdtlm

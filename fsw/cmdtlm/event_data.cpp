#include "fsw/cmdtlm/event_data.hpp"

namespace rse::cmdtlm {

namespace {

#define RSE_CMD(NAME, apid, fc, modes, text)
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
#define RSE_TLM(NAME, apid, text)
#define RSE_FIELD(type, name, count, units, text)
#define RSE_TLM_END(NAME)
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why)
#define RSE_EVENT_DATA(first_id, last_id, NAME, text) constexpr EventValueDesc k##NAME##_ValueDescs[] = {
#define RSE_EVENT_VALUE(name, units, text) {#name, units, text},
#define RSE_EVENT_DATA_END(NAME) };
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END

#define RSE_EVENT_DATA(first_id, last_id, NAME, text)                                  \
    {#NAME, first_id, last_id, text, k##NAME##_ValueDescs,                             \
     static_cast<std::uint8_t>(sizeof k##NAME##_ValueDescs / sizeof k##NAME##_ValueDescs[0])},
#define RSE_EVENT_VALUE(name, units, text)
#define RSE_EVENT_DATA_END(NAME)
constexpr EventDataDesc kEventData[] = {
#include "fsw/cmdtlm/dictionary.def"
};
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

constexpr std::size_t kEventDataCount = sizeof kEventData / sizeof kEventData[0];

// Two layouts for one id would make an event's numbers ambiguous.
constexpr bool idsOverlap() {
    for (std::size_t i = 0; i < kEventDataCount; ++i) {
        if (kEventData[i].lastId < kEventData[i].firstId) {
            return true;
        }
        for (std::size_t j = i + 1; j < kEventDataCount; ++j) {
            if (kEventData[i].firstId <= kEventData[j].lastId && kEventData[j].firstId <= kEventData[i].lastId) {
                return true;
            }
        }
    }
    return false;
}
static_assert(!idsOverlap(), "every event id has at most one RSE_EVENT_DATA (and first_id <= last_id)");

}  // namespace

const EventDataDesc* eventDataDescs(std::size_t* count) {
    *count = kEventDataCount;
    return kEventData;
}

const EventDataDesc* findEventData(core::EventId id) {
    for (const EventDataDesc& d : kEventData) {
        if (id >= d.firstId && id <= d.lastId) {
            return &d;
        }
    }
    return nullptr;
}

}  // namespace rse::cmdtlm

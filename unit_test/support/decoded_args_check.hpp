// Test helper shared by the corpus replay and the command fuzzer: decodes a
// verdict's arguments with the command's generated decoder and checks the typed
// values against the dictionary's ranges, written out from the .def here (not
// read back through the descriptors the validator used).
#pragma once

#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"

namespace rse::test {

inline bool inClosed(double value, double lo, double hi) { return value >= lo && value <= hi; }

// True when every argument is in range and decoding consumed exactly the argument bytes.
inline bool decodesInRange(const cmdtlm::CommandVerdict& v) {
    using namespace cmdtlm;
    core::BeReader r(v.args, v.argLength);
    switch (v.command->code) {
#define RSE_CMD(NAME, apid, fc, modes, text) \
    case CommandCode::NAME: {                \
        NAME##_Args a{};                     \
        decodeArgs(r, &a);                   \
        bool inRange = true;
#define RSE_ARG(type, name, units, lo, hi, text) \
    inRange = inRange && inClosed(static_cast<double>(a.name), static_cast<double>(lo), static_cast<double>(hi));
#define RSE_BLOB(name, max, text) inRange = inRange && a.name##_length > 0 && a.name##_length <= (max);
#define RSE_CMD_END(NAME)                             \
    return inRange && r.ok() && r.remaining() == 0; \
    }
#define RSE_TLM(NAME, apid, text)
#define RSE_FIELD(type, name, count, units, text)
#define RSE_TLM_END(NAME)
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why)
#define RSE_EVENT_DATA(first_id, last_id, NAME, text)
#define RSE_EVENT_VALUE(name, units, text)
#define RSE_EVENT_DATA_END(NAME)
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
        case CommandCode::kCount:
            break;
    }
    return false;
}

}  // namespace rse::test

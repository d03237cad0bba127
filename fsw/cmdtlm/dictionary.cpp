#include "fsw/cmdtlm/dictionary.hpp"

#include <cmath>
#include <cstring>

#include "fsw/msg/mode_msgs.hpp"

namespace rse::cmdtlm {

// The layers read ModeMsg::mode through msg::mode (they include no cmdtlm header).
static_assert(static_cast<std::uint8_t>(Mode::kSafe) == msg::mode::kSafe, "msg::mode mirrors cmdtlm::Mode");
static_assert(static_cast<std::uint8_t>(Mode::kStandby) == msg::mode::kStandby, "msg::mode mirrors cmdtlm::Mode");
static_assert(static_cast<std::uint8_t>(Mode::kAutonomous) == msg::mode::kAutonomous, "msg::mode mirrors cmdtlm::Mode");
static_assert(static_cast<std::uint8_t>(Mode::kManual) == msg::mode::kManual, "msg::mode mirrors cmdtlm::Mode");
static_assert(kModeCount == msg::mode::kCount, "msg::mode mirrors cmdtlm::Mode");

const char* toString(FieldType type) {
    switch (type) {
        case FieldType::u8: return "u8";
        case FieldType::u16: return "u16";
        case FieldType::u32: return "u32";
        case FieldType::u64: return "u64";
        case FieldType::i16: return "i16";
        case FieldType::i32: return "i32";
        case FieldType::i64: return "i64";
        case FieldType::f32: return "f32";
        case FieldType::f64: return "f64";
        case FieldType::chr: return "chr";
        case FieldType::blob: return "blob";
    }
    return "?";
}

const char* toString(Mode mode) {
    switch (mode) {
        case Mode::kSafe: return "SAFE";
        case Mode::kStandby: return "STANDBY";
        case Mode::kAutonomous: return "AUTONOMOUS";
        case Mode::kManual: return "MANUAL";
    }
    return "?";
}

namespace {
using namespace mode_mask;

// Per-command argument arrays, each closed by a sentinel row so that commands
// without arguments still have an array (its count excludes the sentinel).
#define RSE_CMD(NAME, apid, fc, modes, text) constexpr ArgDesc k##NAME##_ArgDescs[] = {
#define RSE_ARG(type, name, units, lo, hi, text) {#name, FieldType::type, units, lo, hi, 0, text},
#define RSE_BLOB(name, max, text) {#name, FieldType::blob, "B", 0, max, max, text},
#define RSE_CMD_END(NAME) {nullptr, FieldType::u8, nullptr, 0, 0, 0, nullptr}};
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

constexpr std::uint16_t fixedBytes(const ArgDesc* args) {
    std::uint16_t total = 0;
    for (std::size_t i = 0; args[i].name != nullptr; ++i) {
        if (args[i].type != FieldType::blob) {
            total = static_cast<std::uint16_t>(total + wireSize(args[i].type));
        }
    }
    return total;
}
constexpr std::uint16_t blobBytes(const ArgDesc* args) {
    for (std::size_t i = 0; args[i].name != nullptr; ++i) {
        if (args[i].type == FieldType::blob) {
            return args[i].maxBytes;
        }
    }
    return 0;
}
template <std::size_t N>
constexpr std::uint8_t argCount(const ArgDesc (&)[N]) {
    return static_cast<std::uint8_t>(N - 1);
}

#define RSE_CMD(NAME, apid, fc, modes, text)                                                      \
    {CommandCode::NAME, #NAME, apid, fc, modes, text, k##NAME##_ArgDescs, argCount(k##NAME##_ArgDescs), \
     fixedBytes(k##NAME##_ArgDescs), blobBytes(k##NAME##_ArgDescs)},
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
constexpr CommandDesc kCommands[] = {
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
static_assert(sizeof kCommands / sizeof kCommands[0] == kCommandCount, "one descriptor per command code");

#define RSE_CMD(NAME, apid, fc, modes, text)
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
#define RSE_TLM(NAME, apid, text) constexpr FieldDesc k##NAME##_FieldDescs[] = {
#define RSE_FIELD(type, name, count, units, text) {#name, FieldType::type, count, units, text},
#define RSE_TLM_END(NAME) };
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why)
#define RSE_EVENT_DATA(first_id, last_id, NAME, text)
#define RSE_EVENT_VALUE(name, units, text)
#define RSE_EVENT_DATA_END(NAME)
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_TLM
#undef RSE_FIELD
#undef RSE_TLM_END
#undef RSE_LIMIT
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END

#define RSE_TLM(NAME, apid, text)                                                              \
    {#NAME, apid, text, k##NAME##_FieldDescs,                                                  \
     static_cast<std::uint8_t>(sizeof k##NAME##_FieldDescs / sizeof k##NAME##_FieldDescs[0]), \
     static_cast<std::uint16_t>(k##NAME##_TlmSize)},
#define RSE_FIELD(type, name, count, units, text)
#define RSE_TLM_END(NAME)
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why)
#define RSE_EVENT_DATA(first_id, last_id, NAME, text)
#define RSE_EVENT_VALUE(name, units, text)
#define RSE_EVENT_DATA_END(NAME)
constexpr TelemetryDesc kTelemetry[] = {
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

constexpr std::size_t kTelemetryCount = sizeof kTelemetry / sizeof kTelemetry[0];

}  // namespace

const CommandDesc* commandDescs(std::size_t* count) {
    *count = kCommandCount;
    return kCommands;
}

const CommandDesc* findCommand(std::uint16_t apid, std::uint8_t functionCode) {
    for (const CommandDesc& c : kCommands) {
        if (c.apid == apid && c.functionCode == functionCode) {
            return &c;
        }
    }
    return nullptr;
}

const CommandDesc* findCommand(const char* name) {
    for (const CommandDesc& c : kCommands) {
        if (name != nullptr && std::strcmp(c.name, name) == 0) {
            return &c;
        }
    }
    return nullptr;
}

const CommandDesc& describe(CommandCode code) { return kCommands[static_cast<std::size_t>(code)]; }

bool isCommandApid(std::uint16_t apid) {
    for (const CommandDesc& c : kCommands) {
        if (c.apid == apid) {
            return true;
        }
    }
    return false;
}

const TelemetryDesc* telemetryDescs(std::size_t* count) {
    *count = kTelemetryCount;
    return kTelemetry;
}

const TelemetryDesc* findTelemetry(std::uint16_t apid) {
    for (const TelemetryDesc& t : kTelemetry) {
        if (t.apid == apid) {
            return &t;
        }
    }
    return nullptr;
}

const TelemetryDesc* findTelemetry(const char* name) {
    for (const TelemetryDesc& t : kTelemetry) {
        if (name != nullptr && std::strcmp(t.name, name) == 0) {
            return &t;
        }
    }
    return nullptr;
}

double readAsDouble(core::BeReader& r, FieldType type) {
    switch (type) {
        case FieldType::u8: case FieldType::chr: case FieldType::blob: return r.u8();
        case FieldType::u16: return r.u16();
        case FieldType::u32: return r.u32();
        case FieldType::u64: return static_cast<double>(r.u64());
        case FieldType::i16: return r.i16();
        case FieldType::i32: return r.i32();
        case FieldType::i64: return static_cast<double>(r.i64());
        case FieldType::f32: return static_cast<double>(r.f32());
        case FieldType::f64: return r.f64();
    }
    return std::nan("");
}

}  // namespace rse::cmdtlm

// The command and telemetry dictionary expanded for C++: one argument struct per
// command, one struct per telemetry packet, their big-endian codecs, and the
// descriptor tables that the command validator, the ground tool and the exported
// documents read. The data itself is fsw/cmdtlm/dictionary.def (the one source).
// Its display limits (RSE_LIMIT) are the ground's alone
// (ground/telemetry_limits.hpp): every expansion here defines RSE_LIMIT empty.
//
// Generated names keep the dictionary's spelling so a reader can grep one name
// across flight, ground and docs: command GOTO has arguments struct GOTO_Args
// and code CommandCode::GOTO; telemetry HK is struct HK_Tlm.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/byte_codec.hpp"

namespace rse::cmdtlm {

// Wire types. Lower-case so the dictionary's type tokens name them directly.
enum class FieldType : std::uint8_t { u8, u16, u32, u64, i16, i32, i64, f32, f64, chr, blob };
const char* toString(FieldType type);
constexpr std::size_t wireSize(FieldType type) {
    switch (type) {
        case FieldType::u8: case FieldType::chr: case FieldType::blob: return 1;
        case FieldType::u16: case FieldType::i16: return 2;
        case FieldType::u32: case FieldType::i32: case FieldType::f32: return 4;
        case FieldType::u64: case FieldType::i64: case FieldType::f64: return 8;
    }
    return 0;
}

namespace wire {
using u8 = std::uint8_t;
using u16 = std::uint16_t;
using u32 = std::uint32_t;
using u64 = std::uint64_t;
using i16 = std::int16_t;
using i32 = std::int32_t;
using i64 = std::int64_t;
using f32 = float;
using f64 = double;
using chr = char;

// A field of count 1 is a scalar, otherwise an array.
template <typename T, std::size_t N>
struct Storage { using type = T[N]; };
template <typename T>
struct Storage<T, 1> { using type = T; };
}  // namespace wire

// Rover modes; numeric values are part of the command and telemetry format.
enum class Mode : std::uint8_t { kSafe = 0, kStandby = 1, kAutonomous = 2, kManual = 3 };
constexpr std::size_t kModeCount = 4;
const char* toString(Mode mode);

// Mode preconditions: bit (1 << Mode) set means the command is accepted then.
namespace mode_mask {
constexpr std::uint8_t kSafe = 1U << 0;
constexpr std::uint8_t kStandby = 1U << 1;
constexpr std::uint8_t kAutonomous = 1U << 2;
constexpr std::uint8_t kManual = 1U << 3;
constexpr std::uint8_t kAnyMode = kSafe | kStandby | kAutonomous | kManual;
}  // namespace mode_mask
constexpr bool modeAllows(std::uint8_t modes, Mode mode) {
    return (modes & (1U << static_cast<unsigned>(mode))) != 0;
}

// ---- Commands ------------------------------------------------------------------
enum class CommandCode : std::uint8_t {
#define RSE_CMD(NAME, apid, fc, modes, text) NAME,
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
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
    kCount
};
constexpr std::size_t kCommandCount = static_cast<std::size_t>(CommandCode::kCount);

// Argument structs and their decoders (flight) and encoders (ground, tests).
#define RSE_CMD(NAME, apid, fc, modes, text) struct NAME##_Args {
#define RSE_ARG(type, name, units, lo, hi, text) wire::type name;
#define RSE_BLOB(name, max, text) std::uint16_t name##_length; std::uint8_t name[max];
#define RSE_CMD_END(NAME) };
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

inline void readValue(core::BeReader& r, std::uint8_t* v) { *v = r.u8(); }
inline void readValue(core::BeReader& r, std::uint16_t* v) { *v = r.u16(); }
inline void readValue(core::BeReader& r, std::uint32_t* v) { *v = r.u32(); }
inline void readValue(core::BeReader& r, std::uint64_t* v) { *v = r.u64(); }
inline void readValue(core::BeReader& r, std::int16_t* v) { *v = r.i16(); }
inline void readValue(core::BeReader& r, std::int32_t* v) { *v = r.i32(); }
inline void readValue(core::BeReader& r, std::int64_t* v) { *v = r.i64(); }
inline void readValue(core::BeReader& r, float* v) { *v = r.f32(); }
inline void readValue(core::BeReader& r, double* v) { *v = r.f64(); }
inline void writeValue(core::BeWriter& w, std::uint8_t v) { w.u8(v); }
inline void writeValue(core::BeWriter& w, char v) { w.u8(static_cast<std::uint8_t>(v)); }
inline void writeValue(core::BeWriter& w, std::uint16_t v) { w.u16(v); }
inline void writeValue(core::BeWriter& w, std::uint32_t v) { w.u32(v); }
inline void writeValue(core::BeWriter& w, std::uint64_t v) { w.u64(v); }
inline void writeValue(core::BeWriter& w, std::int16_t v) { w.i16(v); }
inline void writeValue(core::BeWriter& w, std::int32_t v) { w.i32(v); }
inline void writeValue(core::BeWriter& w, std::int64_t v) { w.i64(v); }
inline void writeValue(core::BeWriter& w, float v) { w.f32(v); }
inline void writeValue(core::BeWriter& w, double v) { w.f64(v); }
template <typename T, std::size_t N>
void writeValue(core::BeWriter& w, const T (&v)[N]) {
    for (std::size_t i = 0; i < N; ++i) {
        writeValue(w, v[i]);
    }
}

// decodeArgs: the reader holds exactly the argument bytes, already checked by
// the validator against the descriptor (length and ranges).
#define RSE_CMD(NAME, apid, fc, modes, text) \
    inline void decodeArgs(core::BeReader& r, NAME##_Args* a) { (void)r; (void)a;
#define RSE_ARG(type, name, units, lo, hi, text) readValue(r, &a->name);
#define RSE_BLOB(name, max, text)                                                                  \
    a->name##_length = static_cast<std::uint16_t>(r.remaining() < (max) ? r.remaining() : (max)); \
    r.bytes(a->name, a->name##_length);
#define RSE_CMD_END(NAME) }
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_CMD
#undef RSE_ARG
#undef RSE_BLOB
#undef RSE_CMD_END

#define RSE_CMD(NAME, apid, fc, modes, text) \
    inline void encodeArgs(core::BeWriter& w, const NAME##_Args& a) { (void)w; (void)a;
#define RSE_ARG(type, name, units, lo, hi, text) writeValue(w, a.name);
#define RSE_BLOB(name, max, text) w.bytes(a.name, a.name##_length <= (max) ? a.name##_length : (max));
#define RSE_CMD_END(NAME) }
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

// ---- Telemetry -----------------------------------------------------------------
#define RSE_CMD(NAME, apid, fc, modes, text)
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
#define RSE_TLM(NAME, apid_, text) struct NAME##_Tlm { static constexpr std::uint16_t kApid = apid_;
#define RSE_FIELD(T, name, count, units, text) typename wire::Storage<wire::T, count>::type name;
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

#define RSE_TLM(NAME, apid_, text) inline void encodeTelemetry(core::BeWriter& w, const NAME##_Tlm& t) {
#define RSE_FIELD(type, name, count, units, text) writeValue(w, t.name);
#define RSE_TLM_END(NAME) }
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

// Payload sizes on the wire (after the telemetry header).
#define RSE_TLM(NAME, apid_, text) constexpr std::size_t k##NAME##_TlmSize = 0
#define RSE_FIELD(type, name, count, units, text) +wireSize(FieldType::type) * (count)
#define RSE_TLM_END(NAME) ;
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

// ---- Descriptors (generic access by name or id) --------------------------------
struct ArgDesc {
    const char* name;
    FieldType type;
    const char* units;
    double min;
    double max;
    std::uint16_t maxBytes;  // blob only
    const char* description;
};

struct CommandDesc {
    CommandCode code;
    const char* name;
    std::uint16_t apid;
    std::uint8_t functionCode;
    std::uint8_t modes;  // mode_mask bits
    const char* description;
    const ArgDesc* args;
    std::uint8_t argCount;
    std::uint16_t fixedArgBytes;  // all arguments but a blob
    std::uint16_t maxBlobBytes;   // 0: no blob
};

struct FieldDesc {
    const char* name;
    FieldType type;
    std::uint16_t count;
    const char* units;
    const char* description;
};

struct TelemetryDesc {
    const char* name;
    std::uint16_t apid;
    const char* description;
    const FieldDesc* fields;
    std::uint8_t fieldCount;
    std::uint16_t payloadSize;
};

const CommandDesc* commandDescs(std::size_t* count);
const CommandDesc* findCommand(std::uint16_t apid, std::uint8_t functionCode);
const CommandDesc* findCommand(const char* name);
const CommandDesc& describe(CommandCode code);
bool isCommandApid(std::uint16_t apid);
const TelemetryDesc* telemetryDescs(std::size_t* count);
const TelemetryDesc* findTelemetry(std::uint16_t apid);
const TelemetryDesc* findTelemetry(const char* name);

// Reads one scalar of the given wire type as a double (integers exactly up to
// 2^53); used by the validator for range checks and by ground for display.
double readAsDouble(core::BeReader& r, FieldType type);

}  // namespace rse::cmdtlm

#include "fsw/tables/table_image.hpp"

#include "fsw/tables/can_node_map_check.hpp"
#include "fsw/tables/coarse_map_check.hpp"

#include <cfloat>
#include <cmath>
#include <cstring>

#include "fsw/core/byte_codec.hpp"
#include "fsw/core/crc32.hpp"

namespace rse::tables {
namespace {

// Typed field codecs for the generated decodeTable/encodeTable.
void get(core::BeReader& r, std::uint8_t& v) { v = r.u8(); }
void get(core::BeReader& r, std::uint16_t& v) { v = r.u16(); }
void get(core::BeReader& r, std::uint32_t& v) { v = r.u32(); }
void get(core::BeReader& r, std::int32_t& v) { v = r.i32(); }
void get(core::BeReader& r, float& v) { v = r.f32(); }
void get(core::BeReader& r, double& v) { v = r.f64(); }
template <typename T, std::size_t N>
void get(core::BeReader& r, T (&v)[N]) {
    for (T& element : v) {
        get(r, element);
    }
}

void put(core::BeWriter& w, std::uint8_t v) { w.u8(v); }
void put(core::BeWriter& w, std::uint16_t v) { w.u16(v); }
void put(core::BeWriter& w, std::uint32_t v) { w.u32(v); }
void put(core::BeWriter& w, std::int32_t v) { w.i32(v); }
void put(core::BeWriter& w, float v) { w.f32(v); }
void put(core::BeWriter& w, double v) { w.f64(v); }
template <typename T, std::size_t N>
void put(core::BeWriter& w, const T (&v)[N]) {
    for (const T& element : v) {
        put(w, element);
    }
}

#define RSE_TABLE(Name, id, description) void encodeFields(core::BeWriter& w, const Name##Table& table) {
#define RSE_TABLE_FIELD(wire, name, count, units, min, max, description) put(w, table.name);
#define RSE_TABLE_END(Name) }
#include "fsw/tables/table_defs.def"

TableCheck fault(TableReject reason, std::size_t field = 0, bool named = false, std::uint16_t element = 0) {
    TableCheck check;
    check.reason = reason;
    check.field = named ? static_cast<std::int16_t>(field) : std::int16_t{-1};
    check.element = element;
    return check;
}

// Integer wire types: the values they hold, so a double is range-checked
// before it is converted (out-of-range conversion is undefined behaviour).
bool integerLimits(FieldType type, double* lo, double* hi) {
    switch (type) {
        case FieldType::kU8:
            *lo = 0.0;
            *hi = 255.0;
            return true;
        case FieldType::kU16:
            *lo = 0.0;
            *hi = 65535.0;
            return true;
        case FieldType::kU32:
            *lo = 0.0;
            *hi = 4294967295.0;
            return true;
        case FieldType::kI32:
            *lo = -2147483648.0;
            *hi = 2147483647.0;
            return true;
        case FieldType::kF32:
        case FieldType::kF64:
            break;
    }
    return false;
}

bool elementAt(const TableDesc& table, std::size_t payloadLength, std::uint16_t field, std::uint16_t element,
               std::size_t* offset) {
    if (field >= table.fieldCount || element >= table.fields[field].count || payloadLength < table.payloadSize) {
        return false;
    }
    *offset = fieldOffset(table, field) + element * fieldTypeSize(table.fields[field].type);
    return true;
}

}  // namespace

const char* toString(TableReject reason) {
    switch (reason) {
        case TableReject::kNone:
            return "ok";
        case TableReject::kTooShort:
            return "too short";
        case TableReject::kBadMagic:
            return "bad magic";
        case TableReject::kUnknownTable:
            return "unknown table";
        case TableReject::kWrongTable:
            return "wrong table";
        case TableReject::kBadFormat:
            return "bad format";
        case TableReject::kBadLength:
            return "bad length";
        case TableReject::kBadCrc:
            return "bad CRC";
        case TableReject::kOutOfRange:
            return "out of range";
        case TableReject::kNotFinite:
            return "not finite";
        case TableReject::kInconsistent:
            return "inconsistent";
        case TableReject::kTooLarge:
            return "too large";
        case TableReject::kChunkGap:
            return "chunk gap";
        case TableReject::kNotLoaded:
            return "not loaded";
        case TableReject::kNotValidated:
            return "not validated";
        case TableReject::kNoPending:
            return "nothing pending";
        case TableReject::kActivationPending:
            return "activation pending";
        case TableReject::kNoData:
            return "no data";
    }
    return "?";
}

bool readTableHeader(const std::uint8_t* image, std::size_t length, TableHeader* out) {
    if (image == nullptr || out == nullptr || length < kTableHeaderSize) {
        return false;
    }
    core::BeReader r(image, kTableHeaderSize);
    out->magic = r.u32();
    out->tableId = r.u16();
    out->format = r.u16();
    out->version = r.u32();
    out->payloadLength = r.u32();
    out->crc = r.u32();
    return r.ok();
}

std::uint32_t computeTableCrc(const std::uint8_t* image, std::size_t payloadLength) {
    const std::uint32_t header = core::crc32(image, kTableCrcOffset);
    return core::crc32(image + kTableHeaderSize, payloadLength, header);
}

TableCheck checkTableImage(const std::uint8_t* image, std::size_t length) {
    TableHeader header;
    if (!readTableHeader(image, length, &header)) {
        return fault(TableReject::kTooShort);
    }
    return checkTableImage(image, length, static_cast<TableId>(header.tableId));
}

TableCheck checkTableImage(const std::uint8_t* image, std::size_t length, TableId expected) {
    TableHeader header;
    if (!readTableHeader(image, length, &header)) {
        return fault(TableReject::kTooShort);
    }
    if (header.magic != kTableMagic) {
        return fault(TableReject::kBadMagic);
    }
    if (header.format != kTableFormat) {
        return fault(TableReject::kBadFormat);
    }
    const TableDesc* table = findTable(static_cast<TableId>(header.tableId));
    if (table == nullptr) {
        return fault(TableReject::kUnknownTable);
    }
    if (table->id != expected) {
        return fault(TableReject::kWrongTable);
    }
    if (header.payloadLength != table->payloadSize || length - kTableHeaderSize != table->payloadSize) {
        return fault(TableReject::kBadLength);
    }
    if (computeTableCrc(image, table->payloadSize) != header.crc) {
        return fault(TableReject::kBadCrc);
    }
    return checkTablePayload(*table, image + kTableHeaderSize, table->payloadSize);
}

TableReject checkFieldValue(const TableFieldDesc& field, double value) {
    double lo = field.min;
    double hi = field.max;
    if (isFloatType(field.type)) {
        if (!std::isfinite(value)) {
            return TableReject::kNotFinite;
        }
        if (field.type == FieldType::kF32) {
            // Stored as a float, so judged as one: 0.1 at the bound of [0, 0.1] is in range.
            if (std::fabs(value) > static_cast<double>(FLT_MAX)) {
                return TableReject::kOutOfRange;
            }
            value = static_cast<double>(static_cast<float>(value));
            lo = static_cast<double>(static_cast<float>(lo));
            hi = static_cast<double>(static_cast<float>(hi));
        }
    } else if (!std::isfinite(value) || std::trunc(value) != value) {
        return TableReject::kOutOfRange;
    }
    return (value < lo || value > hi) ? TableReject::kOutOfRange : TableReject::kNone;
}

TableCheck checkTablePayload(const TableDesc& table, const std::uint8_t* payload, std::size_t length) {
    if (payload == nullptr || length != table.payloadSize) {
        return fault(TableReject::kBadLength);
    }
    for (std::size_t f = 0; f < table.fieldCount; ++f) {
        const TableFieldDesc& field = table.fields[f];
        for (std::uint16_t e = 0; e < field.count; ++e) {
            double value = 0.0;
            if (!readFieldValue(table, payload, length, static_cast<std::uint16_t>(f), e, &value)) {
                return fault(TableReject::kBadLength);
            }
            const TableReject reason = checkFieldValue(field, value);
            if (reason != TableReject::kNone) {
                return fault(reason, f, true, e);
            }
        }
    }
    std::size_t ruleCount = 0;
    const TableRuleDesc* rules = tableRules(&ruleCount);
    for (std::size_t i = 0; i < ruleCount; ++i) {
        const TableRuleDesc& rule = rules[i];
        double lower = 0.0;
        double upper = 0.0;
        if (rule.id == table.id && readFieldValue(table, payload, length, rule.lower, 0, &lower) &&
            readFieldValue(table, payload, length, rule.upper, 0, &upper) && !(lower < upper)) {
            return fault(TableReject::kInconsistent, rule.lower, true);
        }
    }
    if (table.id == TableId::kCoarseMap) {
        return checkCoarseMapPayload(table, payload, length);
    }
    if (table.id == TableId::kCanNodeMap) {
        return checkCanNodeMapPayload(table, payload, length);
    }
    return TableCheck{};
}

std::size_t fieldOffset(const TableDesc& table, std::uint16_t field) {
    std::size_t offset = 0;
    for (std::size_t f = 0; f < field && f < table.fieldCount; ++f) {
        offset += table.fields[f].count * fieldTypeSize(table.fields[f].type);
    }
    return offset;
}

bool readFieldValue(const TableDesc& table, const std::uint8_t* payload, std::size_t payloadLength,
                    std::uint16_t field, std::uint16_t element, double* value) {
    std::size_t offset = 0;
    if (payload == nullptr || value == nullptr || !elementAt(table, payloadLength, field, element, &offset)) {
        return false;
    }
    core::BeReader r(payload + offset, payloadLength - offset);
    switch (table.fields[field].type) {
        case FieldType::kU8:
            *value = r.u8();
            break;
        case FieldType::kU16:
            *value = r.u16();
            break;
        case FieldType::kU32:
            *value = r.u32();
            break;
        case FieldType::kI32:
            *value = r.i32();
            break;
        case FieldType::kF32:
            *value = static_cast<double>(r.f32());
            break;
        case FieldType::kF64:
            *value = r.f64();
            break;
    }
    return r.ok();
}

bool writeFieldValue(const TableDesc& table, std::uint8_t* payload, std::size_t payloadLength, std::uint16_t field,
                     std::uint16_t element, double value) {
    std::size_t offset = 0;
    if (payload == nullptr || !elementAt(table, payloadLength, field, element, &offset)) {
        return false;
    }
    const FieldType type = table.fields[field].type;
    double lo = 0.0;
    double hi = 0.0;
    if (integerLimits(type, &lo, &hi) && !(value >= lo && value <= hi && std::trunc(value) == value)) {
        return false;
    }
    if (type == FieldType::kF32 && std::isfinite(value) && std::fabs(value) > static_cast<double>(FLT_MAX)) {
        return false;
    }
    core::BeWriter w(payload + offset, payloadLength - offset);
    switch (type) {
        case FieldType::kU8:
            w.u8(static_cast<std::uint8_t>(value));
            break;
        case FieldType::kU16:
            w.u16(static_cast<std::uint16_t>(value));
            break;
        case FieldType::kU32:
            w.u32(static_cast<std::uint32_t>(value));
            break;
        case FieldType::kI32:
            w.i32(static_cast<std::int32_t>(value));
            break;
        case FieldType::kF32:
            w.f32(static_cast<float>(value));
            break;
        case FieldType::kF64:
            w.f64(value);
            break;
    }
    return w.ok();
}

std::size_t sealTableImage(TableId id, std::uint32_t version, std::uint8_t* image, std::size_t capacity) {
    const TableDesc* table = findTable(id);
    if (table == nullptr || image == nullptr || capacity < kTableHeaderSize + table->payloadSize) {
        return 0;
    }
    core::BeWriter w(image, kTableHeaderSize);
    w.u32(kTableMagic);
    w.u16(static_cast<std::uint16_t>(id));
    w.u16(kTableFormat);
    w.u32(version);
    w.u32(static_cast<std::uint32_t>(table->payloadSize));
    w.u32(computeTableCrc(image, table->payloadSize));
    return w.ok() ? kTableHeaderSize + table->payloadSize : 0;
}

#define RSE_TABLE(Name, id, description)                                                                  \
    TableCheck decodeTable(const std::uint8_t* image, std::size_t length, Name##Table* out) {             \
        const TableCheck check = checkTableImage(image, length, TableId::k##Name);                        \
        if (!check.ok() || out == nullptr) {                                                              \
            return check;                                                                                 \
        }                                                                                                 \
        core::BeReader r(image + kTableHeaderSize, length - kTableHeaderSize);                            \
        Name##Table table{};
#define RSE_TABLE_FIELD(wire, name, count, units, min, max, description) get(r, table.name);
#define RSE_TABLE_END(Name)                                                                               \
    if (!r.ok()) {                                                                                        \
        return fault(TableReject::kBadLength);                                                            \
    }                                                                                                     \
    *out = table;                                                                                         \
    return check;                                                                                         \
    }                                                                                                     \
    std::size_t encodeTable(const Name##Table& table, std::uint32_t version, std::uint8_t* out,          \
                            std::size_t capacity) {                                                       \
        if (out == nullptr || capacity < kTableHeaderSize + k##Name##PayloadSize) {                       \
            return 0;                                                                                     \
        }                                                                                                 \
        core::BeWriter w(out + kTableHeaderSize, k##Name##PayloadSize);                                   \
        encodeFields(w, table);                                                                           \
        return w.ok() ? sealTableImage(TableId::k##Name, version, out, capacity) : 0;                     \
    }
#include "fsw/tables/table_defs.def"

}  // namespace rse::tables

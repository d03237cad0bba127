// Table ids, the typed table structs and the descriptors of every field, all
// expanded from fsw/tables/table_defs.def so the flight code, the ground table
// compiler and the docs cannot disagree about a table's layout.
//
// The structs are what flight code reads (TableService's accessors); the
// descriptors are what generic code walks (image checks, the ground compiler,
// dumps): name, wire type, element count, units, allowed range, description.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rse::tables {

// Wire type of a field; every element is big-endian in an image payload.
enum class FieldType : std::uint8_t { kU8 = 0, kU16, kU32, kI32, kF32, kF64 };
const char* toString(FieldType type);  // "u8", "u16", ... as written in the .def

constexpr std::size_t fieldTypeSize(FieldType type) {
    switch (type) {
        case FieldType::kU8:
            return 1;
        case FieldType::kU16:
            return 2;
        case FieldType::kU32:
        case FieldType::kI32:
        case FieldType::kF32:
            return 4;
        case FieldType::kF64:
            return 8;
    }
    return 0;
}

constexpr bool isFloatType(FieldType type) { return type == FieldType::kF32 || type == FieldType::kF64; }

namespace detail {

// The .def names types u8 ... f64; these map them to C++ types and FieldType.
using CType_u8 = std::uint8_t;
using CType_u16 = std::uint16_t;
using CType_u32 = std::uint32_t;
using CType_i32 = std::int32_t;
using CType_f32 = float;
using CType_f64 = double;
constexpr FieldType kType_u8 = FieldType::kU8;
constexpr FieldType kType_u16 = FieldType::kU16;
constexpr FieldType kType_u32 = FieldType::kU32;
constexpr FieldType kType_i32 = FieldType::kI32;
constexpr FieldType kType_f32 = FieldType::kF32;
constexpr FieldType kType_f64 = FieldType::kF64;

// count 1 is a plain scalar member, count N an array of N.
template <typename T, std::size_t N>
struct Storage {
    using type = T[N];
};
template <typename T>
struct Storage<T, 1> {
    using type = T;
};

}  // namespace detail

// Ids are part of the ground interface (docs/tables.md).
enum class TableId : std::uint16_t {
#define RSE_TABLE(Name, id, description) k##Name = id,
#include "fsw/tables/table_defs.def"
};

constexpr std::size_t kTableCount = 0
#define RSE_TABLE(Name, id, description) +1
#include "fsw/tables/table_defs.def"
    ;

// One plain struct per table, members named and ordered as in the .def.
#define RSE_TABLE(Name, id, description) struct Name##Table {
#define RSE_TABLE_FIELD(wire, name, count, units, min, max, description) \
    detail::Storage<detail::CType_##wire, count>::type name{};
#define RSE_TABLE_END(Name) \
    }                       \
    ;
#include "fsw/tables/table_defs.def"

// Field indices per table (RoverGeometryField::wheel_radius_m == 0, ...), the
// `field` of a TableCheck and the index into TableDesc::fields.
#define RSE_TABLE(Name, id, description) \
    struct Name##Field {                 \
        enum Index : std::uint16_t {
#define RSE_TABLE_FIELD(wire, name, count, units, min, max, description) name,
#define RSE_TABLE_END(Name) \
    kCount                  \
    }                       \
    ;                       \
    }                       \
    ;
#include "fsw/tables/table_defs.def"

// Payload bytes per table (k<Name>PayloadSize) and the largest of them.
#define RSE_TABLE(Name, id, description) constexpr std::size_t k##Name##PayloadSize = 0
#define RSE_TABLE_FIELD(wire, name, count, units, min, max, description) \
    +std::size_t{count} * sizeof(detail::CType_##wire)
#define RSE_TABLE_END(Name) ;
#include "fsw/tables/table_defs.def"

namespace detail {
constexpr std::size_t kPayloadSizes[] = {
#define RSE_TABLE(Name, id, description) k##Name##PayloadSize,
#include "fsw/tables/table_defs.def"
};
constexpr std::size_t largestPayload() {
    std::size_t largest = 0;
    for (std::size_t size : kPayloadSizes) {
        largest = size > largest ? size : largest;
    }
    return largest;
}
}  // namespace detail

constexpr std::size_t kMaxTablePayloadSize = detail::largestPayload();

struct TableFieldDesc {
    const char* name;
    FieldType type;
    std::uint16_t count;  // 1 = scalar
    const char* units;
    double min;           // every element must lie in [min, max]
    double max;
    const char* description;
};

struct TableDesc {
    TableId id;
    const char* name;  // upper snake case, as in the sources: "ROVER_GEOMETRY"
    const char* description;
    const TableFieldDesc* fields;
    std::size_t fieldCount;
    std::size_t payloadSize;  // bytes, big-endian packed
};

// A cross-field rule: field `lower` strictly below field `upper` (both scalar).
struct TableRuleDesc {
    TableId id;
    std::uint16_t lower;
    std::uint16_t upper;
    const char* why;
};

// nullptr for an id or name that is no table. Names match exactly ("ROVER_GEOMETRY").
const TableDesc* findTable(TableId id);
const TableDesc* findTable(const char* name);
// Every table, in .def order (which is id order); *count = kTableCount.
const TableDesc* tableDescs(std::size_t* count);
// Position of a table in tableDescs() (0 .. kTableCount-1); kTableCount for an unknown id.
std::size_t tableIndex(TableId id);
// Every cross-field rule of every table.
const TableRuleDesc* tableRules(std::size_t* count);

}  // namespace rse::tables

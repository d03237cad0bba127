#include "fsw/tables/table_types.hpp"

#include <cstring>

namespace rse::tables {
namespace {

// "RoverGeometry" -> "ROVER_GEOMETRY" at compile time: the .def names a table
// once, in the spelling C++ wants, and operators see the spelling sources use.
template <std::size_t N>
struct UpperSnakeName {
    char text[2 * N] = {};
    constexpr explicit UpperSnakeName(const char (&camel)[N]) {
        std::size_t out = 0;
        for (std::size_t i = 0; i + 1 < N; ++i) {
            const char c = camel[i];
            if (c >= 'A' && c <= 'Z' && i > 0) {
                text[out++] = '_';
            }
            text[out++] = (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
        }
    }
};

#define RSE_TABLE(Name, id, description) constexpr UpperSnakeName k##Name##Name(#Name);
#include "fsw/tables/table_defs.def"

#define RSE_TABLE(Name, id, description) constexpr TableFieldDesc k##Name##Fields[] = {
#define RSE_TABLE_FIELD(wire, name, count, units, min, max, description) \
    {#name, detail::kType_##wire, count, units, min, max, description},
#define RSE_TABLE_END(Name) \
    }                       \
    ;
#include "fsw/tables/table_defs.def"

constexpr TableDesc kDescs[] = {
#define RSE_TABLE(Name, id, description)                                                         \
    {TableId::k##Name, k##Name##Name.text, description, k##Name##Fields,                         \
     sizeof k##Name##Fields / sizeof k##Name##Fields[0], k##Name##PayloadSize},
#include "fsw/tables/table_defs.def"
};
static_assert(sizeof kDescs / sizeof kDescs[0] == kTableCount, "one descriptor per table");

// The trailing entry keeps the array non-empty should the .def hold no rule.
constexpr TableRuleDesc kRules[] = {
#define RSE_TABLE_RULE_LESS(Name, lower, upper, why) {TableId::k##Name, Name##Field::lower, Name##Field::upper, why},
#include "fsw/tables/table_defs.def"
    {TableId{0}, 0, 0, nullptr},
};
constexpr std::size_t kRuleCount = sizeof kRules / sizeof kRules[0] - 1;

constexpr bool idsAscendAndFieldsFit() {
    for (std::size_t i = 0; i < kTableCount; ++i) {
        if (i > 0 && static_cast<std::uint16_t>(kDescs[i].id) <= static_cast<std::uint16_t>(kDescs[i - 1].id)) {
            return false;
        }
        // TableCheck::field is an int16_t.
        if (kDescs[i].fieldCount > 0x7FFF) {
            return false;
        }
    }
    return true;
}
static_assert(idsAscendAndFieldsFit(), "table ids must be unique and listed in ascending order in the .def");

}  // namespace

const char* toString(FieldType type) {
    switch (type) {
        case FieldType::kU8:
            return "u8";
        case FieldType::kU16:
            return "u16";
        case FieldType::kU32:
            return "u32";
        case FieldType::kI32:
            return "i32";
        case FieldType::kF32:
            return "f32";
        case FieldType::kF64:
            return "f64";
    }
    return "?";
}

const TableDesc* findTable(TableId id) {
    const std::size_t index = tableIndex(id);
    return index < kTableCount ? &kDescs[index] : nullptr;
}

const TableDesc* findTable(const char* name) {
    if (name == nullptr) {
        return nullptr;
    }
    for (const TableDesc& desc : kDescs) {
        if (std::strcmp(desc.name, name) == 0) {
            return &desc;
        }
    }
    return nullptr;
}

const TableDesc* tableDescs(std::size_t* count) {
    if (count != nullptr) {
        *count = kTableCount;
    }
    return kDescs;
}

std::size_t tableIndex(TableId id) {
    for (std::size_t i = 0; i < kTableCount; ++i) {
        if (kDescs[i].id == id) {
            return i;
        }
    }
    return kTableCount;
}

const TableRuleDesc* tableRules(std::size_t* count) {
    if (count != nullptr) {
        *count = kRuleCount;
    }
    return kRules;
}

}  // namespace rse::tables

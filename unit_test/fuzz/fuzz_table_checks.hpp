// The table-image checks shared by the table fuzz targets (fuzz_table.cpp:
// the image checks and codecs alone; fuzz_table_service.cpp: the same and the
// table service's whole load sequence). unit_test/fuzz/README.md.
//
// Invariants (a broken one traps, which libFuzzer reports as a crash):
//   - checkTableImage without an expected id agrees with the check against
//     the header's own id, and passes against no other id;
//   - decodeTable gives the verdict of checkTableImage for its table, leaves
//     its output untouched when it refuses, and when it accepts, encodeTable of
//     the result reproduces the image byte for byte;
//   - every element of an accepted image reads back finite (floats) and within
//     its [min, max], and every cross-field rule holds.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>

#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::fuzz_table {

using namespace rse::tables;

// A little beyond the largest image the service takes, to reach too_large.
constexpr std::size_t kMaxInput = kMaxTableImageSize + 64;

#define FUZZ_REQUIRE(condition) \
    do {                        \
        if (!(condition)) {     \
            __builtin_trap();   \
        }                       \
    } while (0)

// FNV-1a: a data-derived, deterministic choice of chunk boundaries.
inline std::uint32_t fnv1a(const std::uint8_t* data, std::size_t size) {
    std::uint32_t h = 2166136261U;
    for (std::size_t i = 0; i < size; ++i) {
        h = (h ^ data[i]) * 16777619U;
    }
    return h;
}

// Field-by-field check of an accepted image, from the descriptors and the
// documented rule (f32 bounds compared as floats), independently of
// checkTablePayload.
inline void requireFieldsInRange(const TableDesc& table, const std::uint8_t* image, std::size_t length) {
    const std::uint8_t* payload = image + kTableHeaderSize;
    const std::size_t payloadLength = length - kTableHeaderSize;
    for (std::size_t f = 0; f < table.fieldCount; ++f) {
        const TableFieldDesc& field = table.fields[f];
        for (std::uint16_t e = 0; e < field.count; ++e) {
            double value = 0.0;
            FUZZ_REQUIRE(readFieldValue(table, payload, payloadLength, static_cast<std::uint16_t>(f), e, &value));
            FUZZ_REQUIRE(std::isfinite(value));
            if (field.type == FieldType::kF32) {
                const auto v = static_cast<float>(value);
                FUZZ_REQUIRE(v >= static_cast<float>(field.min) && v <= static_cast<float>(field.max));
            } else {
                FUZZ_REQUIRE(value >= field.min && value <= field.max);
            }
        }
        // An index past the end reads nothing.
        double ignored = 0.0;
        FUZZ_REQUIRE(!readFieldValue(table, payload, payloadLength, static_cast<std::uint16_t>(f), field.count,
                                     &ignored));
    }
    // Writing back every value read, then sealing, reproduces the image.
    std::uint8_t copy[kMaxTableImageSize];
    std::memcpy(copy, image, length);
    for (std::size_t f = 0; f < table.fieldCount; ++f) {
        for (std::uint16_t e = 0; e < table.fields[f].count; ++e) {
            double value = 0.0;
            FUZZ_REQUIRE(readFieldValue(table, payload, payloadLength, static_cast<std::uint16_t>(f), e, &value));
            FUZZ_REQUIRE(writeFieldValue(table, copy + kTableHeaderSize, payloadLength, static_cast<std::uint16_t>(f),
                                         e, value));
        }
    }
    TableHeader header;
    FUZZ_REQUIRE(readTableHeader(image, length, &header));
    FUZZ_REQUIRE(sealTableImage(table.id, header.version, copy, length) == length);
    FUZZ_REQUIRE(std::memcmp(copy, image, length) == 0);

    std::size_t ruleCount = 0;
    const TableRuleDesc* rules = tableRules(&ruleCount);
    for (std::size_t i = 0; i < ruleCount; ++i) {
        if (rules[i].id != table.id) {
            continue;
        }
        double lower = 0.0;
        double upper = 0.0;
        FUZZ_REQUIRE(readFieldValue(table, payload, payloadLength, rules[i].lower, 0, &lower));
        FUZZ_REQUIRE(readFieldValue(table, payload, payloadLength, rules[i].upper, 0, &upper));
        FUZZ_REQUIRE(lower < upper);
    }
}

// checkTableImage against every id (and a few that name no table), and the
// typed decoder and encoder of every table.
inline void checkAndDecode(const std::uint8_t* data, std::size_t size) {
    const TableCheck any = checkTableImage(data, size);
    TableHeader header;
    const bool haveHeader = readTableHeader(data, size, &header);
    FUZZ_REQUIRE(haveHeader == (size >= kTableHeaderSize));
    if (!haveHeader) {
        FUZZ_REQUIRE(any.reason == TableReject::kTooShort);
    }
    const TableDesc* named = haveHeader ? findTable(static_cast<TableId>(header.tableId)) : nullptr;
    if (any.ok()) {
        FUZZ_REQUIRE(named != nullptr);
        requireFieldsInRange(*named, data, size);
    }
    if (named != nullptr) {
        const TableCheck own = checkTableImage(data, size, named->id);
        FUZZ_REQUIRE(own.reason == any.reason && own.field == any.field && own.element == any.element);
        if (own.field >= 0) {
            FUZZ_REQUIRE(static_cast<std::size_t>(own.field) < named->fieldCount);
            FUZZ_REQUIRE(own.element < named->fields[own.field].count);
        }
    }

    std::size_t count = 0;
    const TableDesc* descs = tableDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        const TableCheck c = checkTableImage(data, size, descs[i].id);
        FUZZ_REQUIRE(!c.ok() || (any.ok() && named != nullptr && named->id == descs[i].id));
    }
    for (const std::uint16_t bogus : {std::uint16_t{0}, std::uint16_t{kTableCount + 1}, std::uint16_t{0xFFFF}}) {
        FUZZ_REQUIRE(!checkTableImage(data, size, static_cast<TableId>(bogus)).ok());
    }

    std::uint8_t encoded[kMaxTableImageSize];
#define RSE_TABLE(Name, id, description)                                                                  \
    {                                                                                                     \
        Name##Table table;                                                                                \
        std::memset(&table, 0xA5, sizeof table);                                                          \
        Name##Table untouched;                                                                            \
        std::memcpy(&untouched, &table, sizeof table);                                                    \
        const TableCheck decoded = decodeTable(data, size, &table);                                       \
        const TableCheck expected = checkTableImage(data, size, TableId::k##Name);                        \
        FUZZ_REQUIRE(decoded.reason == expected.reason && decoded.field == expected.field);               \
        if (!decoded.ok()) {                                                                              \
            FUZZ_REQUIRE(std::memcmp(&table, &untouched, sizeof table) == 0);                             \
        } else {                                                                                          \
            const std::size_t n = encodeTable(table, header.version, encoded, sizeof encoded);            \
            FUZZ_REQUIRE(n == size && std::memcmp(encoded, data, size) == 0);                             \
            FUZZ_REQUIRE(encodeTable(table, header.version, encoded, size - 1) == 0);                     \
        }                                                                                                 \
    }
#include "fsw/tables/table_defs.def"
}

// Header payload length and CRC made consistent with the bytes that follow.
inline bool repair(const std::uint8_t* data, std::size_t size, std::uint8_t* out) {
    if (size < kTableHeaderSize || size > kMaxTableImageSize) {
        return false;
    }
    std::memcpy(out, data, size);
    const auto payloadLength = static_cast<std::uint32_t>(size - kTableHeaderSize);
    for (std::size_t i = 0; i < 4; ++i) {
        out[12 + i] = static_cast<std::uint8_t>(payloadLength >> (24 - 8 * i));
    }
    const std::uint32_t crc = computeTableCrc(out, payloadLength);
    for (std::size_t i = 0; i < 4; ++i) {
        out[kTableCrcOffset + i] = static_cast<std::uint8_t>(crc >> (24 - 8 * i));
    }
    return true;
}

}  // namespace rse::fuzz_table

// Table images: the binary form of a parameter table, as built by the ground
// table compiler, uploaded, checked, activated and dumped (docs/tables.md).
//
//   offset  size  field
//        0     4  magic 0x52534554 ("RSET")
//        4     2  table id (TableId)
//        6     2  format (kTableFormat)
//        8     4  version: the operator's content revision, from the source
//       12     4  payload length in bytes (must equal the table's payloadSize)
//       16     4  CRC-32 (core::crc32) over bytes 0..15, then over the payload
//       20     n  payload: the fields in .def order, big-endian, packed
//
// The CRC covers the header too, so a flipped version byte is caught; header
// fields with a meaning of their own (magic, id, format, length) are checked
// first so a rejection names the specific fault.
//
// Flight-safe (no heap, no exceptions, every loop bounded by a table's field
// count) and linked into the host ground tool as well, so ground and flight
// run the same checks.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/tables/table_types.hpp"

namespace rse::tables {

constexpr std::uint32_t kTableMagic = 0x52534554U;  // "RSET"
constexpr std::uint16_t kTableFormat = 1;
constexpr std::size_t kTableHeaderSize = 20;
constexpr std::size_t kTableCrcOffset = 16;  // the CRC field, also the length of header it covers
constexpr std::size_t kMaxTableImageSize = kTableHeaderSize + kMaxTablePayloadSize;
// Each table keeps an inactive buffer of this size; the bound keeps uploads a
// few dozen load chunks and the service's memory small (the coarse map, 16
// polygons of 8 vertices, is the largest table at 1077 bytes).
static_assert(kMaxTableImageSize <= 2048, "a table image must fit in 2048 bytes");

// An image somewhere in memory (a default image, an upload).
struct TableImageRef {
    const std::uint8_t* data;
    std::size_t length;
};

// Why an image or a table operation was refused. Values are stable: each has
// its own event id (table_events.hpp) and appears in telemetry.
enum class TableReject : std::uint8_t {
    kNone = 0,
    kTooShort,           // shorter than the header
    kBadMagic,           // bytes 0..3 are not "RSET"
    kUnknownTable,       // table id names no table
    kWrongTable,         // a valid id, but not the table the image was loaded for
    kBadFormat,          // format is not kTableFormat
    kBadLength,          // header length, image length and the table's payload size disagree
    kBadCrc,             // CRC-32 does not match
    kOutOfRange,         // a field element outside its [min, max] (TableCheck names it)
    kNotFinite,          // a float field element is NaN or infinite
    kInconsistent,       // a cross-field rule broken (TableCheck names the lower field)
    kTooLarge,           // more bytes than kMaxTableImageSize, or than the caller's buffer
    kChunkGap,           // a chunk's offset is not where the previous one ended
    kNotLoaded,          // nothing in the buffer asked for
    kNotValidated,       // activate before a successful validate
    kNoPending,          // abort with no load, no validated image and no activation waiting
    kActivationPending,  // the table has an activation waiting for the next frame
    kNoData,             // a chunk with a length but no data
};
constexpr std::size_t kTableRejectCount = 18;
const char* toString(TableReject reason);

// The verdict of a check: reason kNone, or why not and (for kOutOfRange,
// kNotFinite, kInconsistent) which field and element.
struct TableCheck {
    TableReject reason = TableReject::kNone;
    std::int16_t field = -1;    // index into the table's fields, -1 when no field is at fault
    std::uint16_t element = 0;  // element of an array field (0 for a scalar)

    bool ok() const { return reason == TableReject::kNone; }
};

struct TableHeader {
    std::uint32_t magic = 0;
    std::uint16_t tableId = 0;  // raw: it may name no table
    std::uint16_t format = 0;
    std::uint32_t version = 0;
    std::uint32_t payloadLength = 0;
    std::uint32_t crc = 0;
};

// Decodes the header fields as they are, unchecked; false if length < kTableHeaderSize.
bool readTableHeader(const std::uint8_t* image, std::size_t length, TableHeader* out);

// The CRC an image with this header and payloadLength bytes of payload after it
// must carry (bytes 0..15, then bytes 20 .. 20 + payloadLength - 1).
std::uint32_t computeTableCrc(const std::uint8_t* image, std::size_t payloadLength);

// Every check, in order: length >= header, magic, format, id known (and equal to
// expected), header length == the table's payload size == image length - header,
// CRC, then every element of every field (floats finite; all within [min, max]),
// then the cross-field rules.
TableCheck checkTableImage(const std::uint8_t* image, std::size_t length);
TableCheck checkTableImage(const std::uint8_t* image, std::size_t length, TableId expected);

// The field and rule checks alone, on a payload of exactly table.payloadSize bytes.
TableCheck checkTablePayload(const TableDesc& table, const std::uint8_t* payload, std::size_t length);

// Whether one value may be stored in a field: kNone, kNotFinite or kOutOfRange.
// Integer fields also refuse a value with a fractional part; f32 fields compare
// the value and the bounds as floats, as they are stored.
TableReject checkFieldValue(const TableFieldDesc& field, double value);

// Byte offset of a field in its table's payload (the sum of the fields before it).
std::size_t fieldOffset(const TableDesc& table, std::uint16_t field);

// Generic access to element `element` of field `field` of a payload of
// table.payloadSize bytes. Read: false for an index outside the table. Write:
// also false for a value the field's wire type cannot hold (integer fields:
// fractional or beyond the type; f32: beyond float's range); ranges are not
// checked here, so tests and tools can build out-of-range images deliberately.
bool readFieldValue(const TableDesc& table, const std::uint8_t* payload, std::size_t payloadLength,
                    std::uint16_t field, std::uint16_t element, double* value);
bool writeFieldValue(const TableDesc& table, std::uint8_t* payload, std::size_t payloadLength, std::uint16_t field,
                     std::uint16_t element, double value);

// Writes the header (with CRC) in front of a payload already at
// image + kTableHeaderSize. Returns the image length, or 0 for an unknown id or
// capacity < kTableHeaderSize + the table's payload size.
std::size_t sealTableImage(TableId id, std::uint32_t version, std::uint8_t* image, std::size_t capacity);

// Typed codecs, one pair per table. decodeTable checks the image first (as
// checkTableImage with the table's id) and writes *out only if it passes.
// encodeTable writes the struct as an image whatever its values (0 if capacity
// is too small) and returns its length.
#define RSE_TABLE(Name, id, description)                                                         \
    TableCheck decodeTable(const std::uint8_t* image, std::size_t length, Name##Table* out);      \
    std::size_t encodeTable(const Name##Table& table, std::uint32_t version, std::uint8_t* out, \
                            std::size_t capacity);
#include "fsw/tables/table_defs.def"

}  // namespace rse::tables

// Host side of the parameter tables: compiles the human-editable sources
// (tables/*.toml) into table images, renders images as text, and emits the C++
// source of the default images rse-fsw boots with. docs/tables.md describes
// the sources and the image format; fsw/tables/table_defs.def the fields.
//
// A source:
//   table = "ROVER_GEOMETRY"     # TableDesc::name
//   version = 1                  # the operator's content revision, 0 .. 2^32-1
//   [values]                     # every field of the table, no other key
//   wheel_radius_m = 0.10
//   drive_node_id = [1, 2, 3, 4, 5, 6]
//
// Every value is checked with the same code the flight software runs
// (checkFieldValue, checkTablePayload), so an image this compiler produces
// passes the rover's validation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::ground {

// A source that does not compile, or a file that cannot be read or written. The
// message names the file and, where there is one, the line and the field; a
// source with several faults gets one line for each.
class TableSourceError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct CompiledTable {
    const tables::TableDesc* table = nullptr;
    std::uint32_t version = 0;
    std::vector<std::uint8_t> image;  // header + payload, passes checkTableImage
    std::string source;               // file (or name) it was compiled from
};

// Compiles TOML text; sourceName is used in error messages.
CompiledTable compileTableText(const std::string& text, const std::string& sourceName);
CompiledTable compileTableFile(const std::string& path);
// The image of one source file.
std::vector<std::uint8_t> compileTableSource(const std::string& path);

// Whole-file image I/O. Reading does not check the contents (describeImage and
// checkTableImage do, and say what is wrong, a wrong length included); it only
// refuses files far beyond any image (1 MiB).
std::vector<std::uint8_t> readTableImageFile(const std::string& path);
void writeTableImageFile(const std::string& path, const std::vector<std::uint8_t>& image);
// The image a table file holds: a source (name ending ".toml") compiled, any
// other file read as an image (unchecked, as readTableImageFile).
std::vector<std::uint8_t> readTableFile(const std::string& path);

// One line for a check verdict: "ok", "bad CRC (header 0x..., computed 0x...)",
// "out of range: drive_node_id[2] = 200, allowed [1, 127] node", ...
std::string describeCheck(const std::uint8_t* image, std::size_t length);

// A human-readable rendering of an image, good or bad: header fields, the check
// verdict, then (if the payload is long enough for its table) every field with
// its value, units, range and description, the faulty one marked.
std::string describeImage(const std::uint8_t* image, std::size_t length);

// The C++ source of kDefaultTableImages (fsw/tables/default_tables.hpp): exactly
// one image per table, in id order. Throws TableSourceError naming the missing
// or duplicated tables.
std::string defaultTablesSource(const std::vector<CompiledTable>& tables);

// Text for one value of a field: shortest form that reads back to the same
// stored value ("0.1" for the float 0.1f, "1e-09", "127").
std::string formatFieldValue(tables::FieldType type, double value);

}  // namespace rse::ground

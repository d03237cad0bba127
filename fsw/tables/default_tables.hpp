// The default table images rse-fsw boots with: one per table, compiled from
// tables/*.toml by `rse-ground table build --cpp` into
// build/<arch>/gen/default_tables.cpp (the Makefile's rule), so the flight
// software starts from exactly the bytes ground would upload. Order: by table id.
#pragma once

#include <cstddef>

#include "fsw/tables/table_image.hpp"

namespace rse::tables {

extern const TableImageRef kDefaultTableImages[];
extern const std::size_t kDefaultTableImageCount;

}  // namespace rse::tables

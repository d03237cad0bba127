// The coarse map's content rules, beyond what field ranges can say: every
// obstacle slot in use holds a strictly convex polygon of 3..8 vertices, and
// every other slot and vertex element is zero, so an image has one meaning and
// a stale polygon cannot hide beyond obstacle_count. Run by checkTablePayload,
// so the ground table compiler and the flight table service refuse the same
// images; the refusal is kInconsistent naming the element at fault.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/tables/table_image.hpp"

namespace rse::tables {

TableCheck checkCoarseMapPayload(const TableDesc& table, const std::uint8_t* payload, std::size_t length);

}  // namespace rse::tables

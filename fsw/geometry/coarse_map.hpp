// The coarse (orbital) map, table 9, as the planners read it: its slots of
// convex polygons and the distance from a point to the nearest of them. Shared
// by the habitual layer (its local map, escapes) and the deliberative layer (its
// planning problem, leg-end checks); it sits below both.
//
// The table is validated on load (every slot in use has 3..8 vertices and is
// strictly convex, fsw/tables/coarse_map_check.hpp); these readers still bound
// every count they take from it, so a table that slipped through cannot make
// them read out of its arrays.
//
// Pure math: no bus, no events, no state. No heap; loops bounded by the
// table's 16 slots and 8 vertices per slot.
#pragma once

#include <cstddef>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::geometry {

// Coarse-map slots and vertices per slot (table 9 layout).
constexpr std::size_t kCoarseMapSlots = 16;
constexpr std::size_t kCoarseMapVerticesPerSlot = 8;

// The slots in use: obstacle_count, at most kCoarseMapSlots.
std::size_t coarseMapSlotsUsed(const tables::CoarseMapTable& coarse);

// The vertex count of a slot in use, or 0 when it is not 3..kCoarseMapVerticesPerSlot
// (or slot is out of range).
std::size_t coarseMapVerticesUsed(const tables::CoarseMapTable& coarse, std::size_t slot);

// Vertex vertex of slot slot (both below their kCoarseMap* bound).
Point2 coarseMapVertex(const tables::CoarseMapTable& coarse, std::size_t slot, std::size_t vertex);

// Distance from p to the nearest coarse-map polygon, either winding (0 inside
// one); +inf without polygons.
double distanceToCoarseMap(const tables::CoarseMapTable& coarse, Point2 p);

}  // namespace rse::geometry

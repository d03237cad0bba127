// The local map the habitual layer plans on: a rectangle the rover centre must
// stay in, the coarse map's obstacles as convex polygons and the hazard
// detector's obstacles as discs, every one inflated by the rover's footprint
// radius (the clearance). The rover is then a point: a point is free when it
// lies inside the bounds (closed) and farther than the clearance from every
// obstacle; a segment is free when every point of it is.
//
// The tests are exact and analytic, not sampled: segment against a convex
// polygon inflated by r is "distance(segment, polygon) > r", against a disc
// "distance(centre, segment) > R + r". Touching (distance exactly r) is blocked.
// Cost: a 16 x 16 grid of obstacle bit masks over the bounds narrows a query to
// the obstacles whose inflated bounding box reaches the cells the query's own
// box covers; each of those is tested against its box, then exactly (a
// polygon: at most 8 edge separations, then 8 segment-segment distances).
//
// Pure data: no bus, no events. The caller (map builder) reports what it
// refuses; the map counts refused adds. Fixed size: nothing here allocates.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/geometry/geometry2d.hpp"

namespace rse::habitual {

// A convex rock or ledge outline from the coarse map: 8 vertices describe its
// shape to well within the footprint radius the map is inflated by.
constexpr std::size_t kMaxPolygonVertices = 8;
// Coarse-map obstacles in one local map. A 20 m x 20 m local window at the
// densest terrain the mission planner routes through holds about 30 mapped
// hazards (the cluttered benchmark field is 30); 48 leaves 60 % margin and
// keeps the per-cell polygon set one 64-bit mask.
constexpr std::size_t kMaxMapPolygons = 48;
// Obstacles seen by the hazard detector (HazardMsg) that are not on the coarse
// map yet; one 32-bit mask per cell.
constexpr std::size_t kMaxMapDiscs = 32;
// Obstacle grid cells per axis over the bounds.
constexpr std::size_t kMapGridCells = 16;

class LocalMap {
public:
    // Clears every obstacle. Bounds of the region the planner samples and the
    // rover centre must stay in; clearanceM: the footprint radius every obstacle is
    // inflated by. kInvalidArgument for non-finite values, min >= max on either
    // axis or clearance < 0 (the map then is empty and unusable: nothing is free).
    core::Status reset(geometry::Point2 min, geometry::Point2 max, double clearanceM);

    // A convex polygon, either winding, 3..kMaxPolygonVertices finite vertices,
    // no repeated consecutive vertex, positive area (collinear middle vertices are
    // accepted). kInvalidArgument otherwise, kFull when kMaxMapPolygons are held,
    // kNotInitialized before a successful reset(). The map is unchanged on error.
    core::Status addPolygon(const geometry::Point2* vertices, std::size_t count);
    // A disc of radius > 0 (finite). Errors as addPolygon.
    core::Status addDisc(geometry::Point2 centre, double radiusM);

    bool pointFree(geometry::Point2 p) const;
    bool segmentFree(geometry::Point2 a, geometry::Point2 b) const;

    std::size_t polygonCount() const { return polygonCount_; }
    std::size_t discCount() const { return discCount_; }
    geometry::Point2 min() const { return min_; }
    geometry::Point2 max() const { return max_; }
    double clearance() const { return clearance_; }
    bool valid() const { return valid_; }

    // Calls refused (reset and adds) since construction; reset() keeps the count.
    std::uint32_t refusedCalls() const { return refusedCalls_; }

private:
    struct Box {
        geometry::Point2 lo;
        geometry::Point2 hi;
    };
    struct Polygon {
        geometry::Point2 vertices[kMaxPolygonVertices];  // counter-clockwise
        geometry::Point2 normals[kMaxPolygonVertices];   // outward unit normal of edge i (vertex i -> i + 1)
        double offsets[kMaxPolygonVertices];   // normals[i] . vertices[i]
        Box inflatedBox;
        std::size_t count;
    };
    struct Disc {
        geometry::Point2 centre;
        double inflatedRadius;  // radius + clearance
        Box inflatedBox;
    };
    struct CellMask {
        std::uint64_t polygons;
        std::uint32_t discs;
    };
    struct CellRange {
        std::size_t x0, x1, y0, y1;
    };

    bool inBounds(geometry::Point2 p) const;
    std::size_t cellIndex(double v, double lo, double inverseCell) const;
    CellRange cellsOf(const Box& box) const;
    void markCells(const Box& box, std::uint64_t polygonBit, std::uint32_t discBit);
    CellMask gather(const Box& box) const;
    bool polygonBlocksPoint(const Polygon& poly, geometry::Point2 p) const;
    bool polygonBlocksSegment(const Polygon& poly, geometry::Point2 a, geometry::Point2 b) const;
    core::Status refuse(core::Status status);

    geometry::Point2 min_{0.0, 0.0};
    geometry::Point2 max_{0.0, 0.0};
    geometry::Point2 inverseCell_{0.0, 0.0};
    double clearance_ = 0.0;
    bool valid_ = false;
    Polygon polygons_[kMaxMapPolygons] = {};
    Disc discs_[kMaxMapDiscs] = {};
    std::size_t polygonCount_ = 0;
    std::size_t discCount_ = 0;
    CellMask cells_[kMapGridCells * kMapGridCells] = {};
    std::uint32_t refusedCalls_ = 0;
};

}  // namespace rse::habitual

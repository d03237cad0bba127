// The map: a rectangle of flat ground with convex polygonal obstacles.
//
// Each obstacle is either known (on the coarse orbital map the operators plan
// with) or hidden (only the hazard detector can reveal it). The simulator itself
// treats both alike; "known" only decides what a map export would show.
//
// A site of thousands of rocks (issue 31: generated fields) is indexed as the
// flight software's site map is (docs/site_map.md), by square cells
// (kTerrainCellM) each listing the obstacles whose bounding box touches it,
// so that asking what is near a point costs the cells and rocks there, not
// the site. near() lists them in index order, so a scan of near() visits what
// a scan of every obstacle would find, in the same order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim_stub/world/geometry.hpp"

namespace rse::sim {

struct MapBounds {
    double xMin = -50.0;
    double xMax = 50.0;
    double yMin = -50.0;
    double yMax = 50.0;

    bool contains(Vec2 p) const { return p.x >= xMin && p.x <= xMax && p.y >= yMin && p.y <= yMax; }
    // The whole disc lies inside the map.
    bool containsDisc(Vec2 c, double r) const {
        return c.x - r >= xMin && c.x + r <= xMax && c.y - r >= yMin && c.y + r <= yMax;
    }
};

struct Obstacle {
    // 1..65535, unique (0 is the hazard detector's "nothing in view"). The
    // detector reports a track number of its own (1..255) when ids pass 255.
    std::uint16_t id = 0;
    bool known = true;    // on the orbital map; false = hidden
    // false: the hazard detector never reports it (a flat or dark rock, one
    // in shadow: what the cameras miss). The rover meets it only by contact.
    bool detectable = true;
    ConvexPolygon shape;
};

constexpr std::size_t kNoObstacle = static_cast<std::size_t>(-1);
constexpr double kTerrainCellM = 4.0;

class Terrain {
public:
    // Copies the obstacles (start-up only: the only allocation).
    Terrain(const MapBounds& bounds, const std::vector<Obstacle>& obstacles);

    const MapBounds& bounds() const { return bounds_; }
    std::size_t obstacleCount() const { return obstacles_.size(); }
    const Obstacle& obstacle(std::size_t index) const { return obstacles_[index]; }
    // Index of the obstacle with this id, or kNoObstacle.
    std::size_t findById(std::uint16_t id) const;
    // The obstacles whose bounding box comes within reach of p (a superset of
    // those whose polygon does), in index order, into *out (cleared first).
    void near(Vec2 p, double reach, std::vector<std::size_t>* out) const;

    // Index of the first obstacle containing p (inside or on the boundary), or kNoObstacle.
    std::size_t obstacleAt(Vec2 p) const;
    // Index of the first obstacle the disc touches or overlaps, or kNoObstacle.
    std::size_t firstOverlap(Vec2 centre, double radius) const;
    // Index of the first obstacle the segment touches, or kNoObstacle.
    std::size_t firstOnSegment(Vec2 a, Vec2 b) const;
    // Clearance from p to the nearest obstacle boundary (0 inside one; +inf with none).
    double clearance(Vec2 p) const;

private:
    struct Box {
        double minX, minY, maxX, maxY;
    };
    std::size_t cellColumn(double x) const;
    std::size_t cellRow(double y) const;

    MapBounds bounds_;
    std::vector<Obstacle> obstacles_;
    std::vector<Box> boxes_;
    std::size_t columns_ = 1, rows_ = 1;
    std::vector<std::vector<std::size_t>> cells_;   // per cell, obstacle indices in order
    mutable std::vector<std::uint32_t> stamp_;     // near()'s once-each marks
    mutable std::uint32_t stampNow_ = 0;
};

}  // namespace rse::sim

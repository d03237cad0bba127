// The map: a rectangle of flat ground with convex polygonal obstacles.
//
// Each obstacle is either known (on the coarse orbital map the operators plan
// with) or hidden (only the hazard detector can reveal it). The simulator itself
// treats both alike; "known" only decides what a map export would show.
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
    std::uint8_t id = 0;  // 1..255 (0 is the hazard detector's "nothing in view")
    bool known = true;    // on the orbital map; false = hidden
    ConvexPolygon shape;
};

constexpr std::size_t kNoObstacle = static_cast<std::size_t>(-1);

class Terrain {
public:
    // Copies the obstacles (start-up only: the only allocation).
    Terrain(const MapBounds& bounds, const std::vector<Obstacle>& obstacles);

    const MapBounds& bounds() const { return bounds_; }
    std::size_t obstacleCount() const { return obstacles_.size(); }
    const Obstacle& obstacle(std::size_t index) const { return obstacles_[index]; }
    // Index of the obstacle with this id, or kNoObstacle.
    std::size_t findById(std::uint8_t id) const;

    // Index of the first obstacle containing p (inside or on the boundary), or kNoObstacle.
    std::size_t obstacleAt(Vec2 p) const;
    // Index of the first obstacle the disc touches or overlaps, or kNoObstacle.
    std::size_t firstOverlap(Vec2 centre, double radius) const;
    // Index of the first obstacle the segment touches, or kNoObstacle.
    std::size_t firstOnSegment(Vec2 a, Vec2 b) const;
    // Clearance from p to the nearest obstacle boundary (0 inside one; +inf with none).
    double clearance(Vec2 p) const;

private:
    MapBounds bounds_;
    std::vector<Obstacle> obstacles_;
};

}  // namespace rse::sim

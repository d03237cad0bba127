#include "sim_stub/world/terrain.hpp"

#include <limits>

namespace rse::sim {

Terrain::Terrain(const MapBounds& bounds, const std::vector<Obstacle>& obstacles)
    : bounds_(bounds), obstacles_(obstacles) {}

std::size_t Terrain::findById(std::uint8_t id) const {
    for (std::size_t i = 0; i < obstacles_.size(); ++i) {
        if (obstacles_[i].id == id) {
            return i;
        }
    }
    return kNoObstacle;
}

std::size_t Terrain::obstacleAt(Vec2 p) const {
    for (std::size_t i = 0; i < obstacles_.size(); ++i) {
        if (pointInPolygon(p, obstacles_[i].shape)) {
            return i;
        }
    }
    return kNoObstacle;
}

std::size_t Terrain::firstOverlap(Vec2 centre, double radius) const {
    for (std::size_t i = 0; i < obstacles_.size(); ++i) {
        if (circleIntersectsPolygon(centre, radius, obstacles_[i].shape)) {
            return i;
        }
    }
    return kNoObstacle;
}

std::size_t Terrain::firstOnSegment(Vec2 a, Vec2 b) const {
    for (std::size_t i = 0; i < obstacles_.size(); ++i) {
        if (segmentIntersectsPolygon(a, b, obstacles_[i].shape)) {
            return i;
        }
    }
    return kNoObstacle;
}

double Terrain::clearance(Vec2 p) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Obstacle& o : obstacles_) {
        const double d = distanceToPolygon(p, o.shape);
        best = d < best ? d : best;
    }
    return best;
}

}  // namespace rse::sim

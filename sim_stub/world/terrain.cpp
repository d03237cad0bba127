#include "sim_stub/world/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rse::sim {

Terrain::Terrain(const MapBounds& bounds, const std::vector<Obstacle>& obstacles)
    : bounds_(bounds), obstacles_(obstacles), stamp_(obstacles.size(), 0) {
    const double w = bounds_.xMax - bounds_.xMin;
    const double h = bounds_.yMax - bounds_.yMin;
    columns_ = w > 0.0 ? static_cast<std::size_t>(std::ceil(w / kTerrainCellM)) : 1;
    rows_ = h > 0.0 ? static_cast<std::size_t>(std::ceil(h / kTerrainCellM)) : 1;
    columns_ = std::max<std::size_t>(columns_, 1);
    rows_ = std::max<std::size_t>(rows_, 1);
    cells_.resize(columns_ * rows_);
    boxes_.reserve(obstacles_.size());
    for (std::size_t i = 0; i < obstacles_.size(); ++i) {
        const ConvexPolygon& poly = obstacles_[i].shape;
        Box b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
              -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
        for (std::size_t v = 0; v < poly.n; ++v) {
            b.minX = std::min(b.minX, poly.v[v].x);
            b.minY = std::min(b.minY, poly.v[v].y);
            b.maxX = std::max(b.maxX, poly.v[v].x);
            b.maxY = std::max(b.maxY, poly.v[v].y);
        }
        boxes_.push_back(b);
        if (poly.n == 0) {
            continue;
        }
        for (std::size_t r = cellRow(b.minY); r <= cellRow(b.maxY); ++r) {
            for (std::size_t c = cellColumn(b.minX); c <= cellColumn(b.maxX); ++c) {
                cells_[r * columns_ + c].push_back(i);
            }
        }
    }
}

std::size_t Terrain::cellColumn(double x) const {
    const double f = std::floor((x - bounds_.xMin) / kTerrainCellM);
    return f <= 0.0 ? 0 : std::min(static_cast<std::size_t>(f), columns_ - 1);
}

std::size_t Terrain::cellRow(double y) const {
    const double f = std::floor((y - bounds_.yMin) / kTerrainCellM);
    return f <= 0.0 ? 0 : std::min(static_cast<std::size_t>(f), rows_ - 1);
}

void Terrain::near(Vec2 p, double reach, std::vector<std::size_t>* out) const {
    out->clear();
    if (++stampNow_ == 0) {
        std::fill(stamp_.begin(), stamp_.end(), 0);
        stampNow_ = 1;
    }
    for (std::size_t r = cellRow(p.y - reach); r <= cellRow(p.y + reach); ++r) {
        for (std::size_t c = cellColumn(p.x - reach); c <= cellColumn(p.x + reach); ++c) {
            for (std::size_t i : cells_[r * columns_ + c]) {
                if (stamp_[i] == stampNow_) {
                    continue;
                }
                stamp_[i] = stampNow_;
                const Box& b = boxes_[i];
                const double dx = std::max({b.minX - p.x, 0.0, p.x - b.maxX});
                const double dy = std::max({b.minY - p.y, 0.0, p.y - b.maxY});
                if (dx * dx + dy * dy <= reach * reach) {
                    out->push_back(i);
                }
            }
        }
    }
    std::sort(out->begin(), out->end());
}

std::size_t Terrain::findById(std::uint16_t id) const {
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

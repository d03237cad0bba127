#include "fsw/habitual/local_map.hpp"

#include <cmath>

namespace rse::habitual {

using geometry::Point2;

namespace {

constexpr double kPi = 3.14159265358979323846;

bool overlaps(Point2 lo1, Point2 hi1, Point2 lo2, Point2 hi2) {
    return lo1.x <= hi2.x && lo2.x <= hi1.x && lo1.y <= hi2.y && lo2.y <= hi1.y;
}

}  // namespace

core::Status LocalMap::reset(Point2 min, Point2 max, double clearanceM) {
    valid_ = false;
    polygonCount_ = 0;
    discCount_ = 0;
    for (CellMask& cell : cells_) {
        cell = CellMask{0, 0};
    }
    if (!isFinite(min) || !isFinite(max) || !std::isfinite(clearanceM) || !(min.x < max.x) || !(min.y < max.y) ||
        clearanceM < 0.0) {
        return refuse(core::Status::kInvalidArgument);
    }
    min_ = min;
    max_ = max;
    clearance_ = clearanceM;
    constexpr double kCells = static_cast<double>(kMapGridCells);
    inverseCell_ = Point2{kCells / (max.x - min.x), kCells / (max.y - min.y)};
    if (!isFinite(inverseCell_)) {  // bounds so close that the cell size underflows
        return refuse(core::Status::kInvalidArgument);
    }
    valid_ = true;
    return core::Status::kOk;
}

core::Status LocalMap::addPolygon(const Point2* vertices, std::size_t count) {
    if (!valid_) {
        return refuse(core::Status::kNotInitialized);
    }
    if (vertices == nullptr || count < 3 || count > kMaxPolygonVertices) {
        return refuse(core::Status::kInvalidArgument);
    }
    double area2 = 0.0;  // twice the signed area (shoelace)
    for (std::size_t i = 0; i < count; ++i) {
        if (!isFinite(vertices[i])) {
            return refuse(core::Status::kInvalidArgument);
        }
        area2 += cross(vertices[i], vertices[i + 1 == count ? 0 : i + 1]);
    }
    if (!std::isfinite(area2) || area2 == 0.0) {
        return refuse(core::Status::kInvalidArgument);
    }
    Polygon poly{};
    poly.count = count;
    for (std::size_t i = 0; i < count; ++i) {  // store counter-clockwise
        poly.vertices[i] = area2 > 0.0 ? vertices[i] : vertices[count - 1 - i];
    }
    // Convex and simple: every corner turns left (or runs straight on) and the
    // turns add up to one full turn; a star polygon turns left everywhere too but
    // winds twice.
    double turning = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        const Point2 a = poly.vertices[i];
        const Point2 b = poly.vertices[(i + 1) % count];
        const Point2 c = poly.vertices[(i + 2) % count];
        const Point2 e1 = b - a;
        const Point2 e2 = c - b;
        const double len2 = dot(e1, e1);
        const double turn = cross(e1, e2);
        if (len2 == 0.0 || turn < 0.0 || (turn == 0.0 && dot(e1, e2) <= 0.0)) {
            return refuse(core::Status::kInvalidArgument);
        }
        turning += std::atan2(turn, dot(e1, e2));
        const double len = std::sqrt(len2);
        poly.normals[i] = Point2{e1.y / len, -e1.x / len};
        poly.offsets[i] = dot(poly.normals[i], a);
    }
    if (std::fabs(turning - 2.0 * kPi) > 1e-6) {
        return refuse(core::Status::kInvalidArgument);
    }
    if (polygonCount_ == kMaxMapPolygons) {
        return refuse(core::Status::kFull);
    }
    Box box{poly.vertices[0], poly.vertices[0]};
    for (std::size_t i = 1; i < count; ++i) {
        box.lo = Point2{std::fmin(box.lo.x, poly.vertices[i].x), std::fmin(box.lo.y, poly.vertices[i].y)};
        box.hi = Point2{std::fmax(box.hi.x, poly.vertices[i].x), std::fmax(box.hi.y, poly.vertices[i].y)};
    }
    const Point2 r{clearance_, clearance_};
    poly.inflatedBox = Box{box.lo - r, box.hi + r};
    polygons_[polygonCount_] = poly;
    markCells(poly.inflatedBox, std::uint64_t{1} << polygonCount_, 0);
    ++polygonCount_;
    return core::Status::kOk;
}

core::Status LocalMap::addDisc(Point2 centre, double radiusM) {
    if (!valid_) {
        return refuse(core::Status::kNotInitialized);
    }
    if (!isFinite(centre) || !std::isfinite(radiusM) || !(radiusM > 0.0)) {
        return refuse(core::Status::kInvalidArgument);
    }
    if (discCount_ == kMaxMapDiscs) {
        return refuse(core::Status::kFull);
    }
    const double inflated = radiusM + clearance_;
    const Point2 r{inflated, inflated};
    Disc& disc = discs_[discCount_];
    disc = Disc{centre, inflated, Box{centre - r, centre + r}};
    markCells(disc.inflatedBox, 0, std::uint32_t{1} << discCount_);
    ++discCount_;
    return core::Status::kOk;
}

bool LocalMap::pointFree(Point2 p) const {
    if (!inBounds(p)) {
        return false;
    }
    const CellMask mask = cells_[cellIndex(p.y, min_.y, inverseCell_.y) * kMapGridCells +
                                 cellIndex(p.x, min_.x, inverseCell_.x)];
    for (std::size_t i = 0; i < polygonCount_; ++i) {
        if ((mask.polygons >> i & 1U) != 0 && polygonBlocksPoint(polygons_[i], p)) {
            return false;
        }
    }
    for (std::size_t i = 0; i < discCount_; ++i) {
        if ((mask.discs >> i & 1U) != 0) {
            const double r = discs_[i].inflatedRadius;
            if (distanceSquared(p, discs_[i].centre) <= r * r) {
                return false;
            }
        }
    }
    return true;
}

bool LocalMap::segmentFree(Point2 a, Point2 b) const {
    // The bounds are convex: both ends inside keeps the whole segment inside.
    if (!inBounds(a) || !inBounds(b)) {
        return false;
    }
    const Box box{Point2{std::fmin(a.x, b.x), std::fmin(a.y, b.y)}, Point2{std::fmax(a.x, b.x), std::fmax(a.y, b.y)}};
    const CellMask mask = gather(box);
    for (std::size_t i = 0; i < polygonCount_; ++i) {
        if ((mask.polygons >> i & 1U) != 0) {
            const Polygon& poly = polygons_[i];
            if (overlaps(box.lo, box.hi, poly.inflatedBox.lo, poly.inflatedBox.hi) &&
                polygonBlocksSegment(poly, a, b)) {
                return false;
            }
        }
    }
    for (std::size_t i = 0; i < discCount_; ++i) {
        if ((mask.discs >> i & 1U) != 0) {
            const Disc& disc = discs_[i];
            if (overlaps(box.lo, box.hi, disc.inflatedBox.lo, disc.inflatedBox.hi) &&
                pointSegmentDistanceSquared(disc.centre, a, b) <= disc.inflatedRadius * disc.inflatedRadius) {
                return false;
            }
        }
    }
    return true;
}

bool LocalMap::inBounds(Point2 p) const {
    return valid_ && p.x >= min_.x && p.x <= max_.x && p.y >= min_.y && p.y <= max_.y;
}

// Monotonic in v, so a box's cell range and a point's cell agree on which side
// of a cell border a shared coordinate falls: a point inside an obstacle's box
// always lands in a cell marked for that obstacle.
std::size_t LocalMap::cellIndex(double v, double lo, double inverseCell) const {
    const double f = std::floor((v - lo) * inverseCell);
    if (!(f > 0.0)) {
        return 0;
    }
    constexpr double kLast = static_cast<double>(kMapGridCells - 1);
    return f >= kLast ? kMapGridCells - 1 : static_cast<std::size_t>(f);
}

LocalMap::CellRange LocalMap::cellsOf(const Box& box) const {
    return CellRange{cellIndex(box.lo.x, min_.x, inverseCell_.x), cellIndex(box.hi.x, min_.x, inverseCell_.x),
                     cellIndex(box.lo.y, min_.y, inverseCell_.y), cellIndex(box.hi.y, min_.y, inverseCell_.y)};
}

void LocalMap::markCells(const Box& box, std::uint64_t polygonBit, std::uint32_t discBit) {
    // Boxes wholly outside the bounds touch no point the planner may use.
    if (!overlaps(box.lo, box.hi, min_, max_)) {
        return;
    }
    const CellRange r = cellsOf(box);
    for (std::size_t y = r.y0; y <= r.y1; ++y) {
        for (std::size_t x = r.x0; x <= r.x1; ++x) {
            cells_[y * kMapGridCells + x].polygons |= polygonBit;
            cells_[y * kMapGridCells + x].discs |= discBit;
        }
    }
}

LocalMap::CellMask LocalMap::gather(const Box& box) const {
    const CellRange r = cellsOf(box);
    CellMask mask{0, 0};
    for (std::size_t y = r.y0; y <= r.y1; ++y) {
        for (std::size_t x = r.x0; x <= r.x1; ++x) {
            mask.polygons |= cells_[y * kMapGridCells + x].polygons;
            mask.discs |= cells_[y * kMapGridCells + x].discs;
        }
    }
    return mask;
}

bool LocalMap::polygonBlocksPoint(const Polygon& poly, Point2 p) const {
    bool inside = true;
    for (std::size_t i = 0; i < poly.count; ++i) {
        const double s = dot(poly.normals[i], p) - poly.offsets[i];
        if (s > clearance_) {
            return false;  // beyond the inflated half-plane of this edge
        }
        inside = inside && s <= 0.0;
    }
    if (inside) {
        return true;
    }
    const double r2 = clearance_ * clearance_;
    for (std::size_t i = 0; i < poly.count; ++i) {
        const Point2 v0 = poly.vertices[i];
        const Point2 v1 = poly.vertices[i + 1 == poly.count ? 0 : i + 1];
        if (pointSegmentDistanceSquared(p, v0, v1) <= r2) {
            return true;
        }
    }
    return false;
}

bool LocalMap::polygonBlocksSegment(const Polygon& poly, Point2 a, Point2 b) const {
    bool aInside = true;
    for (std::size_t i = 0; i < poly.count; ++i) {
        const double sa = dot(poly.normals[i], a) - poly.offsets[i];
        const double sb = dot(poly.normals[i], b) - poly.offsets[i];
        if (sa > clearance_ && sb > clearance_) {
            return false;  // the whole segment lies beyond the inflated half-plane
        }
        aInside = aInside && sa <= 0.0;
    }
    if (aInside) {
        return true;
    }
    // a is outside: the segment meets the polygon only by meeting an edge, so
    // the distance to the polygon is the least distance to an edge.
    const double r2 = clearance_ * clearance_;
    for (std::size_t i = 0; i < poly.count; ++i) {
        const Point2 v0 = poly.vertices[i];
        const Point2 v1 = poly.vertices[i + 1 == poly.count ? 0 : i + 1];
        if (segmentSegmentDistanceSquared(a, b, v0, v1) <= r2) {
            return true;
        }
    }
    return false;
}

core::Status LocalMap::refuse(core::Status status) {
    ++refusedCalls_;
    return status;
}

}  // namespace rse::habitual

// Fixed-size nearest-neighbour structure for the RRT* node pool: a uniform grid
// whose cells hold intrusive singly linked lists through the point array (one
// "next" index per point), so inserting is O(1) and nothing is ever allocated.
//
// The grid lives in a frame of its own (an origin and a unit axis: a rotation of
// the site frame) over a box of that frame, with square cells, as many as the
// owner asks for up to kMaxCells (about one per point keeps queries short).
// The planner puts the axis along start -> goal; once it has a solution every
// node it may still add lies in an ellipse around that axis, and re-gridding
// the kept points over the ellipse's box keeps the cells matched to the
// density there (regrid()).
//
// Queries search rings of cells outward from the query's cell and stop as soon
// as the nearest possible point of the next ring lies farther than what they
// already hold (the k-th best, or the radius). Rings are clipped to the box of
// cells that hold any point, so a query far from a young tree starts at the
// tree's edge. Distances are taken in the site frame (a rotation keeps them).
// Every loop is bounded: rings by the cells per axis, a list by the capacity (a
// point is in exactly one list, inserted once), re-sizing by a fixed count.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/geometry/geometry2d.hpp"

namespace rse::habitual {

struct Neighbour {
    std::uint32_t id;
    double distanceSquared;
};

template <std::size_t Capacity>
class PointGrid {
    static_assert(Capacity > 0 && Capacity < 0xFFFFFFFFU, "ids are 32-bit with one value reserved");

public:
    static constexpr std::uint32_t kNone = 0xFFFFFFFFU;
    // Cell heads (4 B each), in any nx x ny shape: with all of them a 20 m
    // square gets 128 x 128 cells of 0.16 m, a thin ellipse 25 m x 0.8 m some
    // 700 x 23 cells of 0.036 m. The owner picks how many to use (about one per
    // point keeps queries short) and re-grids as its points multiply.
    static constexpr std::size_t kMaxCells = 16384;

    // Empties the grid and sets its frame: local = ((p - origin) . axis,
    // axis x (p - origin)) for a unit axis; box [lo, hi] in local coordinates,
    // cut into at most `cells` (1..kMaxCells) square cells. kInvalidArgument for
    // a non-finite value, an axis not of unit length, an empty box or a bad count.
    core::Status reset(geometry::Point2 origin, geometry::Point2 axis, geometry::Point2 lo, geometry::Point2 hi,
                       std::size_t cells) {
        size_ = 0;
        nx_ = 0;
        ny_ = 0;
        if (!isFinite(origin) || !isFinite(axis) || std::fabs(dot(axis, axis) - 1.0) > 1e-9 || !isFinite(lo) ||
            !isFinite(hi) || !(lo.x < hi.x) || !(lo.y < hi.y) || cells < 1 || cells > kMaxCells) {
            return core::Status::kInvalidArgument;
        }
        origin_ = origin;
        axis_ = axis;
        shape(lo, hi, cells);
        return core::Status::kOk;
    }

    // Appends p; its id is the insertion index. kFull at capacity,
    // kInvalidArgument outside the box (or before a successful reset).
    core::Status insert(geometry::Point2 p, std::uint32_t* id) {
        if (size_ == Capacity) {
            return core::Status::kFull;
        }
        const geometry::Point2 l = toLocal(p);
        if (nx_ == 0 || !(l.x >= lo_.x && l.x <= hi_.x && l.y >= lo_.y && l.y <= hi_.y)) {
            return core::Status::kInvalidArgument;
        }
        const auto newId = static_cast<std::uint32_t>(size_);
        link(p);
        if (id != nullptr) {
            *id = newId;
        }
        return core::Status::kOk;
    }

    // Keeps the points whose keep[id] is nonzero, renumbered 0.. in id order (a
    // kept point's new id is the number of kept points before it), over a new
    // box: [lo, hi] widened to hold every kept point, in at most `cells` cells
    // (clamped to 1..kMaxCells). keep covers ids 0..size()-1. O(size + cells).
    void regrid(const std::uint8_t* keep, geometry::Point2 lo, geometry::Point2 hi, std::size_t cells) {
        if (nx_ == 0) {
            return;
        }
        const std::size_t old = size_;
        for (std::size_t id = 0; id < old; ++id) {
            if (keep[id] != 0) {
                const geometry::Point2 l = toLocal(points_[id].p);
                lo = geometry::Point2{std::fmin(lo.x, l.x), std::fmin(lo.y, l.y)};
                hi = geometry::Point2{std::fmax(hi.x, l.x), std::fmax(hi.y, l.y)};
            }
        }
        if (!(lo.x < hi.x) || !(lo.y < hi.y) || !isFinite(lo) || !isFinite(hi)) {
            lo = lo_;  // nothing sensible asked for: keep the old box
            hi = hi_;
        }
        shape(lo, hi, cells < 1 ? 1 : (cells > kMaxCells ? kMaxCells : cells));
        for (std::size_t id = 0; id < old; ++id) {
            if (keep[id] != 0) {
                link(points_[id].p);  // size_ <= id: never overwrites a point not yet read
            }
        }
    }

    std::size_t size() const { return size_; }
    std::size_t cellsX() const { return nx_; }
    std::size_t cellsY() const { return ny_; }
    std::size_t cellCount() const { return nx_ * ny_; }
    double cellSize() const { return cell_; }
    geometry::Point2 point(std::uint32_t id) const { return points_[id].p; }
    geometry::Point2 toLocal(geometry::Point2 p) const {
        const geometry::Point2 d = p - origin_;
        return geometry::Point2{dot(d, axis_), cross(axis_, d)};
    }

    // The nearest point to q (ties: any of them); kNone when empty.
    std::uint32_t nearest(geometry::Point2 q) const {
        Neighbour best{kNone, INFINITY};
        search(q, INFINITY, 1, &best);
        return best.id;
    }

    // The k (>= 1) points nearest to q within radius (distance <= radius), or
    // all there are if fewer, into out[0..k) in no particular order (ties at
    // the k-th distance: any of them). Returns how many.
    std::size_t nearestWithin(geometry::Point2 q, double radius, std::size_t k, Neighbour* out) const {
        if (k == 0 || out == nullptr || !(radius >= 0.0)) {
            return 0;
        }
        return search(q, radius * radius, k, out);
    }

private:
    struct Entry {
        geometry::Point2 p;  // site frame
        std::uint32_t next;
    };

    // Square cells, at most `cells` (<= kMaxCells) of them over [lo, hi];
    // empties every list.
    void shape(geometry::Point2 lo, geometry::Point2 hi, std::size_t cells) {
        const double target = static_cast<double>(cells);
        const double w = hi.x - lo.x;
        const double h = hi.y - lo.y;
        double cell = std::fmax(std::sqrt(w * h / target), std::fmax(w, h) / target) * (1.0 + 1e-9);
        cell = cell > 0.0 ? cell : 1.0;
        for (int grow = 0; grow < 64 && cellsFor(w, cell) * cellsFor(h, cell) > cells; ++grow) {
            cell *= 1.03;
        }
        nx_ = cellsFor(w, cell);
        ny_ = cellsFor(h, cell);
        if (nx_ * ny_ > cells) {  // not reached for finite boxes; one cell is always correct
            cell = std::fmax(w, h);
            nx_ = 1;
            ny_ = 1;
        }
        lo_ = lo;
        hi_ = hi;
        cell_ = cell;
        inverseCell_ = 1.0 / cell;
        for (std::size_t i = 0; i < nx_ * ny_; ++i) {
            heads_[i] = kNone;
        }
        size_ = 0;
        boxX0_ = static_cast<long>(nx_);
        boxX1_ = -1;
        boxY0_ = static_cast<long>(ny_);
        boxY1_ = -1;
    }

    // Appends p (inside the box, room left) as id size_.
    void link(geometry::Point2 p) {
        const geometry::Point2 l = toLocal(p);
        const long cx = cellX(l.x);
        const long cy = cellY(l.y);
        const std::size_t cell = static_cast<std::size_t>(cy) * nx_ + static_cast<std::size_t>(cx);
        points_[size_] = Entry{p, heads_[cell]};
        heads_[cell] = static_cast<std::uint32_t>(size_);
        ++size_;
        boxX0_ = cx < boxX0_ ? cx : boxX0_;
        boxX1_ = cx > boxX1_ ? cx : boxX1_;
        boxY0_ = cy < boxY0_ ? cy : boxY0_;
        boxY1_ = cy > boxY1_ ? cy : boxY1_;
    }

    static std::size_t cellsFor(double extent, double cell) {
        const double n = std::ceil(extent / cell);
        constexpr double kCells = static_cast<double>(kMaxCells);
        return n < 1.0 ? 1 : (n > kCells ? kMaxCells : static_cast<std::size_t>(n));
    }
    static long clampCell(double f, std::size_t n) {
        if (!(f > 0.0)) {
            return 0;
        }
        const double last = static_cast<double>(n - 1);
        return f >= last ? static_cast<long>(n - 1) : static_cast<long>(f);
    }
    long cellX(double localX) const { return clampCell(std::floor((localX - lo_.x) * inverseCell_), nx_); }
    long cellY(double localY) const { return clampCell(std::floor((localY - lo_.y) * inverseCell_), ny_); }

    // Offers the points of one cell to out[0..count), a max-heap on distance of
    // at most k entries (its root is the k-th best once full).
    std::size_t scanCell(std::size_t cell, geometry::Point2 q, double limit2, std::size_t k, Neighbour* out,
                         std::size_t count) const {
        std::size_t guard = 0;  // a list holds each point at most once
        for (std::uint32_t id = heads_[cell]; id != kNone && guard < Capacity; id = points_[id].next, ++guard) {
            const double d2 = distanceSquared(q, points_[id].p);
            if (d2 > limit2 || (count == k && d2 >= out[0].distanceSquared)) {
                continue;
            }
            if (count < k) {  // sift up from the new leaf
                std::size_t i = count++;
                for (; i > 0 && out[(i - 1) / 2].distanceSquared < d2; i = (i - 1) / 2) {
                    out[i] = out[(i - 1) / 2];
                }
                out[i] = Neighbour{id, d2};
                continue;
            }
            std::size_t i = 0;  // replace the root and sift down
            for (std::size_t child = 1; child < k; child = 2 * i + 1) {
                if (child + 1 < k && out[child + 1].distanceSquared > out[child].distanceSquared) {
                    ++child;
                }
                if (out[child].distanceSquared <= d2) {
                    break;
                }
                out[i] = out[child];
                i = child;
            }
            out[i] = Neighbour{id, d2};
        }
        return count;
    }

    std::size_t search(geometry::Point2 q, double limit2, std::size_t k, Neighbour* out) const {
        if (size_ == 0) {
            return 0;
        }
        const geometry::Point2 l = toLocal(q);
        const long cx = cellX(l.x);
        const long cy = cellY(l.y);
        // Distance from q to the border of its own cell (0 if q lies outside the grid).
        const double fx = l.x - (lo_.x + static_cast<double>(cx) * cell_);
        const double fy = l.y - (lo_.y + static_cast<double>(cy) * cell_);
        const double margin = std::fmax(0.0, std::fmin(std::fmin(fx, cell_ - fx), std::fmin(fy, cell_ - fy)));
        long first = 0;  // Chebyshev distance in cells from q's cell to the occupied box
        first = boxX0_ - cx > first ? boxX0_ - cx : first;
        first = cx - boxX1_ > first ? cx - boxX1_ : first;
        first = boxY0_ - cy > first ? boxY0_ - cy : first;
        first = cy - boxY1_ > first ? cy - boxY1_ : first;
        long last = 0;  // beyond this ring no occupied cell remains
        last = cx - boxX0_ > last ? cx - boxX0_ : last;
        last = boxX1_ - cx > last ? boxX1_ - cx : last;
        last = cy - boxY0_ > last ? cy - boxY0_ : last;
        last = boxY1_ - cy > last ? boxY1_ - cy : last;
        std::size_t count = 0;
        for (long r = first; r <= last; ++r) {
            if (r > 0) {
                const double reach = static_cast<double>(r - 1) * cell_ + margin;  // nearest point of ring r
                const double reach2 = reach * reach;
                if (reach2 > limit2 || (count == k && reach2 >= out[0].distanceSquared)) {
                    break;
                }
            }
            count = scanRing(q, cx, cy, r, limit2, k, out, count);
        }
        return count;
    }

    std::size_t scanRing(geometry::Point2 q, long cx, long cy, long r, double limit2, std::size_t k, Neighbour* out,
                         std::size_t count) const {
        const long x0 = cx - r > boxX0_ ? cx - r : boxX0_;
        const long x1 = cx + r < boxX1_ ? cx + r : boxX1_;
        const long y0 = cy - r + 1 > boxY0_ ? cy - r + 1 : boxY0_;
        const long y1 = cy + r - 1 < boxY1_ ? cy + r - 1 : boxY1_;
        const long rows[2] = {cy - r, cy + r};
        for (std::size_t i = 0; i < (r == 0 ? 1U : 2U); ++i) {
            if (rows[i] < boxY0_ || rows[i] > boxY1_) {
                continue;
            }
            const std::size_t base = static_cast<std::size_t>(rows[i]) * nx_;
            for (long x = x0; x <= x1; ++x) {
                count = scanCell(base + static_cast<std::size_t>(x), q, limit2, k, out, count);
            }
        }
        const long cols[2] = {cx - r, cx + r};
        for (std::size_t i = 0; r > 0 && i < 2; ++i) {
            if (cols[i] < boxX0_ || cols[i] > boxX1_) {
                continue;
            }
            for (long y = y0; y <= y1; ++y) {
                count = scanCell(static_cast<std::size_t>(y) * nx_ + static_cast<std::size_t>(cols[i]), q, limit2, k,
                                 out, count);
            }
        }
        return count;
    }

    Entry points_[Capacity] = {};
    std::uint32_t heads_[kMaxCells] = {};
    std::size_t size_ = 0;
    std::size_t nx_ = 0;
    std::size_t ny_ = 0;
    geometry::Point2 origin_{0.0, 0.0};
    geometry::Point2 axis_{1.0, 0.0};
    geometry::Point2 lo_{0.0, 0.0};  // box in the local frame
    geometry::Point2 hi_{0.0, 0.0};
    double cell_ = 1.0;
    double inverseCell_ = 1.0;
    long boxX0_ = 0;  // occupied cells: [boxX0_, boxX1_] x [boxY0_, boxY1_]
    long boxX1_ = -1;
    long boxY0_ = 0;
    long boxY1_ = -1;
};

}  // namespace rse::habitual

// Plane geometry for the planners (habitual and deliberative; it sits below
// both): points in the site frame (metres, x east, y north), the exact distance
// tests the collision checks are built from, and heading differences.
//
// Everything works on squared distances where it can, so the hot collision path
// takes no square root. Touching counts as meeting: a distance of exactly zero is
// reported as zero, never as "apart", so a free test that asks for distance > r
// is conservative at the boundary.
#pragma once

#include <cmath>
#include <cstddef>

namespace rse::geometry {

struct Point2 {
    double x;
    double y;
};

inline Point2 operator+(Point2 a, Point2 b) { return Point2{a.x + b.x, a.y + b.y}; }
inline Point2 operator-(Point2 a, Point2 b) { return Point2{a.x - b.x, a.y - b.y}; }
inline Point2 operator*(double s, Point2 a) { return Point2{s * a.x, s * a.y}; }

inline double dot(Point2 a, Point2 b) { return a.x * b.x + a.y * b.y; }
// z of the 3-D cross product: > 0 when b turns left (counter-clockwise) from a.
inline double cross(Point2 a, Point2 b) { return a.x * b.y - a.y * b.x; }

inline double distanceSquared(Point2 a, Point2 b) { return dot(a - b, a - b); }
inline double distance(Point2 a, Point2 b) { return std::sqrt(distanceSquared(a, b)); }

inline bool isFinite(Point2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// The point of the closed segment [a, b] nearest p (a when a == b).
inline Point2 closestOnSegment(Point2 p, Point2 a, Point2 b) {
    const Point2 ab = b - a;
    const double len2 = dot(ab, ab);
    if (len2 <= 0.0) {
        return a;
    }
    double t = dot(p - a, ab) / len2;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return a + t * ab;
}

// Squared distance from p to the closed segment [a, b] (a point when a == b).
inline double pointSegmentDistanceSquared(Point2 p, Point2 a, Point2 b) {
    return distanceSquared(p, closestOnSegment(p, a, b));
}

// True when the open interiors cross at a single point (a proper crossing).
// Touching and collinear overlap are left to the endpoint distances, which find
// them exactly (an endpoint then lies on the other segment: distance 0).
inline bool segmentsCrossProperly(Point2 a, Point2 b, Point2 c, Point2 d) {
    const double o1 = cross(b - a, c - a);
    const double o2 = cross(b - a, d - a);
    const double o3 = cross(d - c, a - c);
    const double o4 = cross(d - c, b - c);
    return ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0)) && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0));
}

// Squared distance between the closed segments [a, b] and [c, d]: zero when they
// meet, otherwise the nearest pair involves an endpoint of one of them.
inline double segmentSegmentDistanceSquared(Point2 a, Point2 b, Point2 c, Point2 d) {
    if (segmentsCrossProperly(a, b, c, d)) {
        return 0.0;
    }
    double best = pointSegmentDistanceSquared(a, c, d);
    const double db = pointSegmentDistanceSquared(b, c, d);
    const double dc = pointSegmentDistanceSquared(c, a, b);
    const double dd = pointSegmentDistanceSquared(d, a, b);
    best = db < best ? db : best;
    best = dc < best ? dc : best;
    best = dd < best ? dd : best;
    return best;
}

// p inside or on the boundary of the convex polygon whose count vertices run
// counter-clockwise. Callers bound count (habitual::LocalMap: kMaxPolygonVertices).
inline bool pointInConvexPolygon(Point2 p, const Point2* ccwVertices, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
        const Point2 a = ccwVertices[i];
        const Point2 b = ccwVertices[i + 1 == count ? 0 : i + 1];
        if (cross(b - a, p - a) < 0.0) {
            return false;
        }
    }
    return true;
}

// Squared distance from the closed segment [a, b] to the convex polygon whose
// count vertices run counter-clockwise: 0 when they meet (an end inside, or
// the segment crossing or touching an edge). A segment that enters the
// polygon with neither end inside crosses an edge, so the end test and the
// edge distances cover every case.
inline double segmentConvexPolygonDistanceSquared(Point2 a, Point2 b, const Point2* ccwVertices, std::size_t count) {
    if (pointInConvexPolygon(a, ccwVertices, count)) {
        return 0.0;
    }
    double best = INFINITY;
    for (std::size_t i = 0; i < count; ++i) {
        const double d = segmentSegmentDistanceSquared(a, b, ccwVertices[i], ccwVertices[i + 1 == count ? 0 : i + 1]);
        best = d < best ? d : best;
    }
    return best;
}

// An angle wrapped to (-pi, pi]; non-finite values pass through.
inline double wrapAngleRad(double radians) {
    constexpr double kPi = 3.14159265358979323846;
    constexpr double kTwoPi = 2.0 * kPi;
    if (!std::isfinite(radians)) {
        return radians;
    }
    double a = std::fmod(radians, kTwoPi);  // (-2 pi, 2 pi)
    if (a > kPi) {
        a -= kTwoPi;
    } else if (a <= -kPi) {
        a += kTwoPi;
    }
    return a;
}

}  // namespace rse::geometry

// Plane geometry for the simulated world: points, poses, convex polygons and the
// queries the collision check and the hazard detector need.
//
// Polygons are convex with their vertices counter-clockwise (the scenario parser
// rejects anything else) and stored inline (at most kMaxPolygonVertices), so an
// obstacle is a plain value: nothing here allocates.
#pragma once

#include <array>
#include <cstddef>

namespace rse::sim {

constexpr double kPi = 3.14159265358979323846;

struct Vec2 {
    double x = 0.0;
    double y = 0.0;
};

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(double k, Vec2 a) { return {k * a.x, k * a.y}; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
double norm(Vec2 a);

// Rover pose in the map frame: metres, heading in radians from +x, counter-clockwise.
struct Pose2 {
    double x = 0.0;
    double y = 0.0;
    double theta = 0.0;
};

// Wraps an angle to (-pi, pi].
double wrapAngle(double a);

// A map-frame point expressed in the frame of a pose (x ahead, y to the left).
Vec2 toBodyFrame(const Pose2& pose, Vec2 world);

constexpr std::size_t kMaxPolygonVertices = 16;

struct ConvexPolygon {
    std::array<Vec2, kMaxPolygonVertices> v{};
    std::size_t n = 0;

    Vec2 vertex(std::size_t i) const { return v[i % n]; }
};

// True when the vertices form a strictly convex polygon listed counter-clockwise
// (every turn strictly left, the boundary winding once): no repeated or collinear
// vertices, no self-intersection. Fewer than 3 vertices is false.
bool isConvexCcw(const Vec2* vertices, std::size_t count);

// Closest point of segment [a, b] to p.
Vec2 closestOnSegment(Vec2 p, Vec2 a, Vec2 b);

// Inside or on the boundary.
bool pointInPolygon(Vec2 p, const ConvexPolygon& poly);
// Closest point of the polygon (its boundary, or p itself when p is inside).
Vec2 closestPoint(Vec2 p, const ConvexPolygon& poly);
// 0 when p is inside.
double distanceToPolygon(Vec2 p, const ConvexPolygon& poly);
// The disc of radius r around c touches or overlaps the polygon (distance <= r).
bool circleIntersectsPolygon(Vec2 c, double r, const ConvexPolygon& poly);
// Proper or touching intersection of two segments.
bool segmentsIntersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);
// The segment [a, b] touches the polygon (an end inside, or crossing an edge).
bool segmentIntersectsPolygon(Vec2 a, Vec2 b, const ConvexPolygon& poly);

// Keeps the part of poly on the left of the directed line through a with
// direction dir (cross(dir, p - a) >= 0). Sutherland-Hodgman, one edge; the
// output holds at most in.n + 1 vertices (truncated at kMaxPolygonVertices + 4).
struct ClipPolygon {
    std::array<Vec2, kMaxPolygonVertices + 4> v{};
    std::size_t n = 0;
};
void clipLeftOf(const ClipPolygon& in, Vec2 a, Vec2 dir, ClipPolygon* out);

}  // namespace rse::sim

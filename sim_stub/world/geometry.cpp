#include "sim_stub/world/geometry.hpp"

#include <cmath>

namespace rse::sim {

double norm(Vec2 a) { return std::hypot(a.x, a.y); }

double wrapAngle(double a) {
    if (a > -kPi && a <= kPi) {
        return a;
    }
    double w = std::fmod(a + kPi, 2.0 * kPi);
    if (w <= 0.0) {
        w += 2.0 * kPi;
    }
    return w - kPi;
}

Vec2 toBodyFrame(const Pose2& pose, Vec2 world) {
    const double dx = world.x - pose.x;
    const double dy = world.y - pose.y;
    const double c = std::cos(pose.theta);
    const double s = std::sin(pose.theta);
    return {c * dx + s * dy, -s * dx + c * dy};
}

bool isConvexCcw(const Vec2* vertices, std::size_t count) {
    if (vertices == nullptr || count < 3) {
        return false;
    }
    double turned = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        const Vec2 a = vertices[i];
        const Vec2 b = vertices[(i + 1) % count];
        const Vec2 c = vertices[(i + 2) % count];
        const Vec2 e1 = b - a;
        const Vec2 e2 = c - b;
        if (norm(e1) <= 0.0 || !(cross(e1, e2) > 0.0)) {
            return false;  // repeated vertex, straight or right turn (or NaN)
        }
        turned += std::atan2(cross(e1, e2), dot(e1, e2));
    }
    // Every turn left and the exterior angles summing to one full turn: a simple
    // convex polygon (a star that winds twice also turns left at every vertex).
    return std::fabs(turned - 2.0 * kPi) < 1e-6;
}

Vec2 closestOnSegment(Vec2 p, Vec2 a, Vec2 b) {
    const Vec2 ab = b - a;
    const double len2 = dot(ab, ab);
    if (len2 <= 0.0) {
        return a;
    }
    double t = dot(p - a, ab) / len2;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return a + t * ab;
}

bool pointInPolygon(Vec2 p, const ConvexPolygon& poly) {
    if (poly.n < 3) {
        return false;
    }
    for (std::size_t i = 0; i < poly.n; ++i) {
        const Vec2 a = poly.vertex(i);
        const Vec2 b = poly.vertex(i + 1);
        if (cross(b - a, p - a) < 0.0) {
            return false;  // strictly right of a counter-clockwise edge: outside
        }
    }
    return true;
}

Vec2 closestPoint(Vec2 p, const ConvexPolygon& poly) {
    if (pointInPolygon(p, poly) || poly.n == 0) {
        return p;
    }
    Vec2 best = poly.vertex(0);
    double bestD = norm(p - best);
    for (std::size_t i = 0; i < poly.n; ++i) {
        const Vec2 q = closestOnSegment(p, poly.vertex(i), poly.vertex(i + 1));
        const double d = norm(p - q);
        if (d < bestD) {
            bestD = d;
            best = q;
        }
    }
    return best;
}

double distanceToPolygon(Vec2 p, const ConvexPolygon& poly) { return norm(p - closestPoint(p, poly)); }

bool circleIntersectsPolygon(Vec2 c, double r, const ConvexPolygon& poly) {
    return poly.n >= 3 && distanceToPolygon(c, poly) <= r;
}

namespace {
int orientation(Vec2 a, Vec2 b, Vec2 c) {
    const double v = cross(b - a, c - a);
    return v > 0.0 ? 1 : (v < 0.0 ? -1 : 0);
}
bool onSegment(Vec2 p, Vec2 a, Vec2 b) {
    return p.x >= std::fmin(a.x, b.x) && p.x <= std::fmax(a.x, b.x) && p.y >= std::fmin(a.y, b.y) &&
           p.y <= std::fmax(a.y, b.y);
}
}  // namespace

bool segmentsIntersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const int o1 = orientation(a, b, c);
    const int o2 = orientation(a, b, d);
    const int o3 = orientation(c, d, a);
    const int o4 = orientation(c, d, b);
    if (o1 != o2 && o3 != o4) {
        return true;
    }
    return (o1 == 0 && onSegment(c, a, b)) || (o2 == 0 && onSegment(d, a, b)) || (o3 == 0 && onSegment(a, c, d)) ||
           (o4 == 0 && onSegment(b, c, d));
}

bool segmentIntersectsPolygon(Vec2 a, Vec2 b, const ConvexPolygon& poly) {
    if (poly.n < 3) {
        return false;
    }
    if (pointInPolygon(a, poly) || pointInPolygon(b, poly)) {
        return true;
    }
    for (std::size_t i = 0; i < poly.n; ++i) {
        if (segmentsIntersect(a, b, poly.vertex(i), poly.vertex(i + 1))) {
            return true;
        }
    }
    return false;
}

void clipLeftOf(const ClipPolygon& in, Vec2 a, Vec2 dir, ClipPolygon* out) {
    out->n = 0;
    if (in.n == 0) {
        return;
    }
    auto push = [out](Vec2 p) {
        if (out->n < out->v.size()) {
            out->v[out->n++] = p;
        }
    };
    for (std::size_t i = 0; i < in.n; ++i) {
        const Vec2 p = in.v[i];
        const Vec2 q = in.v[(i + 1) % in.n];
        const double sp = cross(dir, p - a);
        const double sq = cross(dir, q - a);
        if (sp >= 0.0) {
            push(p);
        }
        if ((sp >= 0.0) != (sq >= 0.0)) {
            const double t = sp / (sp - sq);
            push(p + t * (q - p));
        }
    }
}

}  // namespace rse::sim

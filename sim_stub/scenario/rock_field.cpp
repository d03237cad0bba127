#include "sim_stub/scenario/rock_field.hpp"

#include <algorithm>
#include <cmath>

#include "sim_stub/world/random.hpp"

namespace rse::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kTableSteps = 4096;   // the inverse CDF's table
constexpr std::size_t kShapePoints = 7;

double density(double k, double q, double d) { return 4.0 * k * q * std::exp(-q * d) / (kPi * d * d); }

// The CDF of n on [lo, hi] at kTableSteps + 1 points (trapezoids on a
// geometric grid, fine where n is steep), normalised; diameters at the points.
struct DiameterTable {
    std::vector<double> diameter;
    std::vector<double> cdf;
    double total = 0.0;  // rocks per m^2 in [lo, hi]
};

DiameterTable tabulate(double k, double lo, double hi) {
    DiameterTable t;
    const double q = golombekRappQ(k);
    const double ratio = std::pow(hi / lo, 1.0 / static_cast<double>(kTableSteps));
    double d = lo;
    double sum = 0.0;
    t.diameter.push_back(d);
    t.cdf.push_back(0.0);
    for (std::size_t i = 0; i < kTableSteps; ++i) {
        const double next = i + 1 == kTableSteps ? hi : d * ratio;
        sum += 0.5 * (density(k, q, d) + density(k, q, next)) * (next - d);
        t.diameter.push_back(next);
        t.cdf.push_back(sum);
        d = next;
    }
    t.total = sum;
    for (double& c : t.cdf) {
        c /= sum;
    }
    return t;
}

double drawDiameter(const DiameterTable& t, SimRng& rng) {
    const double u = rng.uniform();
    const auto it = std::upper_bound(t.cdf.begin(), t.cdf.end(), u);
    const std::size_t i = static_cast<std::size_t>(std::min<std::ptrdiff_t>(
        std::max<std::ptrdiff_t>(it - t.cdf.begin(), 1), static_cast<std::ptrdiff_t>(t.cdf.size() - 1)));
    const double span = t.cdf[i] - t.cdf[i - 1];
    const double f = span > 0.0 ? (u - t.cdf[i - 1]) / span : 0.0;
    return t.diameter[i - 1] + f * (t.diameter[i] - t.diameter[i - 1]);
}

// Poisson(mean): inversion below 30, else the normal approximation rounded.
std::size_t drawCount(double mean, SimRng& rng) {
    if (mean < 30.0) {
        double p = std::exp(-mean);
        double cumulative = p;
        const double u = rng.uniform();
        std::size_t n = 0;
        while (u > cumulative && n < 1000) {
            ++n;
            p *= mean / static_cast<double>(n);
            cumulative += p;
        }
        return n;
    }
    const double n = std::round(mean + std::sqrt(mean) * rng.gaussian());
    return n > 0.0 ? static_cast<std::size_t>(n) : 0U;
}

double cross(const RockVertex& o, const RockVertex& a, const RockVertex& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Andrew's monotone chain: the hull counter-clockwise, no collinear points.
std::vector<RockVertex> convexHull(std::vector<RockVertex> p) {
    std::sort(p.begin(), p.end(), [](const RockVertex& a, const RockVertex& b) {
        return a.x < b.x || (a.x == b.x && a.y < b.y);
    });
    std::vector<RockVertex> hull(2 * p.size());
    std::size_t n = 0;
    for (const RockVertex& v : p) {
        while (n >= 2 && cross(hull[n - 2], hull[n - 1], v) <= 0.0) {
            --n;
        }
        hull[n++] = v;
    }
    for (std::size_t i = p.size() - 1, lower = n + 1; i-- > 0;) {
        while (n >= lower && cross(hull[n - 2], hull[n - 1], p[i]) <= 0.0) {
            --n;
        }
        hull[n++] = p[i];
    }
    hull.resize(n - 1);
    return hull;
}

// kShapePoints round a circle of the diameter, each angle and radius jittered.
std::vector<RockVertex> rockShape(double cx, double cy, double diameter, SimRng& rng) {
    std::vector<RockVertex> points;
    const double turn = rng.uniform() * 2.0 * kPi;
    for (std::size_t i = 0; i < kShapePoints; ++i) {
        const double a = turn + 2.0 * kPi * (static_cast<double>(i) + 0.3 * (rng.uniform() - 0.5)) /
                                    static_cast<double>(kShapePoints);
        const double r = 0.5 * diameter * (0.85 + 0.15 * rng.uniform());
        // Rounded to the site map's f32, so the hull is convex in the image too.
        points.push_back({static_cast<double>(static_cast<float>(cx + r * std::cos(a))),
                          static_cast<double>(static_cast<float>(cy + r * std::sin(a)))});
    }
    return convexHull(points);
}

}  // namespace

double golombekRappQ(double k) { return 1.79 + 0.152 / k; }

double rockAreaFraction(double k, double diameterM) { return k * std::exp(-golombekRappQ(k) * diameterM); }

double rocksPerSquareMetre(double k, double fromM, double toM) {
    if (!(k > 0.0 && k < 1.0 && fromM > 0.0 && toM > fromM)) {
        return 0.0;
    }
    return tabulate(k, fromM, toM).total;
}

std::vector<FieldRock> generateRockField(const RockFieldParams& p) {
    std::vector<FieldRock> rocks;
    const double w = p.xMax - p.xMin;
    const double h = p.yMax - p.yMin;
    if (!(p.k > 0.0 && p.k < 1.0 && w > 0.0 && h > 0.0 && p.minDiameterM > 0.0 && p.maxDiameterM > p.minDiameterM)) {
        return rocks;
    }
    const DiameterTable table = tabulate(p.k, p.minDiameterM, p.maxDiameterM);
    SimRng rng(p.seed, RngStream::kRockField);
    const std::size_t count = drawCount(table.total * w * h, rng);
    rocks.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        FieldRock r;
        r.diameterM = drawDiameter(table, rng);
        // The whole rock on the site: its centre a radius in from every edge.
        const double margin = 0.5 * r.diameterM + 0.01;  // + a float rounding of the vertices
        r.x = p.xMin + margin + rng.uniform() * std::max(0.0, w - 2.0 * margin);
        r.y = p.yMin + margin + rng.uniform() * std::max(0.0, h - 2.0 * margin);
        r.known = r.diameterM >= p.orbitalResolutionM;
        r.vertices = rockShape(r.x, r.y, r.diameterM, rng);
        rocks.push_back(std::move(r));
    }
    return rocks;
}

}  // namespace rse::sim

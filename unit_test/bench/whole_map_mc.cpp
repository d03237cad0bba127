#include "unit_test/bench/whole_map_mc.hpp"

#include <cmath>
#include <random>

#include "fsw/geometry/geometry2d.hpp"

namespace rse::test {

namespace {

constexpr std::size_t kNearCapacity = 256;

bool segmentHitsMap(const site_map::SiteMap& map, geometry::Point2 a, geometry::Point2 b, double radiusM,
                    site_map::SiteQuery* query, bool* crowded) {
    std::uint16_t near[kNearCapacity];
    site_map::QueryStats stats;
    const std::size_t found = map.rocksNearSegment(a, b, radiusM, query, near, kNearCapacity, &stats);
    if (stats.overflow || stats.refused) {
        *crowded = true;
        return true;  // not measured: counted against the plan
    }
    const double r2 = radiusM * radiusM;
    for (std::size_t k = 0; k < found; ++k) {
        const site_map::Rock& rock = map.rock(near[k]);
        geometry::Point2 v[site_map::kMaxRockVertices];
        for (std::size_t i = 0; i < rock.count; ++i) {
            v[i] = geometry::Point2{rock.x[i], rock.y[i]};
        }
        if (geometry::segmentConvexPolygonDistanceSquared(a, b, v, rock.count) < r2) {
            return true;
        }
    }
    return false;
}

}  // namespace

WholeMapMcResult sampleAgainstWholeMap(const site_map::SiteMap& map, const deliberative::CcProblem& problem,
                                       const deliberative::CcPlan& plan, double radiusM, std::size_t samples,
                                       std::uint64_t seed) {
    static site_map::SiteQuery query;
    WholeMapMcResult result;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n01(0.0, 1.0);
    // Sigma_0 = L L^T (2 x 2 Cholesky; a zero or negative pivot taken as 0).
    const double l00 = std::sqrt(std::fmax(problem.startCov[0], 0.0));
    const double l10 = l00 > 0.0 ? problem.startCov[2] / l00 : 0.0;
    const double l11 = std::sqrt(std::fmax(problem.startCov[3] - l10 * l10, 0.0));
    for (std::size_t s = 0; s < samples; ++s) {
        const double z0 = n01(rng), z1 = n01(rng);
        double ex = l00 * z0;
        double ey = l10 * z0 + l11 * z1;
        geometry::Point2 prev{plan.meanX[0] + ex, plan.meanY[0] + ey};
        bool hit = false;
        for (std::size_t t = 0; t < plan.steps && !hit; ++t) {
            ex += problem.processSigmaM * n01(rng);
            ey += problem.processSigmaM * n01(rng);
            const geometry::Point2 next{plan.meanX[t + 1] + ex, plan.meanY[t + 1] + ey};
            hit = segmentHitsMap(map, prev, next, radiusM, &query, &result.crowded);
            prev = next;
        }
        result.collisions += hit ? 1 : 0;
    }
    result.samples = samples;
    return result;
}

}  // namespace rse::test

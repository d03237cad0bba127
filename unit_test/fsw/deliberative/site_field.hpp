// Site-mode test fixtures shared by the deliberative tests: a generated
// Golombek-Rapp field loaded as the site map, and the check that every rock of
// the whole map within a plan's far reach is among its candidates (a scan of
// every rock, not through the map's index).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "fsw/deliberative/deliberative_task.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/site_map/site_map.hpp"
#include "ground/site_map_encoder.hpp"
#include "sim_stub/scenario/rock_field.hpp"

#include "CppUTest/TestHarness.h"

namespace rse::test {

// Golombek-Rapp rocks of 1 m and more on x 0 .. w, y 0 .. h, none within 5 m
// of the given points, loaded into *map.
inline void loadSiteField(site_map::SiteMap* map, double k, double w, double h, std::uint64_t seed,
                          const std::vector<geometry::Point2>& clearOf) {
    sim::RockFieldParams p;
    p.k = k;
    p.xMax = w;
    p.yMax = h;
    p.minDiameterM = 1.0;
    p.seed = seed;
    ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, static_cast<float>(w), static_cast<float>(h)};
    for (const sim::FieldRock& r : sim::generateRockField(p)) {
        bool near = false;
        for (const geometry::Point2& q : clearOf) {
            near = near || std::hypot(r.x - q.x, r.y - q.y) < 5.0 + r.diameterM;
        }
        bool inside = true;
        std::vector<ground::MapVertex> v;
        for (const sim::RockVertex& q : r.vertices) {
            inside = inside && q.x > 0.0 && q.x < w && q.y > 0.0 && q.y < h;
            v.push_back({static_cast<float>(q.x), static_cast<float>(q.y)});
        }
        if (!near && inside) {
            spec.rocks.push_back(v);
        }
    }
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(spec);
    site_map::SiteMapCheck check;
    CHECK(map->load(image.data(), image.size(), &check) == core::Status::kOk);
}

inline double rockDistance(geometry::Point2 a, geometry::Point2 b, const site_map::Rock& rock) {
    geometry::Point2 v[8];
    for (std::size_t i = 0; i < rock.count; ++i) {
        v[i] = geometry::Point2{rock.x[i], rock.y[i]};
    }
    return std::sqrt(geometry::segmentConvexPolygonDistanceSquared(a, b, v, rock.count));
}

// Every rock of the map within the far reach of the plan's means is a candidate.
inline void checkEveryNearRockIsACandidate(const deliberative::DeliberativeTask& task, const site_map::SiteMap& map) {
    const deliberative::CcPlan& plan = task.plan();
    const deliberative::PlanMaker& maker = task.planMaker();
    const double reach = maker.farRocks().reachM;
    CHECK(reach > 0.0);
    const deliberative::MapObstacles& c = maker.candidates();
    for (std::size_t r = 0; r < map.rockCount(); ++r) {
        double d = INFINITY;
        for (std::size_t t = 0; t < plan.steps; ++t) {
            d = std::fmin(d, rockDistance({plan.meanX[t], plan.meanY[t]}, {plan.meanX[t + 1], plan.meanY[t + 1]},
                                          map.rock(r)));
        }
        if (d >= reach) {
            continue;
        }
        bool listed = false;
        for (std::size_t i = 0; i < c.polygons && !listed; ++i) {
            listed = c.mapId[i] == r;
        }
        CHECK_TEXT(listed, "a rock within the far reach of the plan is not among its candidates");
    }
}

}  // namespace rse::test

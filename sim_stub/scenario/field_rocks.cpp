#include "sim_stub/scenario/field_rocks.hpp"

#include <cmath>
#include <string>

#include "fsw/site_map/site_map_image.hpp"
#include "sim_stub/scenario/scenario.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

namespace rse::sim {

void addFieldRocks(const FieldSpec& field, Scenario* s) {
    if (!field.present) {
        return;
    }
    RockFieldParams p = field.rocks;
    p.xMin = s->map.xMin;
    p.yMin = s->map.yMin;
    p.xMax = s->map.xMax;
    p.yMax = s->map.yMax;
    const std::vector<FieldRock> rocks = generateRockField(p);
    const Vec2 start{s->start.x, s->start.y};
    const bool hasGoal = s->mission.present && s->mission.hasGoal;
    const Vec2 goal{s->mission.goalX, s->mission.goalY};
    std::size_t known = 0;
    std::uint32_t id = kFirstFieldRockId;
    for (const FieldRock& r : rocks) {
        Obstacle o;
        o.known = r.known;
        o.shape.n = r.vertices.size() < kMaxPolygonVertices ? r.vertices.size() : kMaxPolygonVertices;
        bool fits = true;
        for (std::size_t k = 0; k < o.shape.n; ++k) {
            o.shape.v[k] = Vec2{r.vertices[k].x, r.vertices[k].y};
            fits = fits && s->map.contains(o.shape.v[k]);
        }
        const double reach = field.clearM + s->rover.radiusM;
        fits = fits && !circleIntersectsPolygon(start, reach, o.shape) &&
               !(hasGoal && circleIntersectsPolygon(goal, reach, o.shape));
        if (!fits) {
            continue;
        }
        if (id > 0xFFFF) {
            throw ScenarioError(s->source + ": field: more rocks than obstacle ids (" +
                                std::to_string(0xFFFF - kFirstFieldRockId + 1) + ")");
        }
        o.id = static_cast<std::uint16_t>(id++);
        known += o.known ? 1U : 0U;
        s->obstacles.push_back(o);
    }
    if (known > site_map::kMaxSiteRocks) {
        throw ScenarioError(s->source + ": field: " + std::to_string(known) +
                            " known rocks; the site map holds at most " + std::to_string(site_map::kMaxSiteRocks) +
                            " (raise orbital_resolution_m or lower k)");
    }
}

FieldCounts fieldCounts(const Scenario& scenario) {
    FieldCounts c;
    for (const Obstacle& o : scenario.obstacles) {
        if (o.id >= kFirstFieldRockId) {
            ++c.rocks;
            c.known += o.known ? 1U : 0U;
        }
    }
    return c;
}

}  // namespace rse::sim

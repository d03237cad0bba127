#include "sim_stub/scenario/coarse_map_source.hpp"

#include <cstdio>
#include <vector>

namespace rse::sim {

namespace {

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4f", v);
    return text;
}

// One array field: slot i's values at 8i..8i+7, a comment naming the slot.
std::string vertexArray(const char* field, const std::vector<const Obstacle*>& known, bool xs) {
    std::string s = std::string(field) + " = [\n";
    for (std::size_t slot = 0; slot < kCoarseMapSlots; ++slot) {
        s += "    ";
        const Obstacle* o = slot < known.size() ? known[slot] : nullptr;
        for (std::size_t k = 0; k < kCoarseMapSlotVertices; ++k) {
            const bool used = o != nullptr && k < o->shape.n;
            s += used ? number(xs ? o->shape.v[k].x : o->shape.v[k].y) : std::string("0");
            s += ", ";
        }
        s += o != nullptr ? "# " + std::to_string(slot) + ": scenario obstacle " + std::to_string(o->id) + "\n"
                          : "# " + std::to_string(slot) + ": unused\n";
    }
    return s + "]\n";
}

}  // namespace

std::string coarseMapSource(const Scenario& scenario) {
    std::vector<const Obstacle*> known;
    // Site mode: the rocks go with the site map; COARSE_MAP keeps the bounds.
    const bool boundsOnly = scenario.usesSiteMap();
    for (const Obstacle& o : scenario.obstacles) {
        if (!o.known || boundsOnly) {
            continue;
        }
        if (o.shape.n > kCoarseMapSlotVertices) {
            throw CoarseMapError("scenario " + scenario.name + ": known obstacle " + std::to_string(o.id) + " has " +
                                 std::to_string(o.shape.n) + " vertices; COARSE_MAP holds at most " +
                                 std::to_string(kCoarseMapSlotVertices));
        }
        known.push_back(&o);
    }
    if (known.size() > kCoarseMapSlots) {
        throw CoarseMapError("scenario " + scenario.name + ": " + std::to_string(known.size()) +
                             " known obstacles; COARSE_MAP holds at most " + std::to_string(kCoarseMapSlots));
    }
    std::string s = "# COARSE_MAP of scenario " + scenario.name + " (" + scenario.source +
                    (boundsOnly ? "): the site bounds; its known rocks go with the site map (sim_stub/scenario/coarse_map_source.hpp)\n"
                                : "): the site bounds and its known obstacles (sim_stub/scenario/coarse_map_source.hpp)\n");
    s += "table = \"COARSE_MAP\"\nversion = 1\n\n[values]\n";
    s += "x_min_m = " + number(scenario.map.xMin) + "\n";
    s += "x_max_m = " + number(scenario.map.xMax) + "\n";
    s += "y_min_m = " + number(scenario.map.yMin) + "\n";
    s += "y_max_m = " + number(scenario.map.yMax) + "\n";
    s += "obstacle_count = " + std::to_string(known.size()) + "\n";
    s += "vertex_count = [";
    for (std::size_t slot = 0; slot < kCoarseMapSlots; ++slot) {
        s += std::to_string(slot < known.size() ? known[slot]->shape.n : 0);
        s += slot + 1 < kCoarseMapSlots ? ", " : "]\n";
    }
    s += vertexArray("vertex_x_m", known, true);
    s += vertexArray("vertex_y_m", known, false);
    return s;
}

ground::SiteMapSpec siteMapSpec(const Scenario& scenario, MapRocks which) {
    ground::SiteMapSpec spec;
    spec.site = {static_cast<float>(scenario.map.xMin), static_cast<float>(scenario.map.yMin),
                 static_cast<float>(scenario.map.xMax), static_cast<float>(scenario.map.yMax)};
    for (const Obstacle& o : scenario.obstacles) {
        if (!o.known && which == MapRocks::kKnown) {
            continue;
        }
        std::vector<ground::MapVertex> v;
        for (std::size_t k = 0; k < o.shape.n; ++k) {
            v.push_back({static_cast<float>(o.shape.v[k].x), static_cast<float>(o.shape.v[k].y)});
        }
        spec.rocks.push_back(v);
    }
    return spec;
}

}  // namespace rse::sim

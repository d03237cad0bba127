// A leg end too near something (leg_end_clearance.hpp): within the rover's
// clearance + kLegEndMarginM of a coarse-map polygon or of a seen hazard's disc.
#include "fsw/deliberative/leg_end_clearance.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::kLegEndMarginM;
using deliberative::LegEndClearance;

namespace {

// A 20 m x 20 m site with one 2 m square obstacle, x in [10, 12], y in [-1, 1].
tables::CoarseMapTable squareMap() {
    tables::CoarseMapTable map{};
    map.x_min_m = -10.0F;
    map.x_max_m = 30.0F;
    map.y_min_m = -10.0F;
    map.y_max_m = 10.0F;
    map.obstacle_count = 1;
    map.vertex_count[0] = 4;
    const float xs[4] = {10.0F, 12.0F, 12.0F, 10.0F};
    const float ys[4] = {-1.0F, -1.0F, 1.0F, 1.0F};
    for (std::size_t v = 0; v < 4; ++v) {
        map.vertex_x_m[v] = xs[v];
        map.vertex_y_m[v] = ys[v];
    }
    return map;
}

}  // namespace

TEST_GROUP(LegEndClearance){};

TEST(LegEndClearance, AnEndWithinTheClearanceAndMarginOfAPolygonIsTooClose) {
    const tables::CoarseMapTable map = squareMap();
    const msg::KnownHazardsMsg none{};
    const double rover = 0.6;
    const LegEndClearance clear(map, rover, none);
    const double reach = rover + kLegEndMarginM;
    CHECK_TRUE(clear.tooClose(10.0 - reach + 0.01, 0.0));
    CHECK_FALSE(clear.tooClose(10.0 - reach - 0.01, 0.0));
    CHECK_TRUE(clear.tooClose(11.0, 0.0));  // inside
    CHECK_FALSE(clear.tooClose(0.0, 0.0));
}

TEST(LegEndClearance, AnEndWithinTheClearanceAndMarginOfASeenHazardsDiscIsTooClose) {
    tables::CoarseMapTable empty{};
    empty.x_min_m = -10.0F;
    empty.x_max_m = 30.0F;
    empty.y_min_m = -10.0F;
    empty.y_max_m = 10.0F;
    msg::KnownHazardsMsg hazards{};
    hazards.count = 1;
    hazards.hazards[0].xM = 5.0F;
    hazards.hazards[0].yM = 2.0F;
    hazards.hazards[0].radiusM = 0.5F;
    hazards.hazards[0].obstacleId = 1;
    const double rover = 0.6;
    const LegEndClearance clear(empty, rover, hazards);
    const double reach = 0.5 + rover + kLegEndMarginM;
    CHECK_TRUE(clear.tooClose(5.0 + reach - 0.01, 2.0));
    CHECK_FALSE(clear.tooClose(5.0 + reach + 0.01, 2.0));
    CHECK_FALSE(clear.tooClose(0.0, 0.0));
    // The hazards are read where they are: a sighting after construction counts.
    hazards.hazards[0].xM = 0.0F;
    hazards.hazards[0].yM = 0.0F;
    CHECK_TRUE(clear.tooClose(0.0, 0.0));
    // Only the hazards in use.
    hazards.count = 0;
    CHECK_FALSE(clear.tooClose(0.0, 0.0));
}

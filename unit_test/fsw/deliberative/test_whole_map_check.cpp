// A plan's risk against the whole map (whole_map_check.hpp): every candidate
// bounded one unit each within the unit bound, the left-out ones' total, and
// forcing the worst into the problem while there is room.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/map_problem.hpp"
#include "fsw/deliberative/plan_risk.hpp"
#include "fsw/deliberative/whole_map_check.hpp"
#include "fsw/tables/table_types.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::tables::CoarseMapTable;

namespace {

// A 20 m x 20 m site round the origin with a 1 m square rock centred at each (x, y).
CoarseMapTable squares(std::initializer_list<std::initializer_list<float>> centres) {
    CoarseMapTable map{};
    map.x_min_m = -10.0F;
    map.x_max_m = 10.0F;
    map.y_min_m = -10.0F;
    map.y_max_m = 10.0F;
    for (const auto& c : centres) {
        const std::size_t slot = map.obstacle_count;
        const float x = *c.begin();
        const float y = *(c.begin() + 1);
        const float xs[4] = {x - 0.5F, x + 0.5F, x + 0.5F, x - 0.5F};
        const float ys[4] = {y - 0.5F, y - 0.5F, y + 0.5F, y + 0.5F};
        for (std::size_t v = 0; v < 4; ++v) {
            map.vertex_x_m[slot * 8 + v] = xs[v];
            map.vertex_y_m[slot * 8 + v] = ys[v];
        }
        map.vertex_count[slot] = 4;
        map.obstacle_count = static_cast<std::uint8_t>(slot + 1);
    }
    return map;
}

struct Rig {
    rse::tables::PlannerTable planner{};
    rse::tables::RoverGeometryTable geometry{};
    CcProblem problem{};
    MapObstacles obstacles{};
    CcPlan plan{};
    Rig() {
        planner.horizon_steps = 16;
        planner.process_noise_sigma_m = 0.05F;
        planner.risk_allocation = 1;
        geometry.footprint_radius_m = 0.5F;
    }
    void build(const CoarseMapTable& map) {
        PlanRequest r;
        r.startX = -8.0;
        r.goalX = 8.0;
        r.startCov[0] = r.startCov[3] = 0.0025;
        r.riskBound = 1e-3;
        MapProblemReport report;
        CHECK(buildMapProblem(map, planner, geometry, r, &problem, &report, &obstacles) == rse::core::Status::kOk);
        // The straight line from start to goal, as a plan's means.
        plan.status = CcStatus::kFeasible;
        plan.steps = problem.steps;
        for (std::size_t t = 0; t <= plan.steps; ++t) {
            const double f = static_cast<double>(t) / static_cast<double>(plan.steps);
            plan.meanX[t] = -8.0 + 16.0 * f;
            plan.meanY[t] = 0.0;
        }
    }
};

std::size_t indexOfCentre(const MapObstacles& o, double x, double y) {
    // A grown 1 m square's +x face offset is x + 0.5 + 0.5.
    for (std::size_t i = 0; i < o.count; ++i) {
        double right = -INFINITY;
        double top = -INFINITY;
        for (std::size_t j = 0; j < o.grown[i].faceCount; ++j) {
            right = o.grown[i].normalX[j] == 1.0 ? o.grown[i].offset[j] : right;
            top = o.grown[i].normalY[j] == 1.0 ? o.grown[i].offset[j] : top;
        }
        if (std::fabs(right - (x + 1.0)) < 1e-6 && std::fabs(top - (y + 1.0)) < 1e-6) {
            return i;
        }
    }
    return o.count;
}

}  // namespace

TEST_GROUP(WholeMapCheck){};

// Nine rocks far off the line fill the problem's eight slots; the tenth and
// the eleventh, farther still from the line, are left out: one of them sits
// on the path the (pretend) plan takes, the other far from it. The one on the
// path carries nearly certain collision, the other nothing; the total is
// theirs; each unit is within its bound.
TEST(WholeMapCheck, TheLeftOutObstaclesAreBoundedOneUnitEachAndSummed) {
    Rig rig;
    rig.build(squares({{-6, 3}, {-4, -3}, {-2, 3}, {0, -3}, {2, 3}, {4, -3}, {6, 3}, {6, -3}, {0, 0}, {-9, 9}}));
    // (0, 0) lies on the line: rank 0, in the problem. Make room for a test of
    // a left-out rock on the path: force the far ones in, so (0, 0) is left out.
    for (std::size_t i = 0; i < rig.obstacles.count; ++i) {
        rig.obstacles.forced[i] = i != 8;
    }
    MapProblemReport report;
    selectObstacles(&rig.obstacles, &rig.problem, &report);
    LONGS_EQUAL(8, rig.problem.obstacleCount);
    LONGS_EQUAL(2, rig.obstacles.leftOut());
    const std::size_t onPath = indexOfCentre(rig.obstacles, 0, 0);
    const std::size_t corner = indexOfCentre(rig.obstacles, -9, 9);
    CHECK_FALSE(rig.obstacles.inProblem[onPath]);
    CHECK_FALSE(rig.obstacles.inProblem[corner]);

    WholeMapCheck check;
    check.start(rig.problem, rig.plan, rig.obstacles);
    std::size_t units = 0;
    bool done = false;
    while (!done && units < 100) {
        std::uint64_t work = 0;
        done = check.unit(&work);
        CHECK(work <= WholeMapCheck::kMaxUnitWork);
        ++units;
    }
    LONGS_EQUAL(rig.obstacles.count, units);  // one unit a candidate
    LONGS_EQUAL(2, check.leftOutCount());
    CHECK(check.risk(onPath) > 0.5);
    CHECK(check.risk(corner) < 1e-12);
    DOUBLES_EQUAL(check.risk(onPath) + check.risk(corner), check.leftOutRisk(), 1e-12);
    // The same as the certified bound of a problem holding that rock alone.
    CcProblem alone = rig.problem;
    alone.obstacleCount = 1;
    alone.obstacles[0] = rig.obstacles.grown[onPath];
    DOUBLES_EQUAL(planRiskBound(alone, rig.plan.meanX, rig.plan.meanY, nullptr, nullptr), check.risk(onPath), 1e-12);
}

// Forcing: the left-out ones first, worst first, while the forced ones fit
// in the problem's slots; 0 when no left-out one could be forced.
TEST(WholeMapCheck, ForcingTakesTheWorstFirstWhileThereIsRoom) {
    Rig rig;
    rig.build(squares({{-6, 3}, {-4, -3}, {-2, 3}, {0, -3}, {2, 3}, {4, -3}, {6, 3}, {6, -3}, {0, 0}, {-9, 9}}));
    for (std::size_t i = 0; i < rig.obstacles.count; ++i) {
        rig.obstacles.forced[i] = i != 8;
    }
    MapProblemReport report;
    selectObstacles(&rig.obstacles, &rig.problem, &report);
    WholeMapCheck check;
    check.start(rig.problem, rig.plan, rig.obstacles);
    std::uint64_t work = 0;
    while (!check.unit(&work)) {
    }
    const std::size_t onPath = indexOfCentre(rig.obstacles, 0, 0);
    // Nine forced already (more than the slots): no room.
    LONGS_EQUAL(0, check.force(&rig.obstacles, 1e-9));
    // None forced and a floor nearly 0: the left-out rock on the path first
    // (the corner's risk is 0: not above the floor), then the held ones fill
    // the slots; one left out newly forced.
    for (std::size_t i = 0; i < rig.obstacles.count; ++i) {
        rig.obstacles.forced[i] = false;
    }
    LONGS_EQUAL(1, check.force(&rig.obstacles, 1e-300));
    CHECK_TRUE(rig.obstacles.forced[onPath]);
    std::size_t forced = 0;
    for (std::size_t i = 0; i < rig.obstacles.count; ++i) {
        forced += rig.obstacles.forced[i] ? 1U : 0U;
    }
    LONGS_EQUAL(kMaxPlanObstacles, forced);
    // The held ones forced first (every slot): no left-out one fits, so the
    // next problem would be the same: 0.
    for (std::size_t i = 0; i < rig.obstacles.count; ++i) {
        rig.obstacles.forced[i] = rig.obstacles.inProblem[i];
    }
    LONGS_EQUAL(0, check.force(&rig.obstacles, 1e-300));
    for (std::size_t i = 0; i < rig.obstacles.count; ++i) {
        rig.obstacles.forced[i] = false;
    }
    LONGS_EQUAL(1, check.force(&rig.obstacles, 0.5));
    CHECK_TRUE(rig.obstacles.forced[onPath]);
    // Nothing above a floor of 1: nothing forced.
    LONGS_EQUAL(0, check.force(&rig.obstacles, 1.0));
}

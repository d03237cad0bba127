// From the coarse map to the planning problem (map_problem.hpp): polygons of
// either winding grown by exactly the footprint radius, the site shrunk by
// it, the plant and allocation from the PLANNER table, the covariance copied
// and symmetrised, every refusal named, the start inside an obstacle
// flagged, the nearest kMaxPlanObstacles polygons kept; and on the default
// tables (the demo mission's map, start and goal) a problem that plans within
// its risk bound, with Delta = 1e-6 keeping more clearance than 1e-2.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <random>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/gaussian.hpp"
#include "fsw/deliberative/map_problem.hpp"
#include "fsw/geometry/coarse_map.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "ground/plan_svg.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using rse::deliberative::buildMapProblem;
using rse::deliberative::CcPlan;
using rse::deliberative::CcPlanner;
using rse::deliberative::CcPlannerParams;
using rse::deliberative::CcProblem;
using rse::deliberative::CcStatus;
using rse::deliberative::kMaxPlanObstacles;
using rse::deliberative::MapProblemError;
using rse::deliberative::MapProblemReport;
using rse::deliberative::PlanObstacle;
using rse::deliberative::PlanRequest;
using rse::deliberative::RiskAllocation;
using rse::tables::CoarseMapTable;
using rse::tables::PlannerTable;
using rse::tables::RoverGeometryTable;

namespace {

// ~440 KB: static storage, as in flight.
CcPlanner planner;
CcPlan planA;
CcPlan planB;

constexpr double kRadius = 0.5;  // exact in float, so the expected values are exact

int errorOf(MapProblemError e) { return static_cast<int>(e); }

// A 20 m x 20 m site around the origin, no obstacle yet.
CoarseMapTable emptyMap() {
    CoarseMapTable map{};
    map.x_min_m = -10.0F;
    map.x_max_m = 10.0F;
    map.y_min_m = -10.0F;
    map.y_max_m = 10.0F;
    return map;
}

// Appends a polygon (vertices in the order given) in the next slot.
void addPolygon(CoarseMapTable* map, std::initializer_list<std::initializer_list<float>> vertices) {
    const std::size_t slot = map->obstacle_count;
    std::size_t v = 0;
    for (const auto& xy : vertices) {
        map->vertex_x_m[slot * 8 + v] = *xy.begin();
        map->vertex_y_m[slot * 8 + v] = *(xy.begin() + 1);
        ++v;
    }
    map->vertex_count[slot] = static_cast<std::uint8_t>(v);
    map->obstacle_count = static_cast<std::uint8_t>(slot + 1);
}

PlannerTable plannerTable(std::uint8_t allocation) {
    PlannerTable t{};
    t.default_risk_bound = 1e-3;
    t.horizon_steps = 12;
    t.node_budget = 20000;
    t.time_budget_ms = 20;
    t.risk_allocation = allocation;
    t.process_noise_sigma_m = 0.125F;
    return t;
}

RoverGeometryTable geometry() {
    RoverGeometryTable g{};
    g.footprint_radius_m = static_cast<float>(kRadius);
    return g;
}

PlanRequest request(double sx, double sy, double gx, double gy, double risk) {
    PlanRequest r;
    r.startX = sx;
    r.startY = sy;
    r.goalX = gx;
    r.goalY = gy;
    r.startCov[0] = 0.04;
    r.startCov[3] = 0.04;
    r.riskBound = risk;
    return r;
}

// The face of o with outward normal (nx, ny), exactly; -1 when none.
int faceWithNormal(const PlanObstacle& o, double nx, double ny) {
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        if (o.normalX[j] == nx && o.normalY[j] == ny) {
            return static_cast<int>(j);
        }
    }
    return -1;
}

// Builds and expects a refusal naming `why`.
void expectRefused(const CoarseMapTable& map, const PlannerTable& table, const PlanRequest& r, MapProblemError why) {
    CcProblem p;
    p.steps = 77;  // left alone on refusal
    MapProblemReport report;
    CHECK(buildMapProblem(map, table, geometry(), r, &p, &report) == Status::kInvalidArgument);
    CHECK_EQUAL(errorOf(why), errorOf(report.error));
    CHECK_EQUAL(77, p.steps);
    STRCMP_EQUAL(rse::deliberative::toString(why), rse::deliberative::toString(report.error));
}

}  // namespace

TEST_GROUP(MapProblem){};

// The 2 m square [1, 3] x [1, 3] grown by 0.5 m: [0.5, 3.5]^2 (outward unit
// normals +-x and +-y, offsets 3.5 on the +x and +y faces and -0.5 on the -x
// and -y faces: a . x = b, -x = -0.5) with its four corners bevelled: a face
// on the diagonal normal, tangent to the 0.5 m disc round the rock's corner,
// so the grown square's corner (3.5, 3.5), 0.71 m from the rock's, is cut off
// and no point of the polygon lies farther than the old corner. The same for
// either winding; the face order follows the vertices, each bevel after the
// face before its corner.
TEST(MapProblem, SquareOfEitherWindingGrowsByTheFootprintRadius) {
    for (int clockwise = 0; clockwise < 2; ++clockwise) {
        CoarseMapTable map = emptyMap();
        if (clockwise == 0) {
            addPolygon(&map, {{1, 1}, {3, 1}, {3, 3}, {1, 3}});
        } else {
            addPolygon(&map, {{1, 1}, {1, 3}, {3, 3}, {3, 1}});
        }
        CcProblem p;
        MapProblemReport report;
        CHECK(buildMapProblem(map, plannerTable(0), geometry(), request(-5, 0, 5, 0, 1e-3), &p, &report) ==
              Status::kOk);
        CHECK_EQUAL(errorOf(MapProblemError::kNone), errorOf(report.error));
        CHECK_EQUAL(1, p.obstacleCount);
        const PlanObstacle& o = p.obstacles[0];
        CHECK_EQUAL(0, o.id);
        CHECK_EQUAL(8, o.faceCount);
        const struct {
            double nx, ny, b;
        } expected[4] = {{1.0, 0.0, 3.5}, {0.0, 1.0, 3.5}, {-1.0, 0.0, -0.5}, {0.0, -1.0, -0.5}};
        for (const auto& e : expected) {
            const int j = faceWithNormal(o, e.nx, e.ny);
            CHECK_TEXT(j >= 0, "a face with this normal");
            DOUBLES_EQUAL(e.b, o.offset[j], 1e-12);
        }
        // Order: the edge from vertex 0 to vertex 1 is face 0, its corner's bevel face 1.
        const int first = clockwise == 0 ? faceWithNormal(o, 0.0, -1.0) : faceWithNormal(o, -1.0, 0.0);
        CHECK_EQUAL(0, first);
        const double h = std::sqrt(0.5);
        DOUBLES_EQUAL(clockwise == 0 ? h : -h, o.normalX[1], 1e-15);
        DOUBLES_EQUAL(clockwise == 0 ? -h : h, o.normalY[1], 1e-15);
        // Bevels: normal along the diagonal, offset = a . corner + r.
        for (const double cx : {1.0, 3.0}) {
            for (const double cy : {1.0, 3.0}) {
                const double nx = cx > 2.0 ? h : -h;
                const double ny = cy > 2.0 ? h : -h;
                int bevel = -1;
                for (std::size_t j = 0; j < o.faceCount; ++j) {
                    if (std::fabs(o.normalX[j] - nx) < 1e-15 && std::fabs(o.normalY[j] - ny) < 1e-15) {
                        bevel = static_cast<int>(j);
                    }
                }
                CHECK_TEXT(bevel >= 0, "a bevel at every corner");
                DOUBLES_EQUAL(nx * cx + ny * cy + kRadius, o.offset[bevel], 1e-12);
            }
        }
        // The plain growth's corners (0.5, 0.5) and (3.5, 3.5) are cut off:
        // outside the bevel, though on the two faces beside it; the disc's
        // point on the diagonal, r beyond the rock's corner, is on the bevel.
        for (const double c : {0.5, 3.5}) {
            int onFaces = 0;
            bool outside = false;
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                const double s = o.normalX[j] * c + o.normalY[j] * c - o.offset[j];
                onFaces += std::fabs(s) < 1e-12 ? 1 : 0;
                outside = outside || s > 1e-3;
            }
            CHECK_EQUAL(2, onFaces);
            CHECK_TEXT(outside, "the sharp corner is bevelled off");
        }
        const double d = 3.0 + kRadius * h;
        double worst = -INFINITY;
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            worst = std::fmax(worst, o.normalX[j] * d + o.normalY[j] * d - o.offset[j]);
        }
        DOUBLES_EQUAL(0.0, worst, 1e-12);
    }
}

// A slanted face: the triangle (0, 0), (4, 0), (0, 3) has its hypotenuse's
// normal (3, 4) / 5 and offset 12 / 5 (3x + 4y = 12), grown: 12 / 5 + 0.5.
// Every corner turns by more than 90 degrees: three bevels, six faces, the
// hypotenuse's after the first bevel.
TEST(MapProblem, SlantedFaceGrowsAlongItsNormal) {
    CoarseMapTable map = emptyMap();
    addPolygon(&map, {{0, 0}, {4, 0}, {0, 3}});
    CcProblem p;
    MapProblemReport report;
    CHECK(buildMapProblem(map, plannerTable(0), geometry(), request(-5, -5, 5, 5, 1e-3), &p, &report) == Status::kOk);
    const PlanObstacle& o = p.obstacles[0];
    CHECK_EQUAL(6, o.faceCount);
    DOUBLES_EQUAL(0.6, o.normalX[2], 1e-15);
    DOUBLES_EQUAL(0.8, o.normalY[2], 1e-15);
    DOUBLES_EQUAL(2.4 + kRadius, o.offset[2], 1e-12);
}

TEST(MapProblem, SitePlantCovarianceAndAllocationComeFromTablesAndRequest) {
    CoarseMapTable map = emptyMap();
    map.x_min_m = -4.0F;
    map.x_max_m = 12.0F;
    map.y_min_m = -6.0F;
    map.y_max_m = 2.0F;
    PlanRequest r = request(-1.25, -2.5, 9.0, 1.0, 0.02);
    r.startCov[0] = 0.04;
    r.startCov[1] = 0.01;
    r.startCov[2] = 0.03;  // off by rounding in the estimator: symmetrised to the mean
    r.startCov[3] = 0.09;
    for (std::uint8_t allocation = 0; allocation < 2; ++allocation) {
        CcProblem p;
        MapProblemReport report;
        CHECK(buildMapProblem(map, plannerTable(allocation), geometry(), r, &p, &report) == Status::kOk);
        DOUBLES_EQUAL(-4.0 + kRadius, p.xMin, 0.0);
        DOUBLES_EQUAL(12.0 - kRadius, p.xMax, 0.0);
        DOUBLES_EQUAL(-6.0 + kRadius, p.yMin, 0.0);
        DOUBLES_EQUAL(2.0 - kRadius, p.yMax, 0.0);
        CHECK_EQUAL(12, p.steps);
        DOUBLES_EQUAL(0.125, p.processSigmaM, 0.0);
        DOUBLES_EQUAL(0.02, p.riskBound, 0.0);
        DOUBLES_EQUAL(-1.25, p.startX, 0.0);
        DOUBLES_EQUAL(-2.5, p.startY, 0.0);
        DOUBLES_EQUAL(9.0, p.goalX, 0.0);
        DOUBLES_EQUAL(1.0, p.goalY, 0.0);
        DOUBLES_EQUAL(0.04, p.startCov[0], 0.0);
        DOUBLES_EQUAL(0.02, p.startCov[1], 1e-17);
        DOUBLES_EQUAL(p.startCov[1], p.startCov[2], 0.0);
        DOUBLES_EQUAL(0.09, p.startCov[3], 0.0);
        CHECK(p.allocation == (allocation == 1 ? RiskAllocation::kOptimised : RiskAllocation::kEvenSplit));
        CHECK_EQUAL(0, p.obstacleCount);
        CHECK_EQUAL(0, report.obstaclesOnMap);
        CHECK_EQUAL(0, report.obstaclesDropped);
        CHECK(rse::deliberative::checkProblem(p) == Status::kOk);
    }
    // A failed drive's noise factor scales the table's noise per step.
    r.noiseFactor = 5.0;
    CcProblem p;
    MapProblemReport report;
    CHECK(buildMapProblem(map, plannerTable(1), geometry(), r, &p, &report) == Status::kOk);
    DOUBLES_EQUAL(0.625, p.processSigmaM, 0.0);
}

TEST(MapProblem, BadRequestsAreRefused) {
    CoarseMapTable map = emptyMap();
    addPolygon(&map, {{1, 1}, {3, 1}, {3, 3}, {1, 3}});
    const PlanRequest good = request(-5, 0, 5, 0, 1e-2);
    for (int k = 0; k < 11; ++k) {
        PlanRequest r = good;
        switch (k) {
            case 9: r.noiseFactor = 0.5; break;   // a failed drive never tracks better
            case 10: r.noiseFactor = NAN; break;
            case 0: r.startX = NAN; break;
            case 1: r.goalY = INFINITY; break;
            case 2: r.startCov[2] = NAN; break;
            case 3: r.riskBound = 0.0; break;
            case 4: r.riskBound = 0.5; break;
            case 5: r.riskBound = -1e-3; break;
            case 6: r.riskBound = NAN; break;
            case 7: r.riskBound = INFINITY; break;
            default: r.startCov[0] = -INFINITY; break;
        }
        expectRefused(map, plannerTable(1), r, MapProblemError::kBadRequest);
    }
    // Just inside the open interval is accepted.
    CcProblem p;
    MapProblemReport report;
    PlanRequest r = good;
    r.riskBound = 0.4999;
    CHECK(buildMapProblem(map, plannerTable(1), geometry(), r, &p, &report) == Status::kOk);
}

// On the site but within the footprint radius of its edge: off the site the
// means may use.
TEST(MapProblem, StartOrGoalOffTheShrunkSiteIsRefused) {
    const CoarseMapTable map = emptyMap();
    expectRefused(map, plannerTable(1), request(-9.75, 0, 5, 0, 1e-2), MapProblemError::kStartOffSite);
    expectRefused(map, plannerTable(1), request(0, 12, 5, 0, 1e-2), MapProblemError::kStartOffSite);
    expectRefused(map, plannerTable(1), request(0, 0, 5, 9.8, 1e-2), MapProblemError::kGoalOffSite);
    expectRefused(map, plannerTable(1), request(0, 0, 10.2, 0, 1e-2), MapProblemError::kGoalOffSite);
    CcProblem p;
    MapProblemReport report;  // exactly on the shrunk edge: still on the site
    CHECK(buildMapProblem(map, plannerTable(1), geometry(), request(-9.5, 0, 9.5, 9.5, 1e-2), &p, &report) ==
          Status::kOk);
}

// (2, 0.75) is off the rock [1, 3]^2 but inside it grown ([0.5, 3.5]^2); the
// grown boundary itself (y = 0.5) is not inside.
TEST(MapProblem, GoalInsideAGrownObstacleIsRefusedStartInsideIsFlagged) {
    CoarseMapTable map = emptyMap();
    addPolygon(&map, {{-8, -8}, {-7, -8}, {-7, -7}});
    addPolygon(&map, {{1, 1}, {3, 1}, {3, 3}, {1, 3}});
    expectRefused(map, plannerTable(1), request(-5, 0, 2, 0.75, 1e-2), MapProblemError::kGoalInObstacle);
    CcProblem p;
    MapProblemReport report;
    CHECK(buildMapProblem(map, plannerTable(1), geometry(), request(-5, 0, 2, 0.5, 1e-2), &p, &report) == Status::kOk);
    CHECK_FALSE(report.startInObstacle);
    CHECK(buildMapProblem(map, plannerTable(1), geometry(), request(2, 0.75, -5, 0, 1e-2), &p, &report) ==
          Status::kOk);
    CHECK_TRUE(report.startInObstacle);
    CHECK_EQUAL(2, p.obstacleCount);
    CHECK(planner.solve(p, CcPlannerParams{}, &planA) == CcStatus::kNoPlan);  // as the report warns
}

// Polygons the faces cannot describe: a reflex corner, a straight corner, no
// area, a zero-length edge, a pentagram (every turn the same way, but it winds
// twice: its faces bound only the inner pentagon), too few vertices.
TEST(MapProblem, NonConvexPolygonsAreABadMap) {
    for (int k = 0; k < 6; ++k) {
        CoarseMapTable map = emptyMap();
        addPolygon(&map, {{-8, -8}, {-7, -8}, {-7, -7}});  // a good one first
        switch (k) {
            case 0: addPolygon(&map, {{0, 0}, {4, 0}, {4, 4}, {2, 1}, {0, 4}}); break;
            case 1: addPolygon(&map, {{0, 0}, {2, 0}, {4, 0}, {4, 4}, {0, 4}}); break;
            case 2: addPolygon(&map, {{0, 0}, {2, 2}, {4, 4}}); break;
            case 3: addPolygon(&map, {{0, 0}, {4, 0}, {4, 0}, {0, 4}}); break;
            case 4: {
                // Pentagram: the vertices of a regular pentagon taken two at a time.
                CoarseMapTable& m = map;
                m.vertex_count[1] = 5;
                for (std::size_t v = 0; v < 5; ++v) {
                    const double a = M_PI / 2.0 + 2.0 * (2.0 * M_PI / 5.0) * static_cast<double>(v);
                    m.vertex_x_m[8 + v] = static_cast<float>(3.0 * std::cos(a));
                    m.vertex_y_m[8 + v] = static_cast<float>(3.0 * std::sin(a));
                }
                m.obstacle_count = 2;
                break;
            }
            default: addPolygon(&map, {{0, 0}, {4, 0}}); break;
        }
        expectRefused(map, plannerTable(1), request(-5, -5, 5, -5, 1e-2), MapProblemError::kBadMap);
    }
}

TEST(MapProblem, PlannerTableOutOfRangeIsABadProblem) {
    PlannerTable table = plannerTable(1);
    table.horizon_steps = 25;  // beyond kMaxPlanSteps
    expectRefused(emptyMap(), table, request(-5, 0, 5, 0, 1e-2), MapProblemError::kBadProblem);
    table.horizon_steps = 0;
    expectRefused(emptyMap(), table, request(-5, 0, 5, 0, 1e-2), MapProblemError::kBadProblem);
}

// Ten 1 m squares along the line (-8, 0) - (8, 0), their near edges 1, 1.5,
// ..., 5.5 m from it, north and south in turn, in a shuffled slot order: the
// eight nearest are kept in slot order, the two farthest (5 m and 5.5 m, in
// slots 2 and 6) dropped.
TEST(MapProblem, TheEightNearestToTheLineAreKept) {
    const double nearEdge[10] = {2.0, 1.5, 5.0, 1.0, 3.5, 2.5, 5.5, 3.0, 4.5, 4.0};
    CoarseMapTable map = emptyMap();
    for (std::size_t s = 0; s < 10; ++s) {
        const float x0 = static_cast<float>(-7.5 + 1.5 * static_cast<double>(s));
        const float sign = s % 2 == 0 ? 1.0F : -1.0F;
        const float y0 = sign * static_cast<float>(nearEdge[s]);
        const float y1 = sign * static_cast<float>(nearEdge[s] + 1.0);
        addPolygon(&map, {{x0, y0}, {x0 + 1.0F, y0}, {x0 + 1.0F, y1}, {x0, y1}});
    }
    CcProblem p;
    MapProblemReport report;
    CHECK(buildMapProblem(map, plannerTable(1), geometry(), request(-8, 0, 8, 0, 1e-2), &p, &report) == Status::kOk);
    CHECK_EQUAL(10, report.obstaclesOnMap);
    CHECK_EQUAL(8, report.obstaclesUsed);
    CHECK_EQUAL(2, report.obstaclesDropped);
    CHECK_EQUAL(kMaxPlanObstacles, p.obstacleCount);
    const std::uint8_t kept[8] = {0, 1, 3, 4, 5, 7, 8, 9};
    for (std::size_t i = 0; i < 8; ++i) {
        CHECK_EQUAL(kept[i], p.obstacles[i].id);
        CHECK_EQUAL(8, p.obstacles[i].faceCount);  // four sides, four bevels
    }
    // At most eight: nothing dropped.
    map.obstacle_count = 8;
    map.vertex_count[8] = map.vertex_count[9] = 0;
    CHECK(buildMapProblem(map, plannerTable(1), geometry(), request(-8, 0, 8, 0, 1e-2), &p, &report) == Status::kOk);
    CHECK_EQUAL(8, report.obstaclesUsed);
    CHECK_EQUAL(0, report.obstaclesDropped);
    for (std::size_t i = 0; i < 8; ++i) {
        CHECK_EQUAL(i, p.obstacles[i].id);
    }
}

// ---------------------------------------------------------------------------
// The default tables: the demo mission's coarse map, start (0, 0) and goal
// (20, 0) (sim_stub/scenarios/demo_mission.toml), and the start 1-sigma of
// rse-plan-picture's default, 0.2 m (ground/plan_picture.cpp says why).

namespace {

constexpr double kDemoSigma0 = 0.2;

struct DefaultTables {
    rse::core::VirtualClock clock;
    rse::core::EventLog events{clock};
    rse::tables::TableService service{events};
    DefaultTables() {
        CHECK(rse::core::isOk(service.init(rse::tables::kDefaultTableImages, rse::tables::kDefaultTableImageCount)));
    }
};

void planDemo(const DefaultTables& t, double risk, CcProblem* p, CcPlan* plan) {
    PlanRequest r = request(0.0, 0.0, 20.0, 0.0, risk);
    r.startCov[0] = r.startCov[3] = kDemoSigma0 * kDemoSigma0;
    MapProblemReport report;
    CHECK(buildMapProblem(t.service.coarseMap(), t.service.planner(), t.service.roverGeometry(), r, p, &report) ==
          Status::kOk);
    CHECK_EQUAL(4, report.obstaclesOnMap);
    CHECK_EQUAL(0, report.obstaclesDropped);
    CHECK_FALSE(report.startInObstacle);
    const CcStatus s = planner.solve(*p, CcPlannerParams{}, plan);
    CHECK(s == CcStatus::kOptimal || s == CcStatus::kFeasible);
    CHECK(rse::deliberative::checkPlan(*p, *plan) == Status::kOk);
    CHECK(plan->riskUsed <= risk);
}

double faceVar(const CcProblem& p, const PlanObstacle& o, std::size_t j, std::size_t t) {
    return rse::deliberative::faceVariance(o.normalX[j], o.normalY[j], p.startCov, p.processSigmaM,
                                           static_cast<unsigned>(t));
}

// The plan's least clearance in standard deviations: over every segment end
// (t, obstacle i, end e), the slack of its assigned face a . mu - b divided by
// the standard deviation of a . x there. Every end's risk is at most Delta,
// so its margin is at least PhiInv(1 - Delta) sd: the least is >= that.
// *activeZ: the least slack in sd over the ends whose constraint is active
// (slack = margin within 1 um) and whose delta is at least the even split's
// Delta / (2 N M); INFINITY when there is none.
double leastSlackInSd(const CcProblem& p, const CcPlan& plan, double* activeZ) {
    const double evenDelta = p.riskBound / (2.0 * p.steps * p.obstacleCount);
    double least = INFINITY;
    *activeZ = INFINITY;
    for (std::size_t t = 0; t < p.steps; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            const PlanObstacle& o = p.obstacles[i];
            const std::size_t j = plan.face[t][i];
            for (std::size_t e = 0; e < 2; ++e) {
                const double var = faceVar(p, o, j, t + e);
                const double slack = rse::deliberative::endSlack(o, j, plan.meanX[t + e], plan.meanY[t + e], 0.0);
                const double z = slack / std::sqrt(var);
                least = std::fmin(least, z);
                const double delta = plan.delta[t][i][e];
                const bool active =
                    std::fabs(slack - rse::deliberative::tighteningMargin(delta, var)) < 1e-6;
                if (active && delta >= evenDelta * (1.0 - 1e-9)) {
                    *activeZ = std::fmin(*activeZ, z);
                }
            }
        }
    }
    return least;
}

}  // namespace

TEST(MapProblem, DefaultTablesDemoMissionPlansWithinTheBound) {
    DefaultTables t;
    CcProblem p;
    for (const double risk : {t.service.planner().default_risk_bound, 1e-2, 1e-6}) {
        planDemo(t, risk, &p, &planA);
        CHECK_EQUAL(t.service.planner().horizon_steps, p.steps);
        DOUBLES_EQUAL(20.0, planA.meanX[p.steps], 0.0);
        DOUBLES_EQUAL(0.0, planA.meanY[p.steps], 0.0);
        // No mean-path segment touches a grown rock.
        CHECK(rse::ground::pathClearance(p, planA) > 0.0);
    }
}

// Delta = 1e-6 against 1e-2 on the demo. Quantiles (N = 20 steps, M = 4 rocks):
// every end's delta is at most Delta, so at 1e-6 every end keeps at least
// z6 = PhiInv(1 - 1e-6) = 4.753 sd from its face. At 1e-2 the plan is held by
// its margins: an end is active (slack = margin) with a delta at least the
// even split's 1e-2 / 160 (the allocation only moves risk to active ends), so
// its slack is at most z2 = PhiInv(1 - 1e-2 / 160) = 3.836 sd. Hence the least
// slack in sd rises by at least z6 - z2 = 0.92 sd. In metres (the Euclidean
// distance from the mean path to the grown rocks, what the picture shows) the
// sd is at least sigma0 = 0.2 m everywhere, so the expected gain is at least
// (z6 - z2) sigma0 = 0.18 m: asserted as clearance(1e-6) > clearance(1e-2)
// + (z6 - z2) sigma0. (At sigma0 = 0.05 m, the fix's, both plans are nearly
// the straight line and the gain would be a few cm.)
TEST(MapProblem, DefaultTablesSmallerRiskKeepsMoreClearance) {
    DefaultTables t;
    CcProblem p2;
    CcProblem p6;
    planDemo(t, 1e-2, &p2, &planA);
    planDemo(t, 1e-6, &p6, &planB);
    const double z6 = rse::deliberative::upperQuantile(1e-6);
    const double z2 = rse::deliberative::upperQuantile(1e-2 / (2.0 * p2.steps * p2.obstacleCount));
    double active2 = INFINITY;
    double active6 = INFINITY;
    const double least2 = leastSlackInSd(p2, planA, &active2);
    const double least6 = leastSlackInSd(p6, planB, &active6);
    // The guarantees: every end's slack at least PhiInv(1 - Delta) sd.
    CHECK(least2 >= rse::deliberative::upperQuantile(1e-2) - 1e-9);
    CHECK(least6 >= z6 - 1e-9);
    // The 1e-2 plan is held by an active end, at most z2 sd from its face (an
    // LP row holds kSafetyM beyond the margin: up to 1 um / sigma0 more).
    const double rowSafetySd = rse::deliberative::kSafetyM / kDemoSigma0;
    CHECK(std::isfinite(active2));
    CHECK(active2 <= z2 + rowSafetySd + 1e-9);
    CHECK(least6 - least2 >= z6 - z2 - rowSafetySd - 1e-9);
    // In metres.
    const double c2 = rse::ground::pathClearance(p2, planA);
    const double c6 = rse::ground::pathClearance(p6, planB);
    CHECK(c6 >= z6 * kDemoSigma0 - 1e-9);
    CHECK_TEXT(c6 > c2 + (z6 - z2) * kDemoSigma0, "1e-6 keeps visibly farther from the rocks");
}

// Seen hazards (KnownHazardsMsg discs) become octagons circumscribing the disc
// grown by the footprint; one that would swallow the start is grown only as far
// as the start's room (end clearance and its chance tightening) allows, one
// that leaves no such room is left out, and a non-finite one is left out.
TEST(MapProblem, SeenHazardsAreOctagonsRoundTheGrownDiscShrunkForTheStartOrLeftOut) {
    const CoarseMapTable map = emptyMap();
    const rse::msg::KnownHazard hazards[] = {
        {4.0F, 0.0F, 1.0F, 7, {}},     // on the line, clear of start and goal: full growth
        {-2.0F, 1.0F, 0.5F, 8, {}},    // start (-2.75, 1) at 0.75 from the centre: grown less
        {-8.0F, -8.0F, 0.5F, 9, {}},   // off to the side, full growth
        {0.0F, 9.0F, NAN, 10, {}},     // not finite: out
    };
    PlanRequest r = request(-2.75, 1.0, 8.0, 0.0, 1e-3);
    r.startCov[0] = r.startCov[3] = 1e-4;  // a well-fixed start: little tightening
    r.hazards = hazards;
    r.hazardCount = 4;
    CcProblem p;
    MapProblemReport report;
    CHECK(buildMapProblem(map, plannerTable(0), geometry(), r, &p, &report) == Status::kOk);
    LONGS_EQUAL(3, report.hazardsSeen);
    LONGS_EQUAL(3, report.hazardsUsed);
    LONGS_EQUAL(1, report.hazardsShrunk);
    LONGS_EQUAL(1, report.hazardsLeftOut);
    LONGS_EQUAL(3, p.obstacleCount);
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        const PlanObstacle& o = p.obstacles[i];
        LONGS_EQUAL(rse::deliberative::kHazardFaces, o.faceCount);
        const rse::msg::KnownHazard& h = hazards[o.id - 7];
        const double cx = static_cast<double>(h.xM);
        const double cy = static_cast<double>(h.yM);
        // Every face is tangent to one circle about the centre.
        const double reach = o.offset[0] - (o.normalX[0] * cx + o.normalY[0] * cy);
        for (std::size_t k = 0; k < o.faceCount; ++k) {
            DOUBLES_EQUAL(1.0, std::hypot(o.normalX[k], o.normalY[k]), 1e-12);
            DOUBLES_EQUAL(reach, o.offset[k] - (o.normalX[k] * cx + o.normalY[k] * cy), 1e-9);
        }
        if (o.id == 8) {
            // 0.75 from the centre along a face normal, less the start's room.
            const double delta = 1e-3 / (2.0 * 12.0 * static_cast<double>(kMaxPlanObstacles));
            const double room =
                rse::deliberative::kHazardEndClearanceM + rse::deliberative::tighteningMargin(delta, 2e-4);
            CHECK(room > rse::deliberative::kHazardEndClearanceM);
            DOUBLES_EQUAL(0.75 - room, reach, 1e-6);
            CHECK(reach < static_cast<double>(h.radiusM) + kRadius);
        } else {
            DOUBLES_EQUAL(static_cast<double>(h.radiusM) + kRadius, reach, 1e-6);
        }
    }
    CHECK_FALSE(report.startInObstacle);

    // The start on the bare disc of hazard 8: it is left out, not planned into.
    r.startX = -2.3;
    CHECK(buildMapProblem(map, plannerTable(0), geometry(), r, &p, &report) == Status::kOk);
    LONGS_EQUAL(2, report.hazardsUsed);
    LONGS_EQUAL(2, report.hazardsLeftOut);
}

// Hazards compete with the polygons for the planner's slots by distance to the
// straight line: one on the line displaces the farthest polygon.
TEST(MapProblem, ASeenHazardOnTheLineTakesTheSlotOfTheFarthestPolygon) {
    CoarseMapTable map = emptyMap();
    for (std::size_t i = 0; i < kMaxPlanObstacles; ++i) {
        const float y = 2.0F + static_cast<float>(i) * 0.9F;
        addPolygon(&map, {{-1.0F, y}, {0.0F, y}, {0.0F, y + 0.5F}, {-1.0F, y + 0.5F}});
    }
    const rse::msg::KnownHazard onLine[] = {{4.0F, 0.0F, 0.5F, 1, {}}};
    PlanRequest r = request(-6.0, 0.0, 8.0, 0.0, 1e-3);
    r.hazards = onLine;
    r.hazardCount = 1;
    CcProblem p;
    MapProblemReport report;
    CHECK(buildMapProblem(map, plannerTable(0), geometry(), r, &p, &report) == Status::kOk);
    LONGS_EQUAL(kMaxPlanObstacles, p.obstacleCount);
    LONGS_EQUAL(1, report.hazardsUsed);
    LONGS_EQUAL(kMaxPlanObstacles - 1, report.obstaclesUsed);
    LONGS_EQUAL(1, report.obstaclesDropped);
    // The one left out is the highest (farthest) polygon, slot kMaxPlanObstacles - 1.
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        CHECK(p.obstacles[i].faceCount == rse::deliberative::kHazardFaces || p.obstacles[i].id != kMaxPlanObstacles - 1);
    }
}


// ---------------------------------------------------------------------------
// Goals near a rock with a clear straight path (issue 15 item 4). On the demo
// map, GOTO (10, 0) and (10, 0.5), 1.0 m and 1.5 m of footprint clearance from
// the triangle (rock 1) and nothing on the way, were "proven" impossible with 0
// nodes even at Delta = 0.49: the triangle's 59-degree apex grew 1.22 m with
// the faces moved out (a goal 1 m clear lay 0.42 m from the grown polygon),
// and the search gave the goal's end only Delta / (2 N M) of the risk. The
// start is where the demo's rover stands after boot, with a fresh fix's 5 cm.

namespace {

constexpr double kFixSigma0 = 0.05;

CcStatus planFrom(const DefaultTables& t, double sx, double sy, double gx, double gy, double risk, CcProblem* p,
                  CcPlan* plan) {
    PlanRequest r = request(sx, sy, gx, gy, risk);
    r.startCov[0] = r.startCov[3] = kFixSigma0 * kFixSigma0;
    MapProblemReport report;
    CHECK(buildMapProblem(t.service.coarseMap(), t.service.planner(), t.service.roverGeometry(), r, p, &report) ==
          Status::kOk);
    return planner.solve(*p, CcPlannerParams{}, plan);
}

bool planned(CcStatus s) { return s == CcStatus::kOptimal || s == CcStatus::kFeasible; }

// Footprint clearance between the segment a-b and rock `slot`: distance less the radius.
double rockClearance(const CoarseMapTable& map, std::size_t slot, rse::geometry::Point2 a, rse::geometry::Point2 b,
                     double radius) {
    const std::size_t n = map.vertex_count[slot];
    double best = INFINITY;
    for (std::size_t v = 0; v < n; ++v) {
        best = std::fmin(best, rse::geometry::segmentSegmentDistanceSquared(
                                   a, b, rse::geometry::coarseMapVertex(map, slot, v),
                                   rse::geometry::coarseMapVertex(map, slot, (v + 1) % n)));
    }
    return std::sqrt(best) - radius;
}

}  // namespace

TEST(MapProblem, TheIssueGoalsNearTheTriangleArePlannedAtEveryRiskTheGoalAffords) {
    DefaultTables t;
    CcProblem p;
    for (const double gy : {0.0, 0.5}) {
        for (const double risk : {0.49, 1e-2, 1e-3}) {
            const CcStatus s = planFrom(t, 0.1, -0.01, 10.0, gy, risk, &p, &planA);
            CHECK_TEXT(planned(s), "a goal 1 m or 1.5 m clear of a rock, nothing on the way");
            CHECK(rse::deliberative::checkPlan(p, planA) == Status::kOk);
            CHECK(planA.riskUsed <= risk);
            CHECK(planA.euclideanLengthM < 10.5);
        }
    }
    // What is left impossible is so for the goal itself: at 1e-6 (10, 0)'s
    // own end needs more than Delta on the best face of the grown triangle
    // (margin 4.75 x 0.22 m = 1.06 m against 0.99 m of room), proven at once.
    const CcStatus s = planFrom(t, 0.1, -0.01, 10.0, 0.0, 1e-6, &p, &planA);
    CHECK(s == CcStatus::kNoPlan);
    CHECK(planner.searchExhausted());
    double goalNeed = 0.0;  // the most the goal's end needs for one obstacle
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        const PlanObstacle& o = p.obstacles[i];
        double need = 1.0;
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            need = std::fmin(need, rse::deliberative::endRisk(rse::deliberative::endSlack(o, j, 10.0, 0.0, 0.0),
                                                              faceVar(p, o, j, p.steps)));
        }
        goalNeed = std::fmax(goalNeed, need);
    }
    CHECK(goalNeed > 1e-6);
}

// A seeded set: goals 0.8 - 1.6 m of footprint clearance from one of the four
// demo rocks, in every direction, whose straight path from the start keeps at
// least 0.3 m from every rock. At 0.49 and 1e-3 every one is planned (the goal
// end alone needs at most about 4e-4 at 0.8 m: 3.4 sd at step 20). Before the
// bevels and the fixed ends' risk, 2 of these 24 at 0.49 and 11 at 1e-3 were
// "proven" impossible.
TEST(MapProblem, SeededGoalsNearARockWithAClearPathAreAllPlanned) {
    DefaultTables t;
    const CoarseMapTable& map = t.service.coarseMap();
    const double radius = static_cast<double>(t.service.roverGeometry().footprint_radius_m);
    std::mt19937_64 rng(15);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const rse::geometry::Point2 start{0.0, 0.0};
    std::size_t cases = 0;
    CcProblem p;
    for (std::size_t k = 0; k < 400 && cases < 24; ++k) {
        const std::size_t slot = k % 4;
        const std::size_t n = map.vertex_count[slot];
        double cx = 0.0;
        double cy = 0.0;
        for (std::size_t v = 0; v < n; ++v) {
            cx += static_cast<double>(map.vertex_x_m[slot * 8 + v]) / static_cast<double>(n);
            cy += static_cast<double>(map.vertex_y_m[slot * 8 + v]) / static_cast<double>(n);
        }
        const double angle = 6.283185307179586 * unit(rng);
        const double want = 0.8 + 0.8 * unit(rng);
        // Out from the rock's centroid until the footprint clears it by `want`.
        rse::geometry::Point2 g{cx, cy};
        for (std::size_t step = 0; step < 2000; ++step) {
            g = rse::geometry::Point2{cx + 0.005 * static_cast<double>(step) * std::cos(angle),
                                      cy + 0.005 * static_cast<double>(step) * std::sin(angle)};
            if (rockClearance(map, slot, g, g, radius) >= want) {
                break;
            }
        }
        double pathClearance = INFINITY;
        for (std::size_t o = 0; o < 4; ++o) {
            pathClearance = std::fmin(pathClearance, rockClearance(map, o, start, g, radius));
        }
        if (pathClearance < 0.3 || g.x < -4.0 || g.x > 29.0 || std::fabs(g.y) > 9.0) {
            continue;
        }
        ++cases;
        for (const double risk : {0.49, 1e-3}) {
            const CcStatus s = planFrom(t, start.x, start.y, g.x, g.y, risk, &p, &planA);
            CHECK_TEXT(planned(s), "a goal near a rock with a clear path");
            CHECK(rse::deliberative::checkPlan(p, planA) == Status::kOk);
        }
    }
    LONGS_EQUAL(24, cases);
}

// ---------------------------------------------------------------------------
// Monotone in Delta (issue 15 item 5). With the even split a plan at a
// tighter bound is a plan at a looser one (its ends clear larger margins), so
// the looser optimum is never longer. A looser plan longer than a tighter one
// by more than the planner's gap was cut short by the work budget: it must say
// so (kFeasible, which PLAN and event 902 show as a budget plan) and its gap,
// (cost - lower bound) / cost, must cover the excess. The demo route at
// Delta = 1e-1 .. 1e-9 from a start 0.2 m and 0.1 m uncertain (0.2 m: the
// 1e-7 plan was 20.56 m, the 1e-8 one 20.22 m). Every bound is also planned
// seeded with the next looser plan's faces, and is then never longer than
// that seed re-solved at its own margins.
TEST(MapProblem, ALooserDemoPlanLongerThanATighterOneIsABudgetPlanAndItsGapSaysSo) {
    constexpr std::size_t kRungs = 9;
    DefaultTables t;
    static CcPlan ladder[kRungs];
    static CcProblem problems[kRungs];
    double gap[kRungs] = {};
    double lower[kRungs] = {};
    unsigned inversions = 0;
    unsigned seeded = 0;
    for (const double sigma0 : {0.2, 0.1}) {
        for (std::size_t k = 0; k < kRungs; ++k) {
            PlanRequest r = request(0.0, 0.0, 20.0, 0.0, std::pow(10.0, -1.0 - static_cast<double>(k)));
            r.startCov[0] = r.startCov[3] = sigma0 * sigma0;
            MapProblemReport report;
            CcProblem& p = problems[k];
            CHECK(buildMapProblem(t.service.coarseMap(), t.service.planner(), t.service.roverGeometry(), r, &p,
                                  &report) == Status::kOk);
            p.allocation = RiskAllocation::kEvenSplit;
            (void)planner.solve(p, CcPlannerParams{}, &ladder[k]);
            lower[k] = planner.lowerBound();
            const double best = planner.evenSplitCost();
            gap[k] = std::isfinite(best) ? (best - lower[k]) / best : 1.0;
            if (k > 0 && planned(ladder[k - 1].status)) {
                CHECK(planner.start(p, CcPlannerParams{}) == Status::kOk);
                CHECK(planner.setSeedHint(ladder[k - 1]) == Status::kOk);
                for (int guard = 0; guard < 100000 && !planner.step(1000); ++guard) {
                }
                CHECK(planned(planner.plan().status));
                if (std::isfinite(planner.hintSeedCost())) {
                    ++seeded;
                    CHECK(planner.plan().cost <= planner.hintSeedCost() + 1e-9);
                }
            }
        }
        for (std::size_t loose = 0; loose < kRungs; ++loose) {
            for (std::size_t tight = loose + 1; tight < kRungs; ++tight) {
                const CcPlan& a = ladder[loose];
                const CcPlan& b = ladder[tight];
                if (!planned(b.status)) {
                    continue;
                }
                CHECK(planned(a.status));
                CHECK(rse::deliberative::checkPlan(problems[loose], b) == Status::kOk);
                CHECK(lower[loose] <= b.cost + 1e-6);
                if (a.cost > b.cost / (1.0 - CcPlannerParams{}.relativeGap) + 1e-6) {
                    ++inversions;
                    CHECK_EQUAL(static_cast<int>(CcStatus::kFeasible), static_cast<int>(a.status));
                    CHECK(gap[loose] >= (a.cost - b.cost) / a.cost - 1e-9);
                }
            }
        }
    }
    CHECK(inversions > 0);  // the budget does cut some looser plans short here
    CHECK(seeded > 0);
}

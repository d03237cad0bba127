// Site mode (route_horizons.hpp, whole_map_check.hpp "Rocks far from the
// plan"): with a site map in force the deliberative task finds a global route
// to the goal, plans horizon after horizon along it and reaches the goal; every
// plan it sends has every rock of the whole map that comes within the far
// reach of its means among its candidates (checked by a scan of every rock,
// not through the index), its certified risk holds against every rock in a
// Monte Carlo of the plan, and the far rocks' bound holds against sampling.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/site_map/site_map_image.hpp"
#include "fsw/deliberative/whole_map_check.hpp"
#include "fsw/geometry/rover_footprint.hpp"
#include "ground/site_map_encoder.hpp"
#include "sim_stub/scenario/rock_field.hpp"
#include "unit_test/fsw/deliberative/deliberative_rig.hpp"
#include "unit_test/fsw/deliberative/site_field.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using test::DeliberativeRig;

namespace {

site_map::SiteMap* siteMap = nullptr;   // ~1 MB: static storage

void loadField(double k, double w, double h, std::uint64_t seed, std::vector<Point2> clearOf) {
    test::loadSiteField(siteMap, k, w, h, seed, clearOf);
}

void checkEveryNearRockIsACandidate(const deliberative::DeliberativeTask& task) {
    test::checkEveryNearRockIsACandidate(task, *siteMap);
}

// Drives the task's legs (each achieved the run after it is sent) until the
// task completes, calls home or maxRuns pass; checks every plan on the way.
int fly(DeliberativeRig* rig, int maxRuns, unsigned* plansChecked) {
    std::uint32_t lastLegId = 0;
    std::uint32_t plansSeen = 0;
    int runs = 0;
    for (; runs < maxRuns; ++runs) {
        rig->run();
        const deliberative::DeliberativeCounters& c = rig->task.counters();
        if (c.plansFound != plansSeen) {
            plansSeen = c.plansFound;
            checkEveryNearRockIsACandidate(rig->task);
            ++*plansChecked;
        }
        if (rig->task.state() == msg::DeliberativeState::kComplete || rig->safeRequests > 0) {
            break;
        }
        if (rig->legs > 0 && rig->lastLeg.legId != lastLegId) {
            lastLegId = rig->lastLeg.legId;
            rig->achieveLeg();
        }
    }
    return runs;
}

}  // namespace

TEST_GROUP(SiteMode) {
    void setup() override {
        static site_map::SiteMap storage;
        siteMap = &storage;
        siteMap->clear();
    }
};

TEST(SiteMode, ARouteThenHorizonsAlongItReachAGoal180MetresAwayThroughABoulderField) {
    loadField(0.15, 200.0, 60.0, 7, {{10.0, 30.0}, {190.0, 30.0}});
    CHECK(siteMap->rockCount() > 40);
    DeliberativeRig* rig = new DeliberativeRig(siteMap);
    CHECK(rig->init());
    rig->x = 10.0;
    rig->y = 30.0;
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(190.0, 30.0, 1e-3);
    unsigned plans = 0;
    fly(rig, 4000, &plans);
    CHECK(rig->task.state() == msg::DeliberativeState::kComplete);
    LONGS_EQUAL(0, rig->safeRequests);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kRouteFound));
    LONGS_EQUAL(0, rig->seenCount(deliberative::events::kNoRoute));
    const deliberative::DeliberativeCounters& c = rig->task.counters();
    CHECK(c.horizonsReached >= 4);   // 180 m in horizons of 30 m, the last up to 37.5 m
    CHECK(plans >= 5);
    LONGS_EQUAL(1, c.routesFound);
    // The route went down as ROUTE chunks: announced once, every chunk sent,
    // the last one ending at the goal.
    const deliberative::GlobalRoute& route = rig->task.route().route();
    LONGS_EQUAL(1, rig->task.route().routesAnnounced());
    LONGS_EQUAL((route.pointCount() + msg::kRouteChunkPoints - 1) / msg::kRouteChunkPoints, rig->routeChunks);
    const msg::RouteChunkMsg& last = rig->lastRouteChunk;
    LONGS_EQUAL(route.pointCount(), last.pointCount);
    LONGS_EQUAL(last.chunkCount - 1, last.chunkIndex);
    DOUBLES_EQUAL(190.0, last.x[last.count - 1], 1e-4);
    DOUBLES_EQUAL(route.lengthM(), last.lengthM, 1e-9);
    // Every run within its slice: the planner's bound and the route's.
    CHECK(c.maxRunWork <= deliberative::kSliceWork + deliberative::CcPlanner::kMaxUnitWork);
    DOUBLES_EQUAL(190.0, rig->x, 0.5);
    DOUBLES_EQUAL(30.0, rig->y, 0.5);
    delete rig;
}

TEST(SiteMode, AGoalWithNoWayToItOverTheSiteMapCallsHome) {
    // A wall of rocks across the site.
    ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, 100.0F, 40.0F};
    for (float y = 0.5F; y < 40.0F; y += 1.0F) {
        spec.rocks.push_back({{49.5F, y - 0.5F}, {50.5F, y - 0.5F}, {50.5F, y + 0.5F}, {49.5F, y + 0.5F}});
    }
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(spec);
    site_map::SiteMapCheck check;
    CHECK(siteMap->load(image.data(), image.size(), &check) == core::Status::kOk);
    DeliberativeRig* rig = new DeliberativeRig(siteMap);
    CHECK(rig->init());
    rig->x = 10.0;
    rig->y = 20.0;
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(90.0, 20.0, 1e-3);
    CHECK(rig->runUntil([&] { return rig->safeRequests > 0; }, 400));
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kNoRoute));
    CHECK(rig->task.status().callHome == msg::CallHomeReason::kGoalUnreachable);
    LONGS_EQUAL(0, rig->legs);
    delete rig;
}

TEST(SiteMode, TheFarRocksBoundPicksAReachWhoseTailIsTheShare) {
    deliberative::CcProblem p{};
    p.startCov[0] = 0.04;
    p.startCov[3] = 0.01;
    p.processSigmaM = 0.05;
    const std::size_t steps = 24;
    const double share = 1e-5;
    const deliberative::FarRockBound b = deliberative::farRockBound(p, steps, 0.8, share);
    const double lambdaN = 0.04 + 24 * 0.0025;
    const double r = b.reachM - 0.8;
    DOUBLES_EQUAL(share, 25.0 * std::exp(-r * r / (2.0 * lambdaN)), 1e-12);
    CHECK(b.risk <= share);
    CHECK(b.risk > 0.0);
    // Sampling: the chance that some sampled position strays r from its mean
    // is within the bound (at a share large enough to sample).
    const deliberative::FarRockBound loose = deliberative::farRockBound(p, steps, 0.0, 0.05);
    std::mt19937_64 rng(5);
    std::normal_distribution<double> n01(0.0, 1.0);
    int strays = 0;
    const int samples = 20000;
    for (int s = 0; s < samples; ++s) {
        double ex = 0.2 * n01(rng), ey = 0.1 * n01(rng);
        bool stray = std::hypot(ex, ey) >= loose.reachM;
        for (std::size_t t = 0; t < steps && !stray; ++t) {
            ex += 0.05 * n01(rng);
            ey += 0.05 * n01(rng);
            stray = std::hypot(ex, ey) >= loose.reachM;
        }
        strays += stray ? 1 : 0;
    }
    const double rate = static_cast<double>(strays) / samples;
    CHECK(rate <= loose.risk);
    // ... and not far below it: the bound is not vacuous.
    CHECK(rate > loose.risk / 20.0);
    // No uncertainty: the reach is the disc.
    const deliberative::FarRockBound none = deliberative::farRockBound(deliberative::CcProblem{}, steps, 0.8, share);
    DOUBLES_EQUAL(0.8, none.reachM, 0.0);
    DOUBLES_EQUAL(0.0, none.risk, 0.0);
}

TEST(SiteMode, AHorizonsCertifiedRiskHoldsAgainstEveryRockOfTheMap) {
    // A wall across the site (two long rocks) with a gap of 2.4 m (the
    // rover's disc has 0.6 m either side), and 14 small rocks about: the plan
    // passes the gap close, some rocks are left out of its 8-obstacle
    // problem, and sampling sees collisions.
    ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, 60.0F, 30.0F};
    spec.rocks.push_back({{29.5F, 0.1F}, {30.5F, 0.1F}, {30.5F, 13.8F}, {29.5F, 13.8F}});
    spec.rocks.push_back({{29.5F, 16.2F}, {30.5F, 16.2F}, {30.5F, 29.9F}, {29.5F, 29.9F}});
    for (int i = 0; i < 14; ++i) {
        const float x = i < 7 ? 8.0F + 2.5F * static_cast<float>(i) : 36.0F + 2.5F * static_cast<float>(i - 7);
        const float y = i % 2 == 0 ? 3.0F : 27.0F;
        spec.rocks.push_back({{x - 0.3F, y - 0.3F}, {x + 0.3F, y - 0.3F}, {x + 0.3F, y + 0.3F}, {x - 0.3F, y + 0.3F}});
    }
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(spec);
    site_map::SiteMapCheck check;
    CHECK(siteMap->load(image.data(), image.size(), &check) == core::Status::kOk);
    DeliberativeRig* rig = new DeliberativeRig(siteMap);
    CHECK(rig->init());
    rig->x = 20.0;
    rig->y = 10.0;
    rig->positionVariance = 0.01;
    rig->positionSigma = 0.1;
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(40.0, 20.0, 0.05);
    CHECK(rig->runUntil([&] { return rig->legs > 0 || rig->safeRequests > 0; }, 600));
    CHECK(rig->legs > 0);
    const deliberative::CcPlan plan = rig->task.plan();
    const deliberative::CcProblem problem = rig->task.problem();
    const double radius = geometry::clearanceRadiusM(rig->tables.roverGeometry());
    checkEveryNearRockIsACandidate(rig->task);
    // Sample the plan's paths; a collision is a sampled segment within the
    // disc of any rock of the map (the index finds the rocks near it).
    static site_map::SiteQuery query;
    std::mt19937_64 rng(17);
    std::normal_distribution<double> n01(0.0, 1.0);
    const double s0 = std::sqrt(problem.startCov[0]);
    int hits = 0;
    const int samples = 20000;
    for (int s = 0; s < samples; ++s) {
        double ex = s0 * n01(rng), ey = s0 * n01(rng);
        Point2 prev{plan.meanX[0] + ex, plan.meanY[0] + ey};
        bool hit = false;
        for (std::size_t t = 0; t < plan.steps && !hit; ++t) {
            ex += problem.processSigmaM * n01(rng);
            ey += problem.processSigmaM * n01(rng);
            const Point2 next{plan.meanX[t + 1] + ex, plan.meanY[t + 1] + ey};
            std::uint16_t near[64];
            const std::size_t found = siteMap->rocksNearSegment(prev, next, radius, &query, near, 64, nullptr);
            for (std::size_t k = 0; k < found && !hit; ++k) {
                hit = test::rockDistance(prev, next, siteMap->rock(near[k])) < radius;
            }
            prev = next;
        }
        hits += hit ? 1 : 0;
    }
    const double rate = static_cast<double>(hits) / samples;
    const double sd = std::sqrt(plan.riskUsed * (1.0 - plan.riskUsed) / samples);
    CHECK(plan.riskUsed <= rig->task.status().riskInForce * (1.0 + 1e-9));
    CHECK(hits > 0);   // close enough to mean something
    CHECK_TEXT(rate <= plan.riskUsed + 4.0 * sd, "the sampled collision rate exceeds the certified risk");
    delete rig;
}

TEST(SiteMode, RocksNearAPlanOutsideItsCorridorBecomeCandidatesAndTooManyAreRefused) {
    ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, 100.0F, 40.0F};
    const auto square = [&spec](float x, float y) {
        spec.rocks.push_back({{x - 0.5F, y - 0.5F}, {x + 0.5F, y - 0.5F}, {x + 0.5F, y + 0.5F}, {x - 0.5F, y + 0.5F}});
    };
    square(50.0F, 22.0F);   // rock 0: 1.5 m from the corridor
    square(50.0F, 30.0F);   // rock 1: 9.5 m from it
    for (int i = 0; i < 70; ++i) {
        square(5.0F + 1.2F * static_cast<float>(i), 37.0F);   // rocks 2 .. 71: a row along y = 37
    }
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(spec);
    site_map::SiteMapCheck check;
    CHECK(siteMap->load(image.data(), image.size(), &check) == core::Status::kOk);
    DeliberativeRig* rig = new DeliberativeRig(siteMap);
    CHECK(rig->init());
    static site_map::SiteQuery query;
    const Point2 corridor[2] = {{10.0, 20.0}, {90.0, 20.0}};
    msg::KnownHazard hazard{};
    hazard.xM = 70.0F;
    hazard.yM = 15.0F;
    hazard.radiusM = 0.4F;
    hazard.obstacleId = 9;
    deliberative::PlanRequest request;
    request.startX = 10.0;
    request.startY = 20.0;
    request.startCov[0] = request.startCov[3] = 0.01;
    request.goalX = 90.0;
    request.goalY = 20.0;
    request.riskBound = 1e-3;
    request.hazards = &hazard;
    request.hazardCount = 1;
    request.site = deliberative::SiteCorridor{siteMap, &query, corridor, 2, 3.0};
    deliberative::CcProblem problem;
    deliberative::MapProblemReport report;
    static deliberative::MapObstacles candidates;
    CHECK(deliberative::buildMapProblem(rig->tables.coarseMap(), rig->tables.planner(), rig->tables.roverGeometry(),
                                        request, &problem, &report, &candidates) == core::Status::kOk);
    // The site is the site map's, shrunk by the disc; the corridor holds rock 0 alone.
    const double radius = geometry::clearanceRadiusM(rig->tables.roverGeometry());
    DOUBLES_EQUAL(radius, problem.xMin, 1e-9);
    DOUBLES_EQUAL(100.0 - radius, problem.xMax, 1e-9);
    LONGS_EQUAL(1, candidates.polygons);
    LONGS_EQUAL(2, candidates.count);
    LONGS_EQUAL(0, candidates.mapId[0]);
    // A plan that bends to pass rock 1 at 1 m: it becomes a candidate, left
    // out of the problem; the hazard stays after the polygons.
    const double mx[3] = {10.0, 50.0, 90.0};
    const double my[3] = {20.0, 28.5, 20.0};
    std::size_t added = 0;
    CHECK(deliberative::addRocksNearPath(request.site, rig->tables.roverGeometry(), problem, mx, my, 3, 2.0,
                                         &candidates, &added));
    LONGS_EQUAL(1, added);
    LONGS_EQUAL(2, candidates.polygons);
    LONGS_EQUAL(3, candidates.count);
    LONGS_EQUAL(1, candidates.mapId[1]);
    CHECK_FALSE(candidates.inProblem[1]);
    LONGS_EQUAL(deliberative::kHazardFaces, candidates.grown[2].faceCount);
    CHECK(candidates.inProblem[2]);
    // Again: nothing new.
    CHECK(deliberative::addRocksNearPath(request.site, rig->tables.roverGeometry(), problem, mx, my, 3, 2.0,
                                         &candidates, &added));
    LONGS_EQUAL(0, added);
    // A plan along the row of 70 rocks: more than the candidates hold, so it cannot be certified.
    const double rx[2] = {5.0, 90.0};
    const double ry[2] = {35.5, 35.5};
    CHECK_FALSE(deliberative::addRocksNearPath(request.site, rig->tables.roverGeometry(), problem, rx, ry, 2, 2.0,
                                               &candidates, &added));
    delete rig;
}

// The horizon's problem holds rocks, not keep-out zones: a plan whose far
// reach comes to a zone's box is not certified against it and not taken
// (event 992 names why); the route keeps zones PLANNER.site_route_zone_margin_m farther off
// than rocks, so the horizons along it stay clear and are taken.
TEST(SiteMode, KeepOutZonesAreKeptOffByTheRouteAndAPlanNearOneIsNotCertified) {
    ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, 60.0F, 30.0F};
    ground::SiteMapSpec::Zone soft;
    soft.kind = site_map::KeepOutKind::kSoft;
    soft.vertices = {{20.0F, 16.3F}, {40.0F, 16.3F}, {40.0F, 29.0F}, {20.0F, 29.0F}};   // 1.3 m north of the line
    spec.keepOuts.push_back(soft);
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(spec);
    site_map::SiteMapCheck check;
    CHECK(siteMap->load(image.data(), image.size(), &check) == core::Status::kOk);
    // The straight line passes 1.3 m from the zone: within a 2 m far reach.
    const double lineX[2] = {5.0, 55.0};
    const double lineY[2] = {15.0, 15.0};
    CHECK_TRUE(deliberative::keepOutNearPath(*siteMap, lineX, lineY, 2, 2.0));
    CHECK_FALSE(deliberative::keepOutNearPath(*siteMap, lineX, lineY, 2, 1.0));
    // Flown: the route goes round with the margin, and the plan taken stays
    // beyond its far reach of the zone.
    DeliberativeRig* rig = new DeliberativeRig(siteMap);
    CHECK(rig->init());
    rig->x = 5.0;
    rig->y = 15.0;
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(55.0, 15.0, 1e-3);
    CHECK(rig->runUntil([&] { return rig->safeRequests > 0 || rig->legs > 0; }, 600));
    CHECK(rig->legs > 0);
    const deliberative::CcPlan& plan = rig->task.plan();
    CHECK_FALSE(deliberative::keepOutNearPath(*siteMap, plan.meanX, plan.meanY, plan.steps + 1,
                                              rig->task.planMaker().farRocks().reachM));
    const deliberative::GlobalRoute& route = rig->task.route().route();
    const Point2 zone[4] = {{20.0, 16.3}, {40.0, 16.3}, {40.0, 29.0}, {20.0, 29.0}};
    const tables::PlannerTable& planner = rig->tables.planner();
    const double kept = geometry::clearanceRadiusM(rig->tables.roverGeometry()) +
                        static_cast<double>(planner.site_route_margin_m) +
                        static_cast<double>(planner.site_route_zone_margin_m);
    for (std::size_t k = 1; k < route.pointCount(); ++k) {
        const double d2 = geometry::segmentConvexPolygonDistanceSquared(route.point(k - 1), route.point(k), zone, 4);
        CHECK(d2 >= kept * kept - 1e-6);
    }
    delete rig;
}

TEST(SiteMode, NoShareForTheFarRocksCertifiesNothing) {
    deliberative::CcProblem p{};
    p.startCov[0] = p.startCov[3] = 0.01;
    p.processSigmaM = 0.05;
    const deliberative::FarRockBound b = deliberative::farRockBound(p, 24, 0.6, 0.0);
    CHECK_FALSE(std::isfinite(b.reachM));
    DOUBLES_EQUAL(1.0, b.risk, 0.0);
}

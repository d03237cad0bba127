// The global route over the site map (global_route.hpp): a route keeps its
// clearance from every rock and zone of the whole map (checked here by a scan
// of every rock, not through the index), goes through a gap, reports "no
// route" for a wall, refuses what it cannot search with its reason, stops at
// its budget with the best route so far, gives the same route however it is
// sliced, prices the passing of rocks, and takes the memory it states.
#include <cmath>
#include <cstdint>
#include <vector>

#include "fsw/deliberative/global_route.hpp"
#include "ground/site_map_encoder.hpp"
#include "unit_test/fsw/site_map/site_map_fields.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::geometry::Point2;
using rse::site_map::SiteMap;

namespace {

SiteMap* map = nullptr;        // ~2.3 MB and ~2.8 MB: static storage, as in flight
GlobalRoute* route = nullptr;

void load(const rse::ground::SiteMapSpec& spec) {
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(spec);
    rse::site_map::SiteMapCheck check;
    CHECK(map->load(image.data(), image.size(), &check) == rse::core::Status::kOk);
}

rse::ground::SiteMapSpec emptySite(float w, float h) {
    rse::ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, w, h};
    return spec;
}

// A square rock of half side r about (x, y).
std::vector<rse::ground::MapVertex> square(float x, float y, float r) {
    return {{x - r, y - r}, {x + r, y - r}, {x + r, y + r}, {x - r, y + r}};
}

// A wall of square rocks along x = x0 from y0 to y1 (touching), with no rock
// whose centre lies in the gap [gapLow, gapHigh].
void wall(rse::ground::SiteMapSpec* spec, float x0, float y0, float y1, float gapLow, float gapHigh) {
    for (float y = y0; y <= y1; y += 1.0F) {
        if (y >= gapLow && y <= gapHigh) {
            continue;
        }
        spec->rocks.push_back(square(x0, y, 0.5F));
    }
}

// A random field (site_map_fields.hpp) with no rock whose first vertex lies
// within 4 m of the given points, so that the search may start and end there.
rse::ground::SiteMapSpec fieldClearOf(std::size_t count, float side, unsigned seed, std::vector<Point2> ends) {
    rse::ground::SiteMapSpec spec = rse::test::randomField(count, side, seed);
    std::vector<std::vector<rse::ground::MapVertex>> kept;
    for (const auto& rock : spec.rocks) {
        bool near = false;
        for (const Point2& p : ends) {
            near = near || rse::geometry::distance(p, {rock[0].x, rock[0].y}) < 4.0;
        }
        if (!near) {
            kept.push_back(rock);
        }
    }
    spec.rocks = kept;
    return spec;
}

RouteState search(Point2 start, Point2 goal, const RouteParams& params, std::uint64_t slice = 1000000000ULL) {
    CHECK(route->start(*map, start, goal, params) == RouteRefusal::kNone);
    for (int i = 0; i < 100000 && !route->step(slice); ++i) {
    }
    return route->state();
}

// The least distance from the route to any rock or zone of the map, by a scan of all of them.
double routeClearance() {
    double best = INFINITY;
    for (std::size_t k = 1; k < route->pointCount(); ++k) {
        const Point2 a = route->point(k - 1);
        const Point2 b = route->point(k);
        for (std::size_t r = 0; r < map->rockCount(); ++r) {
            const rse::site_map::Rock& rock = map->rock(r);
            Point2 v[8];
            for (std::size_t i = 0; i < rock.count; ++i) {
                v[i] = Point2{rock.x[i], rock.y[i]};
            }
            best = std::fmin(best, std::sqrt(rse::geometry::segmentConvexPolygonDistanceSquared(a, b, v, rock.count)));
        }
        for (std::size_t z = 0; z < map->keepOutCount(); ++z) {
            const rse::site_map::KeepOut& zone = map->keepOut(z);
            Point2 v[16];
            for (std::size_t i = 0; i < zone.count; ++i) {
                v[i] = Point2{zone.x[i], zone.y[i]};
            }
            best = std::fmin(best, std::sqrt(rse::geometry::segmentConvexPolygonDistanceSquared(a, b, v, zone.count)));
        }
    }
    return best;
}

void checkEnds(Point2 start, Point2 goal) {
    CHECK(route->pointCount() >= 2);
    DOUBLES_EQUAL(start.x, route->point(0).x, 1e-9);
    DOUBLES_EQUAL(start.y, route->point(0).y, 1e-9);
    DOUBLES_EQUAL(goal.x, route->point(route->pointCount() - 1).x, 1e-9);
    DOUBLES_EQUAL(goal.y, route->point(route->pointCount() - 1).y, 1e-9);
}

}  // namespace

TEST_GROUP(GlobalRoute) {
    void setup() override {
        static SiteMap storage;
        static GlobalRoute searcher;
        map = &storage;
        route = &searcher;
        map->clear();
    }
};

TEST(GlobalRoute, AnOpenSiteIsCrossedInAStraightLine) {
    load(emptySite(100.0F, 50.0F));
    const Point2 start{5.0, 5.0}, goal{45.0, 40.0};
    CHECK(search(start, goal, RouteParams{}) == RouteState::kFound);
    checkEnds(start, goal);
    LONGS_EQUAL(2, route->pointCount());
    DOUBLES_EQUAL(rse::geometry::distance(start, goal), route->lengthM(), 1e-6);
    DOUBLES_EQUAL(route->lengthM(), route->cost(), 1e-3);   // no rock near: no price
}

TEST(GlobalRoute, ALongWayIsCutIntoSightLinesOfAtMostTheSightRange) {
    load(emptySite(300.0F, 50.0F));
    const Point2 start{5.0, 5.0}, goal{295.0, 45.0};
    CHECK(search(start, goal, RouteParams{}) == RouteState::kFound);
    checkEnds(start, goal);
    const double straight = rse::geometry::distance(start, goal);
    CHECK(route->pointCount() >= 1 + static_cast<std::size_t>(std::ceil(straight / kMaxSightM)));
    CHECK(route->pointCount() <= 3 + static_cast<std::size_t>(std::ceil(straight / kMaxSightM)));
    for (std::size_t k = 1; k < route->pointCount(); ++k) {
        CHECK(rse::geometry::distance(route->point(k - 1), route->point(k)) <= kMaxSightM + 1e-9);
    }
    CHECK(route->lengthM() <= straight * 1.001);
}

TEST(GlobalRoute, AWallIsPassedThroughItsGapWithTheClearanceKept) {
    rse::ground::SiteMapSpec spec = emptySite(60.0F, 60.0F);
    wall(&spec, 30.0F, 1.0F, 59.0F, 44.0F, 48.0F);   // a gap from y 43.5 to 48.5
    load(spec);
    const Point2 start{10.0, 10.0}, goal{50.0, 10.0};
    RouteParams params;
    CHECK(search(start, goal, params) == RouteState::kFound);
    checkEnds(start, goal);
    CHECK(routeClearance() >= params.clearanceM);
    // Through the gap: some point of the route lies in it.
    bool through = false;
    for (std::size_t k = 1; k < route->pointCount(); ++k) {
        const Point2 a = route->point(k - 1), b = route->point(k);
        if ((a.x - 30.0) * (b.x - 30.0) <= 0.0 && a.x != b.x) {
            const double y = a.y + (b.y - a.y) * (30.0 - a.x) / (b.x - a.x);
            through = through || (y > 43.5 + params.clearanceM && y < 48.5 - params.clearanceM);
        }
    }
    CHECK_TRUE(through);
    // Any angle: far fewer points than the 40-odd lattice steps (a few more
    // than two lines: the price of passing the gap's corners bends it), and
    // near the shortest way through the gap's middle.
    CHECK(route->pointCount() <= 6);
    const double viaGap = rse::geometry::distance(start, {30.0, 46.0}) + rse::geometry::distance({30.0, 46.0}, goal);
    CHECK(route->lengthM() <= viaGap * 1.03);
}

TEST(GlobalRoute, AWallWithNoGapWideEnoughIsNoRoute) {
    rse::ground::SiteMapSpec spec = emptySite(60.0F, 60.0F);
    wall(&spec, 30.0F, 0.5F, 59.5F, 20.0F, 21.0F);   // a gap of 1 m between the rock faces, under 2 x 0.8
    load(spec);
    CHECK(search({10.0, 10.0}, {50.0, 10.0}, RouteParams{}) == RouteState::kNoRoute);
    LONGS_EQUAL(0, route->pointCount());
    // Every node the start reaches was expanded: the left half of the lattice.
    CHECK(route->stats().expansions > 500);
    // With a clearance the gap allows, there is one.
    RouteParams narrow;
    narrow.clearanceM = 0.3;
    narrow.comfortM = 1.0;
    narrow.spacingM = 0.25;   // fine enough to put nodes in the gap with room
    CHECK(search({10.0, 10.0}, {50.0, 10.0}, narrow) == RouteState::kFound);
    CHECK(routeClearance() >= narrow.clearanceM);
}

TEST(GlobalRoute, WhatCannotBeSearchedIsRefusedWithItsReason) {
    const RouteParams ok;
    CHECK(route->start(*map, {1.0, 1.0}, {2.0, 2.0}, ok) == RouteRefusal::kNoMap);
    CHECK(route->state() == RouteState::kRefused);
    rse::ground::SiteMapSpec spec = emptySite(40.0F, 40.0F);
    spec.rocks.push_back(square(20.0F, 20.0F, 1.0F));
    rse::ground::SiteMapSpec::Zone zone;
    zone.vertices = {{30.0F, 30.0F}, {36.0F, 30.0F}, {36.0F, 36.0F}, {30.0F, 36.0F}};
    spec.keepOuts.push_back(zone);
    load(spec);
    const Point2 a{5.0, 5.0}, b{35.0, 5.0};
    const auto with = [](auto change) {
        RouteParams p;
        change(&p);
        return p;
    };
    CHECK(route->start(*map, a, b, with([](RouteParams* p) { p->clearanceM = 0.0; })) == RouteRefusal::kBadParams);
    CHECK(route->start(*map, a, b, with([](RouteParams* p) { p->comfortM = p->clearanceM; })) == RouteRefusal::kBadParams);
    CHECK(route->start(*map, a, b, with([](RouteParams* p) { p->proximityCost = -1.0; })) == RouteRefusal::kBadParams);
    CHECK(route->start(*map, a, b, with([](RouteParams* p) { p->spacingM = 0.1; })) == RouteRefusal::kBadParams);
    CHECK(route->start(*map, a, b, with([](RouteParams* p) { p->spacingM = NAN; })) == RouteRefusal::kBadParams);
    CHECK(route->start(*map, a, b, with([](RouteParams* p) { p->heuristicWeight = 0.5; })) == RouteRefusal::kBadParams);
    CHECK(route->start(*map, a, b, with([](RouteParams* p) { p->workBudget = 0; })) == RouteRefusal::kBadParams);
    CHECK(route->start(*map, {NAN, 5.0}, b, ok) == RouteRefusal::kBadPoint);
    CHECK(route->start(*map, {0.5, 5.0}, b, ok) == RouteRefusal::kStartOffSite);   // within the clearance of the edge
    CHECK(route->start(*map, a, {41.0, 5.0}, ok) == RouteRefusal::kGoalOffSite);
    CHECK(route->start(*map, {20.0, 21.5}, b, ok) == RouteRefusal::kStartBlocked);  // 0.5 m from the rock
    CHECK(route->start(*map, a, {33.0, 33.0}, ok) == RouteRefusal::kGoalBlocked);   // in the zone
    CHECK(route->state() == RouteState::kRefused);
    CHECK_TRUE(route->step(1000000));   // nothing to search: ended at once
    LONGS_EQUAL(0, route->pointCount());
}

TEST(GlobalRoute, FiveThousandRocksOnAKilometreAreCrossedClearOfEveryRock) {
    const Point2 start{20.0, 30.0}, goal{980.0, 960.0};
    load(fieldClearOf(5000, 1000.0F, 31, {start, goal}));
    RouteParams params;
    CHECK(search(start, goal, params) == RouteState::kFound);
    checkEnds(start, goal);
    CHECK(routeClearance() >= params.clearanceM);
    // 1 km x 1 km at kMaxRouteNodes: the spacing grows to fit.
    CHECK(route->stats().spacingM > 2.7 && route->stats().spacingM < 2.9);
    CHECK(static_cast<std::size_t>(route->stats().columns) * route->stats().rows <= kMaxRouteNodes);
    const double straight = rse::geometry::distance(start, goal);
    CHECK(route->lengthM() >= straight);
    CHECK(route->lengthM() <= 1.05 * straight);
    CHECK(route->stats().work <= params.workBudget);
}

TEST(GlobalRoute, ASpentBudgetEndsWithTheBestRouteSoFar) {
    const Point2 start{20.0, 30.0}, goal{980.0, 960.0};
    load(fieldClearOf(5000, 1000.0F, 32, {start, goal}));
    RouteParams params;
    params.workBudget = 2000000;
    CHECK(search(start, goal, params, 100000) == RouteState::kBudgetSpent);
    CHECK(route->pointCount() >= 2);
    DOUBLES_EQUAL(start.x, route->point(0).x, 1e-9);
    const Point2 end = route->point(route->pointCount() - 1);
    CHECK(rse::geometry::distance(end, goal) < rse::geometry::distance(start, goal) - 10.0);
    CHECK(routeClearance() >= params.clearanceM);
    // The budget is kept within one expansion's work, and every step within its slice and one expansion.
    CHECK(route->stats().work >= params.workBudget);
    CHECK(route->stats().work < params.workBudget + 400000);
    CHECK(route->stats().maxStepWork < 100000 + 400000);
}

TEST(GlobalRoute, TheRouteIsTheSameHoweverTheSearchIsSliced) {
    const Point2 start{10.0, 10.0}, goal{140.0, 130.0};
    load(fieldClearOf(600, 150.0F, 33, {start, goal}));
    CHECK(search(start, goal, RouteParams{}) == RouteState::kFound);
    std::vector<Point2> whole;
    for (std::size_t k = 0; k < route->pointCount(); ++k) {
        whole.push_back(route->point(k));
    }
    CHECK(search(start, goal, RouteParams{}, 50000) == RouteState::kFound);
    CHECK(route->stats().steps > 10);
    LONGS_EQUAL(whole.size(), route->pointCount());
    for (std::size_t k = 0; k < whole.size(); ++k) {
        DOUBLES_EQUAL(whole[k].x, route->point(k).x, 0.0);
        DOUBLES_EQUAL(whole[k].y, route->point(k).y, 0.0);
    }
}

TEST(GlobalRoute, PassingCloseToRocksIsPricedSoAWiderWayIsTakenWhenItIsWorthIt) {
    // Two ways round a wall: a gap at y 30 that leaves 2 m between rocks
    // (0.2 m more than the clearance each side), and an open end at y 58,
    // farther. Unpriced, the gap; priced, the open end.
    rse::ground::SiteMapSpec spec = emptySite(60.0F, 60.0F);
    wall(&spec, 30.0F, 0.5F, 54.5F, 29.0F, 31.0F);   // rocks at 28.5 and 31.5: faces 29 and 31
    load(spec);
    const Point2 start{20.0, 30.0}, goal{40.0, 30.0};
    RouteParams unpriced;
    unpriced.proximityCost = 0.0;
    CHECK(search(start, goal, unpriced) == RouteState::kFound);
    const double throughGap = route->lengthM();
    CHECK(throughGap < 21.0);
    RouteParams priced;
    priced.proximityCost = 200.0;
    CHECK(search(start, goal, priced) == RouteState::kFound);
    CHECK(route->lengthM() > 40.0);   // round the open end
    CHECK(routeClearance() >= priced.clearanceM);
}

TEST(GlobalRoute, AKeepOutZoneIsGoneRoundWithTheClearance) {
    rse::ground::SiteMapSpec spec = emptySite(60.0F, 60.0F);
    rse::ground::SiteMapSpec::Zone soft;
    soft.kind = rse::site_map::KeepOutKind::kSoft;
    soft.vertices = {{25.0F, 10.0F}, {35.0F, 10.0F}, {35.0F, 50.0F}, {25.0F, 50.0F}};
    spec.keepOuts.push_back(soft);
    load(spec);
    const Point2 start{10.0, 30.0}, goal{50.0, 30.0};
    RouteParams params;
    CHECK(search(start, goal, params) == RouteState::kFound);
    CHECK(routeClearance() >= params.clearanceM);
    CHECK(route->lengthM() > 45.0);
}

TEST(GlobalRoute, AWeightedHeuristicFindsARouteWithinItsWeightForLessWork) {
    const Point2 start{10.0, 190.0}, goal{190.0, 10.0};
    load(fieldClearOf(1000, 200.0F, 34, {start, goal}));
    CHECK(search(start, goal, RouteParams{}) == RouteState::kFound);
    const double cheapest = route->cost();
    const std::uint32_t expansions = route->stats().expansions;
    RouteParams quick;
    quick.heuristicWeight = 1.5;
    CHECK(search(start, goal, quick) == RouteState::kFound);
    CHECK(route->cost() <= 1.5 * cheapest + 1e-6);
    CHECK(route->stats().expansions < expansions);
    CHECK(routeClearance() >= quick.clearanceM);
}

TEST(GlobalRoute, TheSearchTakesTheStaticMemoryTheDocsState) {
    // docs/deliberative.md, "Global route": 21 bytes a node for
    // kMaxRouteNodes + 2 nodes, the query scratch (40 KB) and the route: under 2.82 MB.
    CHECK(kGlobalRouteBytes >= 21 * (kMaxRouteNodes + 2));
    CHECK(kGlobalRouteBytes < 2820000);
}

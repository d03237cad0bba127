#include "fsw/deliberative/map_problem.hpp"

#include "fsw/geometry/rover_footprint.hpp"

#include <cmath>
#include <cstddef>

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/gaussian.hpp"
#include "fsw/geometry/coarse_map.hpp"
#include "fsw/geometry/geometry2d.hpp"

namespace rse::deliberative {

namespace {

using geometry::coarseMapVertex;
using geometry::kCoarseMapSlots;
using geometry::Point2;

// A corner is bevelled when its faces turn by more than this (cos of 30
// degrees): a shallower corner overshoots the disc by under 4 % of the radius
// and a bevel there would only add a face for the search to branch on.
constexpr double kBevelMaxCos = 0.8660254037844386;

// The polygon v[0 .. count) grown by radius: faces with outward unit normals,
// then bevels. False for a polygon that is not strictly convex (a zero-length
// edge, a reflex or straight corner, a boundary that winds more than once).
bool grownPolygon(const Point2* vertex, std::size_t count, double radius, std::uint8_t id, PlanObstacle* out) {
    double twiceArea = 0.0;
    for (std::size_t v = 0; v < count; ++v) {
        twiceArea += geometry::cross(vertex[v], vertex[(v + 1) % count]);
    }
    if (!(std::fabs(twiceArea) > 0.0)) {
        return false;
    }
    const double winding = twiceArea > 0.0 ? 1.0 : -1.0;  // +1 counter-clockwise
    out->id = id;
    double edgeNx[kMaxObstacleFaces] = {};
    double edgeNy[kMaxObstacleFaces] = {};
    for (std::size_t v = 0; v < count; ++v) {
        const Point2 a = vertex[v];
        const Point2 b = vertex[(v + 1) % count];
        const Point2 c = vertex[(v + 2) % count];
        if (winding * geometry::cross(b - a, c - b) <= 0.0) {
            return false;
        }
        // Every other vertex strictly inside this edge: turns of one sign
        // alone let a polygon that winds twice through (a pentagram), whose
        // faces bound only its inner pentagon.
        for (std::size_t w = 0; w < count; ++w) {
            const bool onEdge = w == v || w == (v + 1) % count;
            if (!onEdge && winding * geometry::cross(b - a, vertex[w] - a) <= 0.0) {
                return false;
            }
        }
        const Point2 e = b - a;
        const double length = std::sqrt(geometry::dot(e, e));
        // Outward normal: the edge turned clockwise for a counter-clockwise polygon.
        edgeNx[v] = winding * e.y / length;
        edgeNy[v] = -winding * e.x / length;
    }
    // Bevels: moving the faces out alone leaves each corner of the grown
    // polygon radius / cos(turn / 2) from the rock's vertex, far beyond the
    // disc (1.2 m instead of 0.6 m at the demo triangle's 59-degree apex), and
    // a goal 1 m clear of the rock lay only 0.42 m outside it. A bevel face
    // with the bisecting normal, radius beyond the vertex, is tangent to the
    // disc there, so the polygon still contains the disc sweep. Sharpest
    // corners first, while the planner's kMaxObstacleFaces allow.
    bool bevel[kMaxObstacleFaces] = {};
    std::size_t faces = count;
    for (std::size_t pass = 0; pass < count && faces < kMaxObstacleFaces; ++pass) {
        std::size_t sharpest = count;
        double leastCos = kBevelMaxCos;
        for (std::size_t v = 0; v < count; ++v) {
            const std::size_t w = (v + 1) % count;
            const double c = edgeNx[v] * edgeNx[w] + edgeNy[v] * edgeNy[w];  // cos of the turn at vertex v + 1
            if (!bevel[v] && c < leastCos) {
                leastCos = c;
                sharpest = v;
            }
        }
        if (sharpest == count) {
            break;
        }
        bevel[sharpest] = true;
        ++faces;
    }
    std::size_t f = 0;
    for (std::size_t v = 0; v < count; ++v) {
        const Point2 a = vertex[v];
        out->normalX[f] = edgeNx[v];
        out->normalY[f] = edgeNy[v];
        out->offset[f] = edgeNx[v] * a.x + edgeNy[v] * a.y + radius;
        ++f;
        if (bevel[v]) {
            const std::size_t w = (v + 1) % count;
            const Point2 corner = vertex[w];
            const double mx = edgeNx[v] + edgeNx[w];
            const double my = edgeNy[v] + edgeNy[w];
            const double m = std::sqrt(mx * mx + my * my);
            out->normalX[f] = mx / m;
            out->normalY[f] = my / m;
            out->offset[f] = out->normalX[f] * corner.x + out->normalY[f] * corner.y + radius;
            ++f;
        }
    }
    out->faceCount = static_cast<std::uint8_t>(f);
    return true;
}

// Inside the open grown polygon: below every face.
bool inside(const PlanObstacle& o, double x, double y) {
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        if (o.normalX[j] * x + o.normalY[j] * y >= o.offset[j]) {
            return false;
        }
    }
    return true;
}

// Squared distance from the segment start-goal to the polygon's edges: a
// ranking, not a clearance (0 when they meet).
double rankDistance(const Point2* vertex, std::size_t count, Point2 s, Point2 g) {
    double best = INFINITY;
    for (std::size_t v = 0; v < count; ++v) {
        const double d = geometry::segmentSegmentDistanceSquared(s, g, vertex[v], vertex[(v + 1) % count]);
        best = d < best ? d : best;
    }
    return best;
}

// The octagon that circumscribes the disc (centre, radius): face k's outward
// normal at angle 2 pi k / kHazardFaces.
void hazardOctagon(Point2 centre, double radius, std::uint8_t id, PlanObstacle* out) {
    constexpr double kTwoPi = 6.283185307179586;
    out->id = id;
    out->faceCount = static_cast<std::uint8_t>(kHazardFaces);
    for (std::size_t k = 0; k < kHazardFaces; ++k) {
        const double a = kTwoPi * static_cast<double>(k) / static_cast<double>(kHazardFaces);
        out->normalX[k] = std::cos(a);
        out->normalY[k] = std::sin(a);
        out->offset[k] = out->normalX[k] * centre.x + out->normalY[k] * centre.y + radius;
    }
}

// How far p lies from centre in the octagon's gauge: p is inside the octagon of
// radius r about centre exactly when this is below r.
double octagonGauge(Point2 centre, Point2 p) {
    constexpr double kTwoPi = 6.283185307179586;
    double worst = -INFINITY;
    for (std::size_t k = 0; k < kHazardFaces; ++k) {
        const double a = kTwoPi * static_cast<double>(k) / static_cast<double>(kHazardFaces);
        const double d = std::cos(a) * (p.x - centre.x) + std::sin(a) * (p.y - centre.y);
        worst = d > worst ? d : worst;
    }
    return worst;
}

bool finite(const PlanRequest& r) {
    bool ok = std::isfinite(r.startX) && std::isfinite(r.startY) && std::isfinite(r.goalX) &&
              std::isfinite(r.goalY) && std::isfinite(r.riskBound) && std::isfinite(r.noiseFactor);
    for (double c : r.startCov) {
        ok = ok && std::isfinite(c);
    }
    return ok;
}

}  // namespace

const char* toString(MapProblemError error) {
    switch (error) {
        case MapProblemError::kNone: return "none";
        case MapProblemError::kBadRequest: return "bad request";
        case MapProblemError::kStartOffSite: return "start off the site";
        case MapProblemError::kGoalOffSite: return "goal off the site";
        case MapProblemError::kGoalInObstacle: return "goal inside an obstacle";
        case MapProblemError::kBadMap: return "coarse map polygon not convex";
        case MapProblemError::kBadProblem: return "planner table out of range";
        case MapProblemError::kTooManyRocks: return "too many site-map rocks near the horizon";
    }
    return "?";
}

geometry::SiteBox planningSite(const tables::CoarseMapTable& map, const tables::RoverGeometryTable& rover) {
    return geometry::siteBox(map, rse::geometry::clearanceRadiusM(rover));
}

geometry::SiteBox siteMapBox(const site_map::SiteMap& map, double insetM) {
    const site_map::SiteBounds& b = map.site();
    return geometry::SiteBox{static_cast<double>(b.xMin) + insetM, static_cast<double>(b.xMax) - insetM,
                             static_cast<double>(b.yMin) + insetM, static_cast<double>(b.yMax) - insetM};
}

geometry::SiteBox siteFor(const tables::CoarseMapTable& map, const site_map::SiteMap* site, double insetM) {
    return site != nullptr ? siteMapBox(*site, insetM) : geometry::siteBox(map, insetM);
}

namespace {

// The problem but its obstacles: the plant from the tables and the request,
// the site from the map.
CcProblem problemFrame(const tables::PlannerTable& planner, const PlanRequest& request,
                       const geometry::SiteBox& site) {
    CcProblem p{};
    p.steps = static_cast<std::uint8_t>(planner.horizon_steps <= kMaxPlanSteps ? planner.horizon_steps : 0);
    p.startX = request.startX;
    p.startY = request.startY;
    for (std::size_t k = 0; k < 4; ++k) {
        p.startCov[k] = request.startCov[k];
    }
    // The estimator's covariance is symmetric up to rounding; the planner wants it exactly.
    p.startCov[1] = p.startCov[2] = 0.5 * (request.startCov[1] + request.startCov[2]);
    p.processSigmaM = static_cast<double>(planner.process_noise_sigma_m) * request.noiseFactor;
    p.goalX = request.goalX;
    p.goalY = request.goalY;
    p.xMin = site.minX;
    p.xMax = site.maxX;
    p.yMin = site.minY;
    p.yMax = site.maxY;
    p.riskBound = request.riskBound;
    p.allocation = planner.risk_allocation == 1 ? RiskAllocation::kOptimised : RiskAllocation::kEvenSplit;
    return p;
}

// Every polygon in use grown by the footprint; kBadMap or kGoalInObstacle
// stop the problem.
MapProblemError addMapPolygons(const tables::CoarseMapTable& map, const CcProblem& p, double radius,
                               MapObstacles* c, MapProblemReport* report) {
    const std::size_t slots = rse::geometry::coarseMapSlotsUsed(map);
    const Point2 s{p.startX, p.startY};
    const Point2 g{p.goalX, p.goalY};
    for (std::size_t slot = 0; slot < slots; ++slot) {
        const std::size_t n = map.vertex_count[slot];
        Point2 vertex[kMaxObstacleFaces];
        for (std::size_t v = 0; v < n && v < kMaxObstacleFaces; ++v) {
            vertex[v] = coarseMapVertex(map, slot, v);
        }
        if (n < 3 || n > kMaxObstacleFaces ||
            !grownPolygon(vertex, n, radius, static_cast<std::uint8_t>(slot), &c->grown[c->count])) {
            return MapProblemError::kBadMap;
        }
        if (inside(c->grown[c->count], p.goalX, p.goalY)) {
            return MapProblemError::kGoalInObstacle;
        }
        report->startInObstacle = report->startInObstacle || inside(c->grown[c->count], p.startX, p.startY);
        c->rank[c->count] = rankDistance(vertex, n, s, g);
        c->mapId[c->count] = static_cast<std::uint16_t>(slot);
        ++c->count;
    }
    report->obstaclesOnMap = static_cast<std::uint8_t>(c->count);
    c->polygons = c->count;
    return MapProblemError::kNone;
}

// Site rock id as a candidate (once: already listed is fine). kTooManyRocks
// when kMaxMapPolygons are listed, kBadMap for a polygon the planner cannot
// take, kGoalInObstacle when checkGoal and the grown rock holds the goal.
MapProblemError addSiteRock(const site_map::SiteMap& map, std::uint16_t id, const CcProblem& p, double radius,
                            bool checkGoal, const Point2* corridor, std::size_t corridorCount, MapObstacles* c,
                            bool* startInside) {
    for (std::size_t i = 0; i < c->polygons; ++i) {
        if (c->mapId[i] == id) {
            return MapProblemError::kNone;
        }
    }
    if (c->polygons >= kMaxMapPolygons) {
        return MapProblemError::kTooManyRocks;
    }
    const site_map::Rock& rock = map.rock(id);
    Point2 vertex[kMaxObstacleFaces];
    const std::size_t n = rock.count < kMaxObstacleFaces ? rock.count : kMaxObstacleFaces;
    for (std::size_t v = 0; v < n; ++v) {
        vertex[v] = Point2{rock.x[v], rock.y[v]};
    }
    // Polygons come first in the candidates: a rock added after the seen
    // hazards (a plan's top-up) moves the first hazard to the end.
    const std::size_t at = c->polygons;
    if (c->count > at) {
        c->grown[c->count] = c->grown[at];
        c->rank[c->count] = c->rank[at];
        c->forced[c->count] = c->forced[at];
        c->inProblem[c->count] = c->inProblem[at];
        c->mapId[c->count] = c->mapId[at];
    }
    PlanObstacle& grown = c->grown[at];
    if (n < 3 || !grownPolygon(vertex, n, radius, static_cast<std::uint8_t>(at), &grown)) {
        return MapProblemError::kBadMap;
    }
    if (checkGoal && inside(grown, p.goalX, p.goalY)) {
        return MapProblemError::kGoalInObstacle;
    }
    *startInside = *startInside || inside(grown, p.startX, p.startY);
    double rank = INFINITY;
    for (std::size_t s = 1; s < corridorCount; ++s) {
        rank = std::fmin(rank, rankDistance(vertex, n, corridor[s - 1], corridor[s]));
    }
    c->rank[at] = rank;
    c->forced[at] = false;
    c->inProblem[at] = false;
    c->mapId[at] = id;
    ++c->polygons;
    ++c->count;
    return MapProblemError::kNone;
}

// Every site rock within reach of the polyline points[0 .. count), as candidates.
MapProblemError addSiteRocksNear(const site_map::SiteMap& map, site_map::SiteQuery* query, const Point2* points,
                                 std::size_t count, double reach, const CcProblem& p, double radius, bool checkGoal,
                                 MapObstacles* c, bool* startInside) {
    std::uint16_t near[kMaxMapPolygons];
    for (std::size_t k = 1; k < count; ++k) {
        site_map::QueryStats stats;
        const std::size_t found =
            map.rocksNearSegment(points[k - 1], points[k], reach, query, near, kMaxMapPolygons, &stats);
        if (stats.overflow || stats.refused) {
            return MapProblemError::kTooManyRocks;
        }
        for (std::size_t f = 0; f < found; ++f) {
            const MapProblemError e = addSiteRock(map, near[f], p, radius, checkGoal, points, count, c, startInside);
            if (e != MapProblemError::kNone) {
                return e;
            }
        }
    }
    return MapProblemError::kNone;
}

// Site mode: every site-map rock within the corridor's reach grown by the
// footprint, once each, ranked by its distance to the corridor; as
// addMapPolygons, and kTooManyRocks beyond kMaxMapPolygons.
MapProblemError addSiteRocks(const SiteCorridor& corridor, const CcProblem& p, double radius, MapObstacles* c,
                             MapProblemReport* report) {
    if (corridor.query == nullptr || corridor.points == nullptr || corridor.count < 2 || !(corridor.reachM >= 0.0)) {
        return MapProblemError::kTooManyRocks;
    }
    const MapProblemError e = addSiteRocksNear(*corridor.map, corridor.query, corridor.points, corridor.count,
                                               corridor.reachM, p, radius, true, c, &report->startInObstacle);
    report->obstaclesOnMap = static_cast<std::uint8_t>(c->count);
    return e;
}

// Every usable seen hazard as an octagon grown by the footprint, less where
// the start or the goal needs room (see the header).
void addSeenHazards(const PlanRequest& request, const CcProblem& p, double radius, MapObstacles* c,
                    MapProblemReport* report) {
    const Point2 s{p.startX, p.startY};
    const Point2 g{p.goalX, p.goalY};
    // Room the start needs beyond an obstacle it stands close to: the end
    // clearance and its own chance-constraint tightening at the even split of
    // the largest problem (the trace bounds every face's variance).
    const double startDelta = p.riskBound / (2.0 * static_cast<double>(p.steps > 0 ? p.steps : 1) *
                                             static_cast<double>(kMaxPlanObstacles));
    const double startMargin =
        kHazardEndClearanceM + tighteningMargin(startDelta, p.startCov[0] + p.startCov[3]);
    const std::size_t hazards =
        request.hazards == nullptr ? 0 : (request.hazardCount < msg::kMaxKnownHazards ? request.hazardCount : msg::kMaxKnownHazards);
    for (std::size_t h = 0; h < hazards; ++h) {
        const msg::KnownHazard& hz = request.hazards[h];
        const Point2 centre{static_cast<double>(hz.xM), static_cast<double>(hz.yM)};
        const double r = static_cast<double>(hz.radiusM);
        if (!geometry::isFinite(centre) || !std::isfinite(r) || !(r > 0.0)) {
            ++report->hazardsLeftOut;
            continue;
        }
        ++report->hazardsSeen;
        // The growth that keeps the start and the goal outside (see the header).
        const double room =
            std::fmin(octagonGauge(centre, s) - startMargin, octagonGauge(centre, g) - kHazardEndClearanceM) - r;
        if (room < 0.0) {
            ++report->hazardsLeftOut;
            continue;
        }
        const double growth = room < radius ? room : radius;
        if (growth < radius) {
            ++report->hazardsShrunk;
        }
        hazardOctagon(centre, r + growth, hz.obstacleId, &c->grown[c->count]);
        c->mapId[c->count] = 0;
        const double gap = std::sqrt(geometry::pointSegmentDistanceSquared(centre, s, g)) - r;
        c->rank[c->count] = gap > 0.0 ? gap * gap : 0.0;
        ++c->count;
    }
}

// The index of the nearest candidate not yet taken with forced == wantForced
// (ties to the lower index); c.count when there is none.
std::size_t nearestUntaken(const MapObstacles& c, const bool* taken, bool wantForced) {
    std::size_t pick = c.count;
    for (std::size_t i = 0; i < c.count; ++i) {
        if (!taken[i] && c.forced[i] == wantForced && (pick == c.count || c.rank[i] < c.rank[pick])) {
            pick = i;
        }
    }
    return pick;
}

}  // namespace

void MapObstacles::clear() {
    count = 0;
    polygons = 0;
    for (bool& f : forced) {
        f = false;
    }
}

std::size_t MapObstacles::leftOut() const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < count; ++i) {
        n += inProblem[i] ? 0U : 1U;
    }
    return n;
}

void selectObstacles(MapObstacles* c, CcProblem* p, MapProblemReport* report) {
    bool* taken = c->inProblem;
    for (std::size_t i = 0; i < c->count; ++i) {
        taken[i] = false;
    }
    const std::size_t keep = c->count < kMaxPlanObstacles ? c->count : kMaxPlanObstacles;
    for (std::size_t k = 0; k < keep; ++k) {
        std::size_t pick = nearestUntaken(*c, taken, true);
        pick = pick < c->count ? pick : nearestUntaken(*c, taken, false);
        taken[pick] = true;
    }
    p->obstacleCount = 0;
    std::size_t polygonsUsed = 0;
    for (std::size_t i = 0; i < c->count; ++i) {
        if (taken[i]) {
            p->obstacles[p->obstacleCount++] = c->grown[i];
            polygonsUsed += i < c->polygons ? 1U : 0U;
        }
    }
    report->obstaclesUsed = static_cast<std::uint8_t>(polygonsUsed);
    report->obstaclesDropped = static_cast<std::uint8_t>(c->polygons - polygonsUsed);
    report->hazardsUsed = static_cast<std::uint8_t>(p->obstacleCount - polygonsUsed);
}

core::Status buildMapProblem(const tables::CoarseMapTable& map, const tables::PlannerTable& planner,
                             const tables::RoverGeometryTable& geometry, const PlanRequest& request,
                             CcProblem* out, MapProblemReport* report, MapObstacles* obstacles) {
    *report = MapProblemReport{};
    const auto fail = [report](MapProblemError error) {
        report->error = error;
        return core::Status::kInvalidArgument;
    };
    if (!finite(request) || !(request.riskBound > 0.0 && request.riskBound < 0.5) || !(request.noiseFactor >= 1.0)) {
        return fail(MapProblemError::kBadRequest);
    }
    const double radius = rse::geometry::clearanceRadiusM(geometry);
    const geometry::SiteBox site = siteFor(map, request.site.map, radius);
    CcProblem p = problemFrame(planner, request, site);
    const auto onSite = [&site](double x, double y) { return geometry::outsideBy(site, x, y) <= 0.0; };
    if (!onSite(p.startX, p.startY)) {
        return fail(MapProblemError::kStartOffSite);
    }
    if (!onSite(p.goalX, p.goalY)) {
        return fail(MapProblemError::kGoalOffSite);
    }
    // Grow every polygon in use and every seen hazard; rank by distance to the straight line.
    MapObstacles local;
    MapObstacles* candidates = obstacles != nullptr ? obstacles : &local;
    candidates->clear();
    const MapProblemError mapError = request.site.map != nullptr
                                         ? addSiteRocks(request.site, p, radius, candidates, report)
                                         : addMapPolygons(map, p, radius, candidates, report);
    if (mapError != MapProblemError::kNone) {
        return fail(mapError);
    }
    addSeenHazards(request, p, radius, candidates, report);
    selectObstacles(candidates, &p, report);
    if (!core::isOk(checkProblem(p))) {
        return fail(MapProblemError::kBadProblem);
    }
    *out = p;
    return core::Status::kOk;
}

bool keepOutNearPath(const site_map::SiteMap& map, const double* meanX, const double* meanY, std::size_t points,
                     double reachM) {
    const std::size_t zones = map.keepOutCount();
    for (std::size_t z = 0; z < zones; ++z) {
        // Convex and counter-clockwise: the image check refused any other.
        const site_map::KeepOut& zone = map.keepOut(z);
        const std::size_t n = zone.count < site_map::kMaxKeepOutVertices ? zone.count : site_map::kMaxKeepOutVertices;
        Point2 polygon[site_map::kMaxKeepOutVertices];
        for (std::size_t v = 0; v < n; ++v) {
            polygon[v] = Point2{static_cast<double>(zone.x[v]), static_cast<double>(zone.y[v])};
        }
        for (std::size_t k = 0; k + 1 < points; ++k) {
            const Point2 a{meanX[k], meanY[k]};
            const Point2 b{meanX[k + 1], meanY[k + 1]};
            if (geometry::segmentConvexPolygonDistanceSquared(a, b, polygon, n) <= reachM * reachM) {
                return true;
            }
        }
    }
    return false;
}

bool addRocksNearPath(const SiteCorridor& site, const tables::RoverGeometryTable& geometry, const CcProblem& problem,
                      const double* meanX, const double* meanY, std::size_t points, double reachM,
                      MapObstacles* obstacles, std::size_t* added) {
    *added = 0;
    if (site.map == nullptr || site.query == nullptr || points > kMaxPlanSteps + 1) {
        return false;
    }
    Point2 path[kMaxPlanSteps + 1];
    for (std::size_t k = 0; k < points; ++k) {
        path[k] = Point2{meanX[k], meanY[k]};
    }
    const std::size_t before = obstacles->polygons;
    bool startInside = false;
    const MapProblemError e = addSiteRocksNear(*site.map, site.query, path, points, reachM, problem,
                                               rse::geometry::clearanceRadiusM(geometry), false, obstacles, &startInside);
    *added = obstacles->polygons - before;
    return e == MapProblemError::kNone;
}

}  // namespace rse::deliberative

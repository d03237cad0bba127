// From what the rover knows to the planning problem: the coarse map (table 9),
// the planner and geometry tables, the estimated start (mean and covariance) and
// a goal become a CcProblem (cc_problem.hpp) for the chance-constrained planner.
//
// - Obstacles: every coarse-map polygon grown by the rover's footprint radius
//   (each face moved out along its normal, and every corner turning by more
//   than 30 degrees cut by a bevel face tangent to the disc at the vertex,
//   sharpest first within kMaxObstacleFaces: every face supports the disc
//   sweep of the polygon, so a mean outside it keeps the rover's disc off the
//   rock, and a sharp corner no longer reaches radius / cos(turn / 2) out). The planner takes kMaxPlanObstacles; when the map holds more, the
//   ones the whole-map check forced in come first (PlanMaker, whole_map_check.hpp),
//   then the ones nearest the straight segment from start to goal; the rest are
//   left out of the problem but not out of the plan's risk: the whole-map check
//   bounds each one's risk against the plan before it is sent, and a plan whose
//   left-out obstacles carry more than a negligible share is planned again with
//   them in, or not sent.
// - Seen hazards (KnownHazardsMsg: the habitual layer's remembered discs): each
//   disc grown by the footprint radius becomes the regular octagon that
//   circumscribes it (kHazardFaces faces), so the plan and its legs keep the
//   rover's disc off everything the rover has seen, not only the orbital map.
//   They compete with the polygons for the planner's kMaxPlanObstacles slots by
//   the same ranking. A grown hazard that would contain the start or the goal
//   is grown less, so a rover that stopped close to a rock can still plan away
//   from it: the goal keeps kHazardEndClearanceM, the start that plus its own
//   chance-constraint tightening (PhiInv(1 - Delta / (2 N kMaxPlanObstacles))
//   sqrt(trace Sigma_0)); one that leaves no such room is left out (counted).
// - Site: the coarse map's bounds shrunk by the footprint radius.
// - Plant: PLANNER.horizon_steps steps, PLANNER.process_noise_sigma_m x the
//   request's noise factor per step,
//   Sigma_0 the estimate's (x, y) covariance block; allocation from the table.
//
// Pure: no bus, no events, no state.
#pragma once

#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/geometry/coarse_map.hpp"
#include "fsw/geometry/site_bounds.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/site_map/site_map.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::deliberative {

constexpr std::size_t kHazardFaces = 8;
// Clearance a start or goal keeps from an obstacle grown less for it.
constexpr double kHazardEndClearanceM = 0.05;

// Map polygons one problem's candidates may hold: the coarse map's 16, or the
// site map's rocks near a horizon's corridor (a 30 m horizon in a k = 0.10
// field has about 2 rocks of 1 m and more within 6 m of it; 64 is the
// densest field's share with room).
constexpr std::size_t kMaxMapPolygons = 64;
static_assert(kMaxMapPolygons >= geometry::kCoarseMapSlots, "every coarse-map polygon is a candidate");

// Site mode (the site map in force, docs/site_map.md): the rocks are the
// site map's within reachM of the corridor (the global route's stretch the
// horizon follows, from the start to the horizon's goal), not the coarse
// map's, and the site is the site map's.
struct SiteCorridor {
    const site_map::SiteMap* map = nullptr;     // null: the coarse map (COARSE_MAP) is the map
    site_map::SiteQuery* query = nullptr;       // the caller's query scratch
    const geometry::Point2* points = nullptr;   // the corridor, count points (at least 2)
    std::size_t count = 0;
    double reachM = 0.0;                        // rocks whose box comes within this of the corridor
};

struct PlanRequest {
    double startX = 0.0, startY = 0.0;
    double startCov[4] = {};   // (x, y) covariance, row major, m^2
    double goalX = 0.0, goalY = 0.0;
    double riskBound = 0.0;    // Delta
    // Factor on PLANNER.process_noise_sigma_m (>= 1): the deliberative layer
    // gives PLANNER.failed_drive_noise_factor while a drive is declared failed.
    double noiseFactor = 1.0;
    const msg::KnownHazard* hazards = nullptr;  // seen hazards (site frame), hazardCount of them
    std::size_t hazardCount = 0;                // at most msg::kMaxKnownHazards are read
    SiteCorridor site{};                        // site mode when site.map is set
};

// Why a problem could not be built.
enum class MapProblemError : std::uint8_t {
    kNone = 0,
    kBadRequest = 1,      // non-finite start, goal or covariance, Delta outside (0, 0.5), noise factor below 1
    kStartOffSite = 2,    // the start lies outside the site shrunk by the footprint
    kGoalOffSite = 3,     // the goal lies outside the site shrunk by the footprint
    kGoalInObstacle = 4,  // the goal lies inside a grown obstacle: no plan can end there
    kBadMap = 5,          // a polygon that is not convex or has no area (the table check should have refused it)
    kBadProblem = 6,      // the result failed checkProblem() (a table value out of the planner's range)
    kTooManyRocks = 7,    // site mode: more rocks near the corridor than kMaxMapPolygons (or a corridor not usable)
};
const char* toString(MapProblemError error);

struct MapProblemReport {
    MapProblemError error = MapProblemError::kNone;
    std::uint8_t obstaclesOnMap = 0;
    std::uint8_t obstaclesUsed = 0;
    std::uint8_t obstaclesDropped = 0;   // on the map, beyond kMaxPlanObstacles: left out of the problem
    bool startInObstacle = false;        // the start lies inside a grown obstacle (the planner will find no plan)
    std::uint8_t hazardsSeen = 0;        // usable hazards in the request
    std::uint8_t hazardsUsed = 0;        // of them, in the problem
    std::uint8_t hazardsShrunk = 0;      // grown less than the footprint (start or goal close by)
    std::uint8_t hazardsLeftOut = 0;     // bare disc on the start or goal, or not finite / not positive
};

// Every grown polygon and seen hazard that may enter the problem: the ones it
// holds and the ones it leaves out (the whole-map check bounds their risk).
struct MapObstacles {
    static constexpr std::size_t kCapacity = kMaxMapPolygons + msg::kMaxKnownHazards;
    PlanObstacle grown[kCapacity];
    double rank[kCapacity] = {};     // squared distance to the straight line from start to goal
    bool forced[kCapacity] = {};     // first into the problem: the whole-map check found its risk mattered
    bool inProblem[kCapacity] = {};
    std::uint16_t mapId[kCapacity] = {};  // a polygon's coarse-map slot or site-map rock (hazards: 0)
    std::size_t count = 0;
    std::size_t polygons = 0;        // grown[0 .. polygons) are the map's polygons, the rest seen hazards
    void clear();                    // no candidate, none forced
    std::size_t leftOut() const;     // candidates not in the problem
};

// kOk and *out filled, or kInvalidArgument with report->error saying why.
// *obstacles (when not null) gets every candidate and which the problem holds.
// Where a plan's start, goal and means must lie: the site shrunk by the rover's
// clearance radius (a start or goal outside it: kStartOffSite / kGoalOffSite).
geometry::SiteBox planningSite(const tables::CoarseMapTable& map, const tables::RoverGeometryTable& rover);
// The same for site mode: the site map's bounds shrunk by insetM.
geometry::SiteBox siteMapBox(const site_map::SiteMap& map, double insetM);
// The site mode's site when site is set, else the coarse map's, shrunk by insetM.
geometry::SiteBox siteFor(const tables::CoarseMapTable& map, const site_map::SiteMap* site, double insetM);

core::Status buildMapProblem(const tables::CoarseMapTable& map, const tables::PlannerTable& planner,
                             const tables::RoverGeometryTable& geometry, const PlanRequest& request,
                             CcProblem* out, MapProblemReport* report, MapObstacles* obstacles = nullptr);

// Site mode, before a plan's whole-map check: every site rock within reachM
// of the plan's means (meanX/meanY[0 .. points), its sampled path's centre
// line) that is not a candidate yet is added (grown, left out of the
// problem), so that the check bounds each one. False (some may have been
// added) when they do not fit in kMaxMapPolygons or the query is refused:
// the plan cannot be certified. *added: how many were added.
bool addRocksNearPath(const SiteCorridor& site, const tables::RoverGeometryTable& geometry, const CcProblem& problem,
                      const double* meanX, const double* meanY, std::size_t points, double reachM,
                      MapObstacles* obstacles, std::size_t* added);

// Site mode: some keep-out zone (its polygon) comes within reachM of the
// polyline (meanX, meanY)[0 .. points).
bool keepOutNearPath(const site_map::SiteMap& map, const double* meanX, const double* meanY, std::size_t points,
                     double reachM);

// The problem's obstacles chosen again from *obstacles: the forced ones first
// (nearest first), then the nearest, kMaxPlanObstacles in all, in candidate
// order; inProblem and the report's counts follow. The rest of *problem is kept.
void selectObstacles(MapObstacles* obstacles, CcProblem* problem, MapProblemReport* report);

}  // namespace rse::deliberative

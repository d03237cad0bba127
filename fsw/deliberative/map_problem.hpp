// From what the rover knows to the planning problem: the coarse map (table 9),
// the planner and geometry tables, the estimated start (mean and covariance) and
// a goal become a CcProblem (cc_problem.hpp) for the chance-constrained planner.
//
// - Obstacles: every coarse-map polygon grown by the rover's footprint radius
//   (each face moved out along its normal: the grown polygon contains the disc
//   sweep of the polygon, so a mean outside it keeps the rover's disc off the
//   rock). The planner takes kMaxPlanObstacles; when the map holds more, the
//   ones nearest the straight segment from start to goal are kept and the rest
//   are counted as dropped: the habitual layer still avoids every polygon
//   (its local map holds them all), so a dropped one costs a local detour, not
//   a collision.
// - Site: the coarse map's bounds shrunk by the footprint radius.
// - Plant: PLANNER.horizon_steps steps, PLANNER.process_noise_sigma_m per step,
//   Sigma_0 the estimate's (x, y) covariance block; allocation from the table.
//
// Pure: no bus, no events, no state.
#pragma once

#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::deliberative {

struct PlanRequest {
    double startX = 0.0, startY = 0.0;
    double startCov[4] = {};   // (x, y) covariance, row major, m^2
    double goalX = 0.0, goalY = 0.0;
    double riskBound = 0.0;    // Delta
};

// Why a problem could not be built.
enum class MapProblemError : std::uint8_t {
    kNone = 0,
    kBadRequest = 1,      // non-finite start, goal or covariance, or Delta outside (0, 0.5)
    kStartOffSite = 2,    // the start lies outside the site shrunk by the footprint
    kGoalOffSite = 3,     // the goal lies outside the site shrunk by the footprint
    kGoalInObstacle = 4,  // the goal lies inside a grown obstacle: no plan can end there
    kBadMap = 5,          // a polygon that is not convex or has no area (the table check should have refused it)
    kBadProblem = 6,      // the result failed checkProblem() (a table value out of the planner's range)
};
const char* toString(MapProblemError error);

struct MapProblemReport {
    MapProblemError error = MapProblemError::kNone;
    std::uint8_t obstaclesOnMap = 0;
    std::uint8_t obstaclesUsed = 0;
    std::uint8_t obstaclesDropped = 0;   // on the map, beyond kMaxPlanObstacles, farthest from the line
    bool startInObstacle = false;        // the start lies inside a grown obstacle (the planner will find no plan)
};

// kOk and *out filled, or kInvalidArgument with report->error saying why.
core::Status buildMapProblem(const tables::CoarseMapTable& map, const tables::PlannerTable& planner,
                             const tables::RoverGeometryTable& geometry, const PlanRequest& request,
                             CcProblem* out, MapProblemReport* report);

}  // namespace rse::deliberative

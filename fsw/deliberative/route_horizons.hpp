// Site mode's route and its horizons (docs/deliberative.md, "Site mode"):
// the global route over the site map (global_route.hpp) from the rover to the
// goal, then, one after another, the horizons the chance-constrained planner
// plans along it: from the rover to the route point kHorizonLengthM further
// along the route than the rover's place on it (or to the goal when it is
// within kLastHorizonFactor of that), with the route's stretch between as the
// corridor whose rocks the horizon's problem holds (map_problem.hpp).
//
// The rover's place on the route is its nearest point on the segments from
// the last place on (progress never goes back), so a rover pushed aside by a
// detour or a replan still finds its way on. A route is kept for its goal and
// the map revision it was found on; a new goal or a new map needs a new one.
//
// Time bound: step() is one slice of the search (kSliceWork); next() walks at
// most kMaxRoutePoints segments. Static: the search's arrays are members
// (about 2.8 MB: the task is static).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/global_route.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/site_map/site_map.hpp"

namespace rse::deliberative {

// How far along the route a horizon reaches: within the planner's 24 steps
// (1.25 m a step) and the hazard detector's view of the next stretch.
constexpr double kHorizonLengthM = 30.0;
// A horizon whose goal would leave less than this fraction of a horizon to
// the goal goes to the goal itself (no 3 m last horizon).
constexpr double kLastHorizonFactor = 1.25;
// Rocks whose box comes within this of a horizon's corridor are its
// problem's candidates (the plan's own neighbourhood is added before its
// check: whole_map_check.hpp, "Rocks far from the plan").
constexpr double kCorridorReachM = 6.0;
// The route keeps the footprint radius and this margin off every rock and
// zone, and prices rocks within this comfort beyond that.
constexpr double kRouteMarginM = 0.4;
constexpr double kRouteComfortM = 1.5;
// Keep-out zones are kept this much farther off: a horizon's plan within the
// far reach of a zone is not taken (whole_map_check.hpp), and the far reach
// is about 2 m at the default noise.
constexpr double kRouteZoneMarginM = 2.5;
// ROUTE chunks published in one run (the telemetry pipe takes them as they come).
constexpr std::size_t kRouteChunksPerRun = 4;
// Corridor points a horizon carries (its start, the route's points within it
// and its goal): 30 m of route at the 64 m sight limit holds a handful.
constexpr std::size_t kMaxCorridorPoints = 32;

struct Horizon {
    geometry::Point2 goal{0.0, 0.0};
    bool last = false;                 // goes to the route's goal
    geometry::Point2 corridor[kMaxCorridorPoints] = {};
    std::size_t count = 0;             // corridor points (>= 2)
};

class RouteHorizons {
public:
    // Starts the route from `from` to goal over map for a rover of this
    // footprint radius: kNone, or why not (no route then).
    RouteRefusal begin(const site_map::SiteMap& map, geometry::Point2 from, geometry::Point2 goal, double footprintRadiusM);
    // One slice of the search; true when it has ended.
    bool step();
    // True when a route reaches the goal.
    bool routed() const { return route_.state() == RouteState::kFound && valid_; }
    // A route found to this goal over this map revision.
    bool routes(geometry::Point2 goal, std::uint32_t revision) const;
    void forget() { valid_ = false; }

    // The next horizon from `from` (the rover's estimate); false without a route.
    bool next(geometry::Point2 from, Horizon* out);

    // The route found is to be told (ROUTE telemetry): numbered, its chunks
    // pending from the first.
    void announce(core::TimeNs foundAt, std::uint8_t goalIndex);
    // The next pending chunk of the route announced; false when none is left.
    bool nextChunk(msg::RouteChunkMsg* out);
    std::uint32_t routesAnnounced() const { return routeNumber_; }

    const GlobalRoute& route() const { return route_; }
    std::size_t progress() const { return progress_; }
    // Puts back progress a look-ahead's next() moved (horizon_look_ahead.hpp):
    // the only way it goes back.
    void rewind(std::size_t progress) { progress_ = progress < progress_ ? progress : progress_; }

private:
    GlobalRoute route_;
    geometry::Point2 goal_{0.0, 0.0};
    std::uint32_t revision_ = 0;
    const site_map::SiteMap* map_ = nullptr;
    std::size_t progress_ = 0;   // the route segment the rover was last placed on
    bool valid_ = false;
    // ROUTE: the route announced and its next chunk.
    std::uint32_t routeNumber_ = 0;
    core::TimeNs foundAt_ = 0;
    std::uint8_t goalIndex_ = 0;
    std::size_t nextChunk_ = 0;
    std::size_t chunkCount_ = 0;
};

}  // namespace rse::deliberative

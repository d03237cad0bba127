// Site mode's route and its horizons (docs/deliberative.md, "Site mode"):
// the global route over the site map (global_route.hpp) from the rover to the
// goal, then, one after another, the horizons the chance-constrained planner
// plans along it: from the rover to the route point PLANNER.site_horizon_m
// further along the route than the rover's place on it (or to the goal when it
// is within site_last_horizon_factor of that), with the route's stretch between as the
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

// The route's and the horizons' parameters (PLANNER's site_* fields:
// docs/tables.md), given at each call so an uploaded table applies from the
// next route or horizon on.
struct RouteMargins {
    double marginM = 0.4;       // site_route_margin_m: beyond the footprint radius, off every rock and zone
    double comfortM = 1.5;      // site_route_comfort_m: rocks priced within this beyond the clearance
    double zoneMarginM = 2.5;   // site_route_zone_margin_m: zones kept this much farther off
};
struct HorizonReach {
    double lengthM = 30.0;      // site_horizon_m: how far along the route a horizon reaches
    double lastFactor = 1.25;   // site_last_horizon_factor: the goal itself when less than this x lengthM remains
};
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
    RouteRefusal begin(const site_map::SiteMap& map, geometry::Point2 from, geometry::Point2 goal, double footprintRadiusM,
                       const RouteMargins& margins);
    // One slice of the search; true when it has ended.
    bool step();
    // True when a route reaches the goal.
    bool routed() const { return route_.state() == RouteState::kFound && valid_; }
    // A route found to this goal over this map revision.
    bool routes(geometry::Point2 goal, std::uint32_t revision) const;
    void forget() { valid_ = false; }

    // The next horizon from `from` (the rover's estimate); false without a route.
    bool next(geometry::Point2 from, const HorizonReach& reach, Horizon* out);

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

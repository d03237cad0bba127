// The global route (issue 31, item 2; docs/deliberative.md, "Global route"):
// a way from the rover to the goal over the whole site map (site_map.hpp),
// found before the chance-constrained planner plans the horizon in front of
// the rover along it.
//
// How. Theta* (Nash, Daniel, Koenig and Felner, 2007: A* whose node may take
// its grandparent as parent when the straight line between them is clear, so
// routes run at any angle, not only the lattice's eight) on a square lattice
// of nodes over the site shrunk by the clearance, with the start and the goal
// as two more nodes. A node is usable when its point keeps params.clearanceM
// off every rock and keep-out zone; an edge when the segment does (exact
// segment-to-polygon distances of the rocks rocksNearSegment lists). Risk is
// priced in: an edge costs its length plus, for each rock it passes closer
// than params.comfortM, proximityCost x how close (1 at the clearance, 0 at
// comfort) x the stretch it passes it along (the chord of the comfort circle
// at the least distance, or the edge when shorter). The
// heuristic is the straight-line distance x heuristicWeight (1: the cheapest
// route on the lattice; w > 1: at most w times it, found sooner).
//
// Bounded and sliced. step(slice) expands nodes until the slice's work units
// are spent (cc_work_units.hpp's scale: ~0.45 ns a unit on the development
// host); one expansion is bounded (at most 9 neighbours, the start 17, two sight
// lines each, a sight line at most kMaxSightM long and kMaxSightRocks rocks
// measured), and a search by params.workBudget: when it is spent the search
// ends with the best answer so far (kBudgetSpent: the route to the expanded
// node nearest the goal). A sight line with more rocks near it than
// kMaxSightRocks is taken as blocked (counted), never measured in part.
//
// Memory (static): 21 bytes a node for kMaxRouteNodes + 2 nodes (cost, key,
// parent, heap position, heap slot, flags), 16 bytes a route point, a site
// map query scratch: about 2.81 MB (kGlobalRouteBytes, checked in test_global_route). The lattice
// spacing is params.spacingM or, on a site that would need more nodes, the
// smallest spacing that fits kMaxRouteNodes (a 1 km x 1 km site: 2.77 m).
//
// Pure: no bus, no events; the caller reports.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/site_map/site_map.hpp"

namespace rse::deliberative {

constexpr std::size_t kMaxRouteNodes = 131072;
constexpr std::size_t kMaxRoutePoints = 1024;   // ROUTE: at most 32 chunks of 32
constexpr double kMinRouteSpacingM = 0.25;
// Theta*'s sight lines are tried up to this long; beyond, the node's own edge
// is taken (a longer route vertex gains little and costs a long band query).
constexpr double kMaxSightM = 64.0;
// Rocks one sight line measures exactly: beyond, it is taken as blocked.
constexpr std::size_t kMaxSightRocks = 128;

// Work units (cc_work_units.hpp's scale) the route charges: measured by
// bench_global_route (ns a unit on fields of 100 to 8 192 rocks).
constexpr std::uint64_t kRouteExpandWork = 500;   // a heap pop and its pushes
constexpr std::uint64_t kRouteCellWork = 30;      // a grid cell of a band query
constexpr std::uint64_t kRouteRefWork = 20;       // a rock reference examined
constexpr std::uint64_t kRouteEdgeWork = 100;     // a segment-to-edge distance
constexpr std::uint64_t kRouteNodeResetWork = 10;  // a node cleared at start

struct RouteParams {
    double clearanceM = 0.8;       // the rover's disc radius and a margin: every route point keeps it off rocks and zones
    double comfortM = 2.5;         // closer than this to a rock an edge costs more (> clearanceM)
    double proximityCost = 1.0;    // the added cost of a rock passed at the clearance, per metre passed (>= 0)
    double spacingM = 1.0;         // the lattice spacing wanted (>= kMinRouteSpacingM)
    double heuristicWeight = 1.0;  // >= 1: the route costs at most this times the cheapest on the lattice
    double zoneMarginM = 0.0;      // keep-out zones are kept this much farther off than rocks (>= 0)
    std::uint64_t workBudget = 400000000;  // the whole search (~0.2 - 0.4 s on the development host)
};

enum class RouteState : std::uint8_t {
    kIdle = 0,
    kSearching = 1,
    kFound = 2,        // the route reaches the goal
    kNoRoute = 3,      // every node the start reaches expanded, the goal not among them
    kBudgetSpent = 4,  // the budget ran out: the route goes to the expanded node nearest the goal
    kRefused = 5,      // start() refused (refusal() says why)
};
const char* toString(RouteState state);

enum class RouteRefusal : std::uint8_t {
    kNone = 0,
    kNoMap = 1,          // no site map in force
    kBadParams = 2,      // a parameter not finite or out of its range
    kBadPoint = 3,       // the start or the goal not finite
    kStartOffSite = 4,   // the start outside the site shrunk by the clearance
    kGoalOffSite = 5,
    kStartBlocked = 6,   // the start within the clearance of a rock or zone
    kGoalBlocked = 7,
    kRouteTooLong = 8,   // the route found has more than kMaxRoutePoints points
};
const char* toString(RouteRefusal refusal);

struct RouteStats {
    std::uint32_t columns = 0, rows = 0;   // the lattice
    double spacingM = 0.0;
    std::uint32_t expansions = 0;
    std::uint32_t sightLines = 0;          // segments measured
    std::uint32_t sightLinesCrowded = 0;   // ... taken as blocked: more than kMaxSightRocks rocks near
    std::uint32_t nodesBlocked = 0;        // lattice nodes found within the clearance
    std::uint32_t steps = 0;               // step() calls that searched
    std::uint64_t work = 0;                // work units, start() included
    std::uint64_t maxStepWork = 0;         // the most one step() did
};

class GlobalRoute {
public:
    // Starts a search from start to goal on map (which must outlive the
    // search and not change during it). kNone, or the refusal (state()
    // kRefused, no route).
    RouteRefusal start(const site_map::SiteMap& map, geometry::Point2 start, geometry::Point2 goal,
                       const RouteParams& params);
    // Expands nodes until sliceWork work units are spent or the search ends;
    // true when it has ended (state() not kSearching).
    bool step(std::uint64_t sliceWork);

    RouteState state() const { return state_; }
    RouteRefusal refusal() const { return refusal_; }
    const RouteStats& stats() const { return stats_; }
    // The route (kFound or kBudgetSpent): points from the start to the goal
    // (or to the node nearest it), at least two.
    std::size_t pointCount() const { return pointCount_; }
    geometry::Point2 point(std::size_t i) const { return points_[i < kMaxRoutePoints ? i : 0]; }
    double lengthM() const { return lengthM_; }
    double cost() const { return cost_; }

    // The usable-edge test and price the search uses (exposed for tests and
    // for checking a route against the map): the edge's cost, or a negative
    // value when the segment comes within the clearance of a rock or zone or
    // is crowded.
    double edgeCost(geometry::Point2 a, geometry::Point2 b);

private:
    static constexpr std::uint32_t kNone = 0xFFFFFFFFU;
    // The start's neighbours: the 4 x 4 lattice nodes round it and the goal.
    static constexpr std::size_t kMaxNeighbours = 17;

    // Lattice columns i0 .. i1 and rows j0 .. j1 (inclusive) round a point.
    struct Block {
        std::uint32_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
    };

    // The lattice over the shrunk site (spacingM or the least that fits
    // kMaxRouteNodes), every node cleared (false: it cannot fit); each zone's box.
    bool shapeLattice(double spacingM);
    void boxZones();
    geometry::Point2 nodePoint(std::uint32_t node) const;
    bool nodeUsable(std::uint32_t node);
    bool pointClear(geometry::Point2 p);
    void expand(std::uint32_t node);
    void relax(std::uint32_t from, std::uint32_t to);
    void offer(std::uint32_t node, std::uint32_t parent, double cost);
    void neighboursOf(std::uint32_t node, std::uint32_t* out, std::size_t* count) const;
    Block blockOf(geometry::Point2 p) const;
    double heuristic(std::uint32_t node) const;
    void finish(RouteState state, std::uint32_t last);

    // The open set: a binary heap of nodes on key_, with heapPos_.
    void push(std::uint32_t node);
    std::uint32_t pop();
    void siftUp(std::uint32_t at);
    void siftDown(std::uint32_t at);

    const site_map::SiteMap* map_ = nullptr;
    RouteParams params_{};
    geometry::Point2 origin_{0.0, 0.0};  // lattice node (0, 0)
    geometry::Point2 start_{0.0, 0.0};
    geometry::Point2 goal_{0.0, 0.0};
    double minX_ = 0.0, minY_ = 0.0, maxX_ = 0.0, maxY_ = 0.0;  // the site shrunk by the clearance
    std::uint32_t lattice_ = 0;    // lattice nodes (columns x rows); the start is lattice_, the goal lattice_ + 1
    Block goalBlock_{};            // lattice nodes that see the goal as a neighbour
    double zoneBox_[site_map::kMaxKeepOuts][4] = {};  // each zone's box: x min, y min, x max, y max
    std::uint32_t best_ = kNone;   // the expanded node nearest the goal
    double bestH_ = 0.0;
    RouteState state_ = RouteState::kIdle;
    RouteRefusal refusal_ = RouteRefusal::kNone;
    RouteStats stats_{};

    float cost_g_[kMaxRouteNodes + 2] = {};
    float key_[kMaxRouteNodes + 2] = {};
    std::uint32_t parent_[kMaxRouteNodes + 2] = {};
    std::uint32_t heapPos_[kMaxRouteNodes + 2] = {};
    std::uint32_t heap_[kMaxRouteNodes + 2] = {};
    std::uint8_t flags_[kMaxRouteNodes + 2] = {};
    std::uint32_t heapSize_ = 0;

    site_map::SiteQuery query_{};
    std::uint16_t near_[kMaxSightRocks] = {};

    geometry::Point2 points_[kMaxRoutePoints] = {};
    std::size_t pointCount_ = 0;
    double lengthM_ = 0.0;
    double cost_ = 0.0;
};

constexpr std::size_t kGlobalRouteBytes = sizeof(GlobalRoute);

}  // namespace rse::deliberative

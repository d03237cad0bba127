// What the deliberative layer tells the rest of the rover: the plan it is
// executing (for telemetry: PLAN packet), every plan's mean path with what a
// ground needs to draw its risk ellipses (PLAN_PATH packet) and, when no plan
// within the risk bound exists, the request to safe the rover (the "call home").
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

constexpr std::size_t kPlanPathMeans = 25;   // mu_0 .. mu_N of a plan: deliberative::kMaxPlanSteps + 1 (checked there)
constexpr std::size_t kRouteChunkPoints = 32;  // route points a RouteChunkMsg (ROUTE packet) carries
constexpr std::size_t kPlanStatusLegs = 12;  // legs shown, from the current one (PLAN telemetry: it must fit 512 bytes)

enum class DeliberativeState : std::uint8_t {
    kIdle = 0,        // no goals, or not in AUTONOMOUS
    kWaiting = 1,     // goals pending: waiting for a usable pose (or AUTONOMOUS)
    kPlanning = 2,    // the chance-constrained planner is running (sliced)
    kExecuting = 3,   // legs handed to the habitual layer one at a time
    kCalledHome = 4,  // no plan within the bounds: rover safed, operator alerted; waits for new goals
    kComplete = 5,    // every goal reached
};

// Why the rover called home (kNone otherwise).
enum class CallHomeReason : std::uint8_t {
    kNone = 0,
    kNoPlanWithinRisk = 1,  // no plan even at the risk bound relaxed to PLANNER.risk_relax_limit
    kGoalUnreachable = 2,   // the goal is off the site or inside an obstacle; or the start is off the site
    kReplansExhausted = 3,  // PLANNER.replan_limit replans of one goal failed up again
    kInsufficientPower = 4, // a leg's energy bound would pass PLANNER.bound_relax_limit, replans exhausted
    kMobilityLost = 5,      // a drive declared failed: the rover cannot drive (the interlock holds every drive)
    kFaultUnrecovered = 6,  // fault protection used every attempt of a response (docs/fault_protection.md)
    kPlanNoMethod = 7,      // the plan executive: no method of the running plan remains (docs/plan_executive.md)
};

struct PlanLeg {
    double xM;          // where the leg ends
    double yM;
    double lengthM;     // not-to-exceed length handed to the habitual layer
    double energyJ;     // not-to-exceed energy
    double powerW;      // not-to-exceed drive power at the cruise speed (before any relaxation)
    double risk;        // sum of the deltas of the plan segments in this leg
};

// Published on every change of state, plan or leg, and at 1 Hz.
struct PlanStatusMsg {
    static constexpr core::MsgId kMsgId = ids::kPlanStatus;
    std::int64_t timeNs;
    DeliberativeState state;
    std::uint8_t planStatus;       // deliberative::CcStatus of the plan in force (2 kNoPlan when none)
    CallHomeReason callHome;
    std::uint8_t goalIndex;        // goal being planned for or driven to
    std::uint8_t goalCount;
    std::uint8_t legIndex;         // current leg within the plan
    std::uint8_t legCount;         // legs of the plan
    std::uint8_t shownLegs;        // legs[0..shownLegs) = legs legIndex.. of the plan
    double riskBound;              // the operator's Delta
    double riskInForce;            // Delta after relaxation (>= riskBound)
    double riskUsed;               // sum of the plan's deltas
    double planLengthM;            // Euclidean length of the plan's mean path
    double planGap;                // (search's best cost - its proven lower bound) / best cost: 0 .. 1; the
                                   // most a budget plan (planStatus 1) may be above the best plan for the
                                   // search's allocation; relativeGap (0.002) when proven
    std::uint32_t plansMade;
    std::uint32_t replans;         // plans made from the current state after a fail-up
    std::uint32_t riskRelaxations;
    std::uint32_t boundRelaxations;
    std::uint32_t callHomes;
    std::uint32_t currentLegId;    // legId of the leg in force (0: none)
    std::uint32_t goalRevision;    // revision of the goal list in force (GoalListMsg or PlanGoalMsg)
    // Site mode (docs/deliberative.md "Site mode"), counts since start.
    std::uint8_t siteMode;         // 1: a site map in force: a route, then horizons along it
    std::uint8_t pad2[3];
    std::uint32_t routesFound;
    std::uint32_t routesFailed;
    std::uint32_t horizonsReached;        // horizon ends reached (the next horizon then driven)
    std::uint32_t horizonsDrivenThrough;  // ... whose next leg went out at once (planned while driving)
    std::uint32_t horizonStops;           // ... the rover stopped at to plan the next horizon
    std::uint32_t lookAheadsStarted;      // next horizons planned while driving, restarts included
    std::uint32_t lookAheadsDropped;      // ... dropped (stale after a sighting: planned again; or for good)
    PlanLeg legs[kPlanStatusLegs];
};

// One per plan made: published exactly when PlanStatusMsg::plansMade counts
// (a plan with a path that was cut into legs, and a plan with a path made
// while the interlock holds every drive, which calls home for lost mobility).
// A plan attempt that found no path (no plan within the risk in force, a
// bad problem, a path that could not be cut into legs) counts in no
// plansMade and publishes none. Carries the plan's mean path and what makes
// its covariance, Sigma_t = startCov + t processSigmaM^2 I (cc_problem.hpp),
// so a ground can draw the plan with its risk ellipses (PLAN_PATH packet).
// 504 bytes: within kBusMaxPayload (1024).
struct PlanPathMsg {
    static constexpr core::MsgId kMsgId = ids::kPlanPath;
    std::int64_t timeNs;           // when the planner finished
    std::uint32_t planNumber;      // the PlanStatusMsg::plansMade value this plan made (1 for the first)
    std::uint8_t status;           // deliberative::CcStatus: 0 optimal, 1 feasible (budget plan)
    std::uint8_t steps;            // N: meanX/Y[0..steps] are the means, the rest 0
    std::uint8_t obstaclesInProblem;  // obstacles the planner's problem held (<= kMaxPlanObstacles)
    std::uint8_t obstaclesLeftOut;    // map polygons and seen hazards it left out (whole-map checked)
    double riskBound;              // Delta planned to (the risk in force, after any relaxation)
    double riskUsed;               // the plan's certified bound on P(collision) against the whole map
    double riskLeftOut;            // of riskUsed, the left-out obstacles' share (whole_map_check.hpp)
    double lengthM;                // Euclidean length of the mean path (CcPlan::euclideanLengthM)
    double processSigmaM;          // sigma per step
    double startCov[4];            // Sigma_0, row major, m^2
    double goalX;                  // mu_N as asked (the goal)
    double goalY;
    double meanX[kPlanPathMeans];  // mu_0 (the start planned from) .. mu_N
    double meanY[kPlanPathMeans];
};

// Site mode: a global route found over the site map (docs/deliberative.md,
// "Site mode"), in chunks of kRouteChunkPoints points, chunk 0 first; the
// route's points are chunk k's points[0 .. count) at k * kRouteChunkPoints.
struct RouteChunkMsg {
    static constexpr core::MsgId kMsgId = ids::kRouteChunk;
    std::int64_t timeNs;         // when the route was found
    std::uint32_t routeNumber;   // routes found since start, this one included (1 for the first)
    std::uint16_t pointCount;    // the whole route's points (>= 2)
    std::uint8_t chunkIndex;     // 0 .. chunkCount - 1
    std::uint8_t chunkCount;
    std::uint8_t goalIndex;      // the goal in hand (PlanStatusMsg.goalIndex)
    std::uint8_t count;          // points in this chunk
    std::uint8_t pad[6];
    double lengthM;              // the route's length
    double goalX;                // the goal it reaches
    double goalY;
    float x[kRouteChunkPoints];
    float y[kRouteChunkPoints];
};

// Put the rover in SAFE and hold it there: sent once per call home.
struct SafeRequestMsg {
    static constexpr core::MsgId kMsgId = ids::kSafeRequest;
    std::int64_t timeNs;
    CallHomeReason reason;
    std::uint8_t pad[7];
};

}  // namespace rse::msg

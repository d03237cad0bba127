// The deliberative layer's planning problem and its answer: a chance-constrained
// path for a 2-D single integrator among convex polygonal obstacles (the
// simplified p-Sulu of the RSE paper). One header both sides read: the flight
// planner (fsw/deliberative/) and the host-only exact reference and Monte Carlo
// checker of the benchmark (unit_test/bench/). docs/deliberative.md derives it.
//
// Plant, over steps t = 0 .. N-1:
//   x_{t+1} = x_t + u_t + w_t,   w_t ~ N(0, sigma^2 I),   x_0 ~ N(mu_0, Sigma_0)
// so the means follow mu_{t+1} = mu_t + u_t and the covariance does not depend
// on the controls: Sigma_t = Sigma_0 + t sigma^2 I. The decision variables are
// the means mu_1 .. mu_N; mu_N = goal.
//
// Obstacles: convex polygons, each given by its faces as outward unit normals a_j
// and offsets b_j, so the obstacle is {x : a_j . x < b_j for all j} and its safe
// region is the union over j of the half-planes {x : a_j . x >= b_j}.
//
// Segment constraints (risk selection): for every segment t (mu_t -> mu_{t+1})
// and obstacle i one face j = face[t][i] is chosen, and both ends are tightened
// into its half-plane:
//   a_j . mu_t     >= b_j + PhiInv(1 - delta[t][i][0]) sqrt(a_j' Sigma_t a_j)
//   a_j . mu_{t+1} >= b_j + PhiInv(1 - delta[t][i][1]) sqrt(a_j' Sigma_{t+1} a_j)
// A sampled segment that touches obstacle i leaves the half-plane, and a
// segment's distance to a line is least at one of its ends, so
//   P(segment t meets obstacle i) <= delta[t][i][0] + delta[t][i][1]
// and by Boole's inequality P(the path meets any obstacle) <= sum of all delta.
// The risk bound Delta caps that sum, or (optimised allocation, issue 15) the
// tighter certified bound of plan_risk.hpp, which also needs every end to
// meet its delta's margin but bounds each (segment, obstacle) pair from the
// means and counts Boole only across pairs. Constraining both ends of every segment
// (not the waypoints alone) is what keeps a path from cutting an obstacle's
// corner between two steps.
//
// Objective: path length of the means in the regular kPolygonNormSides-gon norm,
// sum_t max_k c_k . (mu_{t+1} - mu_t) with c_k = (cos 2 pi k / K, sin 2 pi k / K):
// a linear program once the faces are fixed, and within 1 - cos(pi / K) (1.9 %
// for K = 16) below the Euclidean length. The exact reference (a MILP) solves
// the same objective.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rse::deliberative {

constexpr std::size_t kMaxPlanSteps = 24;        // N
constexpr std::size_t kMaxPlanObstacles = 8;     // M
constexpr std::size_t kMaxObstacleFaces = 8;
constexpr std::size_t kPolygonNormSides = 16;    // K

struct PlanObstacle {
    std::uint8_t id = 0;          // the coarse map's id (or the instance's)
    std::uint8_t faceCount = 0;   // 3 .. kMaxObstacleFaces
    double normalX[kMaxObstacleFaces] = {};  // outward unit normal a_j
    double normalY[kMaxObstacleFaces] = {};
    double offset[kMaxObstacleFaces] = {};   // b_j: the face is a_j . x = b_j
};

enum class RiskAllocation : std::uint8_t {
    kEvenSplit = 0,   // every delta = Delta / (2 N M): the RSE paper's split
    kOptimised = 1,   // delta moved to where it shortens the path, sum still <= Delta
};

struct CcProblem {
    std::uint8_t steps = 0;              // N, 1 .. kMaxPlanSteps
    double startX = 0.0, startY = 0.0;   // mu_0
    double startCov[4] = {};             // Sigma_0, row major, m^2 (symmetric, PSD)
    double processSigmaM = 0.0;          // sigma per step
    double goalX = 0.0, goalY = 0.0;     // mu_N
    double xMin = 0.0, xMax = 0.0, yMin = 0.0, yMax = 0.0;  // the means stay inside
    double riskBound = 0.0;              // Delta, (0, 0.5)
    RiskAllocation allocation = RiskAllocation::kEvenSplit;
    std::uint8_t obstacleCount = 0;      // M, 0 .. kMaxPlanObstacles
    PlanObstacle obstacles[kMaxPlanObstacles];
};

enum class CcStatus : std::uint8_t {
    kOptimal = 0,       // proven optimal for the allocation used (flight: within the tolerance)
    kFeasible = 1,      // a plan within the risk bound, the budget ran out before proof
    kNoPlan = 2,        // no plan within the risk bound exists (proven) or none was found in budget
    kBadProblem = 3,    // the problem failed its checks (sizes, finiteness, covariance, Delta)
};

struct CcPlan {
    CcStatus status = CcStatus::kNoPlan;
    std::uint8_t steps = 0;
    double meanX[kMaxPlanSteps + 1] = {};   // mu_0 .. mu_N
    double meanY[kMaxPlanSteps + 1] = {};
    std::uint8_t face[kMaxPlanSteps][kMaxPlanObstacles] = {};
    double delta[kMaxPlanSteps][kMaxPlanObstacles][2] = {};  // risk at the segment's start and end
    // The certified bound on P(collision) (<= riskBound): per (segment, obstacle)
    // the smaller of its two deltas' sum (Boole) and plan_risk.hpp's bound from
    // the means, summed. With optimised allocation the deltas' own sum may pass
    // riskBound (the allocation is stretched until this bound reaches it).
    double riskUsed = 0.0;
    double segmentRisk[kMaxPlanSteps] = {};  // segment t's share of riskUsed
    double cost = 0.0;                      // the K-gon path length (m)
    double euclideanLengthM = 0.0;
};

}  // namespace rse::deliberative

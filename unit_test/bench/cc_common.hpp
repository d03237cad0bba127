// Host-only helpers shared by the chance-constrained planning benchmark: the
// instance generator (cc_instances), the exact MILP reference
// (cc_reference_milp) and the Monte Carlo checker (cc_monte_carlo), and usable
// by any test that wants to check a plan against fsw/deliberative/cc_problem.hpp
// independently of the planner that made it.
//
// Everything follows the problem definition in cc_problem.hpp:
//   Sigma_t = Sigma_0 + t sigma^2 I,
//   margin(t, a, delta) = PhiInv(1 - delta) sqrt(a' Sigma_t a),
//   segment t, obstacle i, face j holds when
//     a_j . mu_t     >= b_j + margin(t,     a_j, delta[t][i][0]) and
//     a_j . mu_{t+1} >= b_j + margin(t + 1, a_j, delta[t][i][1]),
//   cost = sum_t max_k c_k . (mu_{t+1} - mu_t), c_k = (cos 2 pi k / K, sin 2 pi k / K).
// No CBC here: this compiles for the host and for aarch64.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"

namespace rse::test::cc {

using deliberative::CcPlan;
using deliberative::CcProblem;
using deliberative::kMaxObstacleFaces;
using deliberative::kMaxPlanObstacles;
using deliberative::kMaxPlanSteps;
using deliberative::kPolygonNormSides;
using deliberative::PlanObstacle;

// ---- Gaussian
double normalCdf(double x);
// Phi^-1(p) for p in (0, 1) (Acklam's approximation + one Halley step on erfc:
// relative error ~1e-15). Returns -inf / +inf at 0 / 1 and NaN outside [0, 1].
double normalQuantile(double p);
// Phi^-1(1 - delta), computed as -Phi^-1(delta) so that tiny deltas keep their digits.
double normalUpperQuantile(double delta);

// ---- the problem's covariance and margins
// Sigma_t = Sigma_0 + t sigma^2 I (row major).
void stepCovariance(const CcProblem& problem, std::size_t t, double cov[4]);
// PhiInv(1 - delta) sqrt(a' Sigma_t a) for the unit normal a = (ax, ay).
double faceMargin(const CcProblem& problem, std::size_t t, double ax, double ay, double delta);

// One delta per (segment t, obstacle i, end e): e = 0 the segment's start
// (mu_t), e = 1 its end (mu_{t+1}). Entries beyond N x M are unused (0).
struct RiskSplit {
    double delta[kMaxPlanSteps][kMaxPlanObstacles][2] = {};
    double total(const CcProblem& problem) const;
};
// Delta / (2 N M) everywhere (the RSE paper's split); all zero when M = 0.
RiskSplit evenSplit(const CcProblem& problem);
// The deltas a plan reports (CcPlan::delta).
RiskSplit splitOf(const CcPlan& plan);

// ---- path length
double kgonLength(const double* meanX, const double* meanY, std::size_t steps);
double euclideanLength(const double* meanX, const double* meanY, std::size_t steps);

// ---- polygon geometry (obstacle = {x : a_j . x < b_j for all j}, an open set)
struct Point {
    double x = 0.0;
    double y = 0.0;
};
// max_j (a_j . p - b_j): > 0 outside (p is in the safe half-plane of some face),
// < 0 strictly inside (minus the depth to the nearest face line).
double obstacleSlack(const PlanObstacle& obstacle, double x, double y);
bool pointInObstacle(const PlanObstacle& obstacle, double x, double y);
// Exact: does the closed segment p0 -> p1 meet the open polygon? (Clips the
// segment's parameter interval against every face; touching a face or a
// vertex from outside is not a collision.)
bool segmentIntersectsObstacle(const PlanObstacle& obstacle, double x0, double y0, double x1,
                               double y1);
// The polygon's vertices in the order of its faces (vertex k = face k - 1
// meets face k, so face k is the edge vertex k -> vertex k + 1), or an empty vector when the faces are not a closed convex
// polygon listed counter-clockwise with every face an edge of positive length.
std::vector<Point> obstacleVertices(const PlanObstacle& obstacle);
// The obstacle whose faces are the edges of this convex polygon (vertices
// counter-clockwise, 3 .. kMaxObstacleFaces of them; face k is the edge
// vertex k -> vertex k + 1, so obstacleVertices gives the vertices back).
PlanObstacle obstacleFromVertices(const std::vector<Point>& ccwVertices, std::uint8_t id);
// Axis-aligned box [x0, x1] x [y0, y1]; faces bottom, right, top, left.
PlanObstacle boxObstacle(double x0, double y0, double x1, double y1, std::uint8_t id);

// ---- checks
// Empty when the problem is well formed (sizes, finiteness, unit normals,
// closed convex CCW obstacles, PSD Sigma_0, sigma >= 0, Delta in (0, 0.5),
// start and goal inside the site); otherwise what is wrong.
std::string validateProblem(const CcProblem& problem);

// The segment constraints of a path for a given risk split, face free: for
// each (t, i) the best face's min over both ends of (a . mu - b - margin),
// then the minimum of that over all (t, i). >= -tolerance means the path meets
// every segment constraint with some face; +inf when M = 0. (*worstT, *worstI)
// get the binding pair when non-null.
double segmentConstraintSlack(const CcProblem& problem, const double* meanX, const double* meanY,
                              const RiskSplit& split, std::size_t* worstT = nullptr,
                              std::size_t* worstI = nullptr);
// The same with the faces and deltas the plan reports (CcPlan::face, delta).
double planReportedSlack(const CcProblem& problem, const CcPlan& plan);
// Waypoints only: for waypoint w and obstacle i the best face's
// a . mu_w - b - margin(w, a, delta_w) with delta_w the smallest delta of the
// segment ends at w. The constraint the waypoint-only reference enforces.
double waypointConstraintSlack(const CcProblem& problem, const double* meanX, const double* meanY,
                               const RiskSplit& split);
// Largest violation of the site bounds by mu_1 .. mu_{N-1} (<= 0 when inside).
double siteBoundViolation(const CcProblem& problem, const double* meanX, const double* meanY);
// Do any of the mean segments meet any obstacle (the deterministic path)?
bool meanPathHitsObstacle(const CcProblem& problem, const double* meanX, const double* meanY);

// ---- optimality proofs (the benchmark's CBC passes)
// What one exact pass (e.g. CBC unaided, or CBC under a cutoff) says about the
// optimum of an instance.
struct ProofPass {
    bool ran = false;
    bool proven = false;           // its plan's cost is the proven optimum
    bool noneBelowCutoff = false;  // proven: no plan costs less than `cutoff`
    double cost = 0.0;             // its plan's cost (+inf or anything without a plan; used only when proven)
    double cutoff = 0.0;           // used only with noneBelowCutoff
    double bound = 0.0;            // a lower bound on the optimum (used when finite and > 0)
};
// Where a gap comes from, best first.
enum class GapSource : std::uint8_t {
    kNone = 0,           // no pass gives an optimum or a positive bound: no gap
    kProvenUnaided = 1,  // the first pass proved the optimum
    kProvenAided = 2,    // the second pass proved an optimum below its cutoff
    kProvenByCutoff = 3, // the second pass proved nothing costs less than its cutoff
    kBound = 4,          // neither proved: to the best (largest) lower bound of both, an upper bound on the gap
};
struct GapVerdict {
    GapSource source = GapSource::kNone;
    double gap = 0.0;        // (cost - reference) / reference; +inf when cost is not finite (no plan); NaN with kNone
    double reference = 0.0;  // the optimum, the cutoff or the bound
    bool proven() const {
        return source == GapSource::kProvenUnaided || source == GapSource::kProvenAided ||
               source == GapSource::kProvenByCutoff;
    }
};
// The gap of a plan of cost `cost` to the optimum as the passes establish it:
// the unaided proof first, then the aided pass's proven optimum, then its
// proof that nothing costs less than its cutoff (the optimum is >= cutoff, so
// the gap is at most max(0, (cost - cutoff) / cutoff): that is the value
// given), else the gap to the larger of the two passes' lower bounds.
GapVerdict combineProofs(double cost, const ProofPass& unaided, const ProofPass& aided);
// Do two passes agree within the relative tolerance? A proven optimum of one
// must not lie below the other's lower bound (bound, or cutoff when
// noneBelowCutoff) nor, when both proved, differ from the other's optimum.
bool proofsConsistent(const ProofPass& a, const ProofPass& b, double tolerance);
// The cutoff that proves or refutes a plan of this cost: cost x (1 + tolerance).
double cutoffFor(double cost, double tolerance);

// ---- statistics (the benchmark's summaries)
// The q-quantile of the values, q in [0, 1], interpolated linearly between the
// order statistics (q = 0.5 the median, 0 the least, 1 the largest; q outside
// [0, 1] is clamped); NaN when there are no values. An order statistic hit
// exactly is returned as it is (so +inf among the values is fine).
double quantile(std::vector<double> values, double q);

}  // namespace rse::test::cc

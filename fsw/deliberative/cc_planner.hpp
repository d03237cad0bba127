// The deliberative layer's chance-constrained path planner (cc_problem.hpp,
// docs/deliberative.md): a bounded, anytime branch and bound over face
// assignments, seeded from visibility graphs, then risk allocation.
//
// Search. A node assigns faces to some (segment, obstacle) pairs; its bound is
// the LP (cc_lp.hpp) with only those pairs' rows, the even-split margins and
// the rest of the disjunctions dropped, warm-started from its parent's basis
// (LpSolver's dual simplex: a child only adds two rows) and cut off as soon
// as its dual bound reaches the prune threshold. At a node's optimum every
// unassigned pair is scored by max_j min(slack of its two ends on face j):
// when no pair is violated the node's path is a plan (its faces are the
// assigned ones plus, for each other pair, its best face) and, as the bound
// of its subtree, the best there. Otherwise the search branches on the most
// violated pair, one child per face, least violated face first (the
// guide's face before them, see Seed), depth first. A node whose bound reaches
// incumbent (1 - relativeGap) is pruned, so kOptimal means optimal within
// relativeGap (default 0.2 %) for the even split. Going back to a level
// restores its parent's A_B^-1 from a ring of saved factors (the deepest
// levels; older ones are refactorised from their saved basis).
//
// Fixed ends. With kOptimised, a start or goal end that needs more risk on
// its best face than the even split gives gets its need, and the other ends
// share the rest evenly (splitFixedEnds; the search's "even split" below is
// that split). kEvenSplit keeps Delta' / (2 N M) everywhere.
//
// Presolve. The pairs of the first and last segments have an end at the
// fixed start or goal; the faces that end misses are out. A pair with no face
// left proves that there is no plan (kNoPlan, at once: for kOptimised only
// when the fixed ends' needs pass Delta, a proof for any allocation); a pair
// with one face left is fixed at the root.
//
// Hint. setSeedHint(): an earlier plan's faces, re-solved at this problem's
// margins, as the first seed (e.g. the plan at a looser bound).
//
// Seed. Before the search, cheapest first. Visibility variants
// (kSeedVariants): the obstacles inflated by their margin at step N, N / 2 or
// 0 (margins grow with the step: the first is conservative, the last keeps
// gaps open that early steps can use); the shortest path (16-gon length) from
// start to goal in the visibility graph of the free space's corners (the
// inflated obstacles' vertices, where overlapping obstacles meet, where an
// obstacle leaves the site; Dijkstra, edges tested lazily); that path cut
// into N segments, either shared among its legs by length or, "front-loaded",
// one per leg and the rest parked at the goal (the path passes the obstacles
// while the margins are small); every pair given the face its two ends clear
// best, and the fixed-face LP solved; then "polish": each pair moves to the
// face its ends at the LP optimum clear best (the path stays feasible, so the
// cost cannot rise) and the LP is solved again, kPolishRounds (1) times.
// Order: variants N and N / 2, then (only when neither gave a plan) the
// layered seed, then variants 0 and front-loaded. The best seed is the first
// incumbent. The faces of the shortest seed path (even if its LP was
// infeasible) are the search's guide: at every branching the guide's face is
// tried first.
//
// Layered seed: complete on the problem's own constraints. For fixed faces
// the constraints on waypoint tau involve tau alone (half-planes at its
// margins, the site), so if any plan exists, one exists whose every waypoint
// is a vertex of its own feasible polygon: a crossing of two of layer tau's
// lines (each face moved out by its margin at tau, plus 2 kSafetyM; the site's
// sides). Layer 0 is the start; layer tau + 1 keeps each crossing that
// clears some face of every obstacle and is one segment from a point kept in
// layer tau (for every obstacle one face holds both ends: a 64-bit AND of
// the two points' face masks; a crossing whose mask is covered by a point
// already kept is dropped, since a point's moves depend on its mask alone);
// the goal is tried first in every layer, and
// once reached the remaining steps park on it (the goal clears its margin at
// N, the largest). The path found (fewest steps to the goal) gets the faces
// its ends clear best and is seeded like a visibility path. Exact while no
// layer fills its kMaxLayerPoints (layeredSeedFullLayers() counts those),
// up to the 2 um the lines are moved (and crossings of lines within 1e-9 of
// parallel, which are skipped); it stops at the first path, so it is a
// feasibility seed, not a short one (the search and the later variants
// shorten it). Cost: up to (8 M + 4)^2 / 2 crossings a layer, each a mask of
// M x 8 face tests and an AND per point of this layer and the one before.
//
// Risk allocation. kEvenSplit: delta = Delta' / (2 N M) at every end, with
// Delta' = Delta (1 - 1e-12) so that the sum of the 2 N M deltas, added in any
// order in double precision, stays <= Delta. kOptimised: iterative risk
// allocation (Ono & Williams 2008) on the best plan's faces with a budget B:
// every end whose constraint is slack moves 70 % of the way from its delta to
// the risk it has at the plan (computed 2 kSafetyM inside its slack, so the
// plan stays feasible), B minus the deltas is shared equally by the active
// ends, and the LP is solved again (warm: only right-hand sides change).
// Each round's plan is then certified (plan_risk.hpp, one segment a unit):
// per (segment, obstacle) the smaller of its two deltas and the bound from
// the means, summed. Kept when that is <= Delta' and the plan is shorter.
// Stretch (issue 15 item 3): B starts at Delta'; a round that certifies r
// raises it to B (Delta' / r) x 0.97 (at most x 8, and at most halfway to the
// least B that failed); a round that fails halves the way back to the
// largest B that certified and restarts from the best plan's deltas (scaled
// to B). So the deltas' own sum may pass Delta while the certified risk does
// not. At most iraRounds rounds; the rounds end once one gains nothing while
// the certified risk is within 90 % of Delta or B's bracket is within 2 %.
// Never worse than the even split's plan.
//
// Wide search (params.searchRiskScale > 1, kOptimised only): the search, its
// presolve, seeds and fixed ends run at a Boole budget of Delta x the scale,
// so a passage Boole's even split refuses at Delta can be found; those plans
// are not certified, plan() shows none of them (status kNoPlan), and the
// allocation starts at that budget and brings it down until a plan
// certifies within Delta (none: kNoPlan). Its plans are never kOptimal. The
// deliberative task runs it once when a plan at scale 1 finds nothing, before
// it relaxes Delta (deliberative_task.hpp, kWideSearchScale).
//
// Status. kOptimal: the search was exhausted (optimal within relativeGap for
// the even split; with kOptimised the allocation then shortened that plan, and
// the proof is about the even split's faces). kFeasible: a verified plan, the
// budget ran out first. kNoPlan: none found; proven when searchExhausted().
// Every plan handed out is verified first: means inside the site, mu_0 =
// start, mu_N = goal, every end on its face's side by its delta's margin
// exactly (no tolerance), deltas in (0, 0.5), and certified: their sum <=
// Delta, or the certified bound <= Delta. Finish: the plan is pulled taut
// (plan_tauten.hpp) and its certified risk evaluated (one segment a unit,
// while the work budget lasts; else the deltas' sum is its claim); riskUsed
// and segmentRisk[] carry it.
//
// Bounded and sliceable. No clock is read here: work is counted. start() does
// no LP work; step(maxNodes) runs at most maxNodes units, and every unit is
// small: an LP (seed, root, search node, allocation round) runs
// kPivotsPerUnit (16) pivots per unit and resumes from its basis in the next
// (LpSolver keeps it on kIterationLimit), each LP capped at perLpIterations
// pivots in all; a certified-risk evaluation does one segment (M pairs: at
// most 8 x (18 tails and 9 + 32 bivariate orthants), charged 20 units a tail
// and 320 an orthant, their ~8 and ~145 ns of CPU as bench_cc_risk_bounds
// prints them) per unit; a
// visibility seed builds its graph in one unit and settles
// one Dijkstra vertex per unit; the layered seed handles kLayerPairsPerUnit
// (256) line pairs of a layer per unit. Every unit checks the budget first, so
// work() <= workBudget x 1000 + kMaxUnitWork whatever N <= kMaxPlanSteps and
// M <= kMaxPlanObstacles (test_cc_planner_budget: N = 24, M = 8 octagons,
// budgets 0.5 M - 20 M, largest unit measured 315 k units; bench_cc_complete:
// 600 runs of the hard set, worst work / budget in docs/performance.md). A
// plan stops searching when nodeBudget nodes, iterationBudget pivots or
// workBudget thousand work units are spent (with kOptimised the search gets
// 80 % of the work budget, the allocation rounds run to 97 % and the finish's
// certification has the rest, else the deltas' sum is claimed); a seed or an LP cut
// short by the budget is dropped (a search node cut short leaves the search
// incomplete, its parent's bound in lowerBound()). work() is
// LpSolver::work() plus the planner's own scoring, margins and geometry,
// weighted by measured costs: 0.45 - 0.9 ns per unit on the x86-64
// development host (most for small N, and with another process on the other
// core; bench_cc_complete measures CPU ns per unit on its runs). The default
// 20 000 (20 M units) is 10 - 20 ms there.
// Measured with the defaults before the layered seed and the slicing
// (unit_test/fsw/deliberative's random instances, x86-64 host, wall clock,
// another process on the other core; no command reproduces these any more):
// N = 10, M = 4 median 15 ms, max 19 ms (50 instances: ~900 nodes, cost
// within 0.44 % of the proven optimum, median 0 %); N = 20, M = 8 median
// 12 ms, max 13 ms (~180 nodes: the seeds take half the budget there);
// N = 24, M = 8 median 11 ms, max 12 ms. Budget checks, reproducible:
// bench_cc_reference and bench_cc_complete (docs/performance.md).
//
// Memory: sizeof(CcPlanner) = 493 416 B on x86-64 (bench_cc_risk_bounds prints it): one CcLp (216 KiB), the
// factor ring (4 x 72 x 73 doubles, 164 KiB), the search stack (192 levels
// with a basis each, 32 KiB), the layered seed's layers (25 x 256 points:
// two line indices and a predecessor each, 25 KiB, and the last two layers'
// points and masks, 12 KiB: 38 016 B more than before it), the margin table,
// three plans (best, candidate, the empty plan shown during a wide search:
// 3 888 B each) and the problem. Static storage (a task member), never a stack.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/lp_solver.hpp"

namespace rse::deliberative {

struct CcPlannerParams {
    std::uint32_t nodeBudget = 100000;         // search nodes (LP solves) per plan
    std::uint32_t iterationBudget = 1000000;   // simplex pivots per plan (seed + search)
    std::uint32_t perLpIterations = 2000;      // pivots per LP solve
    std::uint32_t workBudget = 20000;          // thousands of work units (see work()); 0: none
    double relativeGap = 0.002;                // prune bound >= incumbent (1 - gap); [0, 0.5)
    std::uint8_t iraRounds = 12;               // risk allocation rounds (kOptimised), 0..50
    bool seed = true;                          // the visibility-graph seed
    bool layeredSeed = true;                   // the layered seed when those find none (false: ablation only)
    // kOptimised only: the search (even split, presolve, seeds) runs at a
    // Boole budget of Delta x this, in [1, kMaxSearchRiskScale]; its plans
    // are then not certified by their deltas and are handed out only once the
    // allocation has certified one within Delta (plan_risk.hpp). For narrow
    // passages that Boole's bound refuses at Delta (see "Risk allocation").
    double searchRiskScale = 1.0;
};

// Checks a plan against its problem exactly (see above): its shape and
// margins, and its risk: the deltas' sum <= Delta with riskUsed no less, or
// else the certified bound (plan_risk.hpp, recomputed here) <= Delta with
// riskUsed no less than it. kInvalidArgument names nothing: the plan is
// simply not to be used.
core::Status checkPlan(const CcProblem& problem, const CcPlan& plan);

class CcPlanner {
public:
    static constexpr std::size_t kPolishRounds = 1;
    static constexpr std::size_t kSeedVariants = 4;
    // The layered seed runs after this many visibility variants found none.
    static constexpr std::size_t kLayeredSeedSlot = 2;
    // Points kept per layer of the layered seed (the first that are reachable).
    static constexpr std::size_t kMaxLayerPoints = 256;
    // Slices of work per unit of step(): LP pivots, line pairs of a layer.
    static constexpr std::uint32_t kPivotsPerUnit = 16;
    static constexpr std::size_t kLayerPairsPerUnit = 256;
    // Factors (A_B^-1) of the deepest search levels, for going back to a
    // level without refactorising: a ring of slots over the stack.
    static constexpr std::size_t kFactorPoolDoubles = 4 * LpSolver::factorDoubles(kLpMaxVariables);
    static constexpr std::size_t kMaxFactorSlots = 64;
    static constexpr std::size_t kMaxSeedVertices = 192;  // start, goal and free-space corners
    // Work units charged per position tautening tries (2 M face checks).
    static constexpr std::uint64_t kTautWorkPerTry = 64;
    // The most work one unit of step() may do (see "Bounded and sliceable";
    // the largest measured is 315 k): a plan's work() never exceeds the
    // budget by more than this.
    static constexpr std::uint64_t kMaxUnitWork = 500000;
    static constexpr double kMaxSearchRiskScale = 64.0;

    // Copies the problem and starts a plan. kInvalidArgument (and a plan of
    // status kBadProblem, finished) when checkProblem() or the parameters fail.
    core::Status start(const CcProblem& problem, const CcPlannerParams& params);

    // After start(), before the first step(): the faces of an earlier plan
    // (same N, each face within its obstacle's count; e.g. the plan at a
    // looser bound) tried first, as one more seed unit: their LP at this
    // problem's margins and a polish round. kInvalidArgument (and no effect)
    // when they do not fit or the seed phase has begun or is off.
    core::Status setSeedHint(const CcPlan& hint);

    // Up to maxNodes units of work; true when the plan is finished.
    bool step(std::uint32_t maxNodes);
    bool finished() const { return phase_ == Phase::kDone; }

    // The best plan so far (status kNoPlan until one exists; kFeasible while
    // running); its final status once finished().
    const CcPlan& plan() const { return bestCertified_ || best_.status == CcStatus::kBadProblem ? best_ : noPlan_; }

    // start() and step() to the end; the plan's status.
    CcStatus solve(const CcProblem& problem, const CcPlannerParams& params, CcPlan* out);

    // Work of the current plan.
    std::uint32_t nodes() const { return nodes_; }                  // search LPs
    std::uint32_t seedSolves() const { return seedSolves_; }        // seed and polish LPs
    std::uint32_t allocationRounds() const { return iraDone_; }
    std::uint32_t lpIterations() const { return lp_.solver().iterations(); }
    // Work of the plan so far in LpSolver::work() units plus the seed's
    // geometry: proportional to time (see the calibration above).
    std::uint64_t work() const { return lp_.solver().work() + geometryWork_; }
    std::uint32_t refactorizations() const { return lp_.solver().refactorizations(); }
    std::uint32_t factorRestores() const { return factorRestores_; }
    std::uint32_t incumbents() const { return incumbents_; }        // improvements of the plan
    // Final plans whose tautened path (plan_tauten.hpp) failed its checks or cost more, or whose
    // evaluation the budget cut short while only the certified bound held it: kept as planned.
    std::uint32_t tautenRefused() const { return tautenRefused_; }
    std::uint32_t nodeOfLastIncumbent() const { return lastIncumbentNode_; }
    std::size_t maxDepth() const { return maxDepth_; }
    bool seedFound() const { return seedFound_; }
    std::size_t layeredSeedLayers() const { return layerTau_; }     // layers the layered seed built (0: not run)
    // Layers that reached kMaxLayerPoints (points beyond were dropped: the
    // layered seed is complete only while this is 0).
    std::uint32_t layeredSeedFullLayers() const { return layerFull_; }
    double seedCost() const { return seedCost_; }                   // INFINITY without a seed
    double hintSeedCost() const { return hintSeedCost_; }           // the hint's seed (INFINITY: none or it failed)
    double evenSplitCost() const { return evenCost_; }              // the search's best (INFINITY: none)
    bool searchExhausted() const { return exhausted_; }             // every node resolved or pruned
    // Start or goal ends given more than the even split because they need it
    // (kOptimised; see splitFixedEnds in the .cpp): 0 when the split is even.
    std::uint8_t fixedEndsRaised() const { return fixedEndsRaised_; }
    // A lower bound on the even split's optimum (valid when the search ran):
    // the least bound of the open nodes, or the incumbent when exhausted.
    double lowerBound() const;

private:
    enum class Phase : std::uint8_t { kIdle, kSeed, kRoot, kSearch, kAllocate, kFinish, kDone };
    enum class SeedStage : std::uint8_t { kIdle, kDijkstra, kLayered };

    struct Level {
        std::uint8_t t;
        std::uint8_t obstacle;
        std::uint8_t count;
        std::uint8_t next;
        std::uint8_t order[kMaxObstacleFaces];
        double bound;
        LpBasis basis;
    };

    void splitFixedEnds();
    double endDelta(std::size_t tau, std::size_t i) const;
    void saveLevelFactor(std::size_t d);
    void restoreLevel(std::size_t d);
    void runSeed();
    void runHintSeed();
    bool seedVertices();
    bool dijkstraStep();
    bool seedLegs(std::size_t* legs);
    void cutSeedPath();
    void seedFromPath(double distance);
    void seedStartLp();
    void seedLpUnit();
    void beginLp(double cutoff, std::uint32_t limit);
    bool continueLp(LpStatus* status);
    void rootLpUnit();
    void nodeLpUnit();
    void abandonNode();
    void allocationCandidate();
    void startEvaluation();
    bool evaluateUnit(CcPlan* plan);
    void judgeCandidate();
    void endAllocation();
    void finishStep();
    double searchScale() const;
    bool layeredSeedStep();
    std::size_t layerLineCount() const;
    void layerLine(std::size_t tau, std::size_t k, double* nx, double* ny, double* c) const;
    bool layerPoint(std::size_t tau, std::uint8_t a, std::uint8_t b, double* x, double* y) const;
    std::uint64_t layerMask(std::size_t tau, double x, double y, bool fixedEnd);
    void chooseFacesAt(const double* mx, const double* my,
                       std::uint8_t (&face)[kMaxPlanSteps][kMaxPlanObstacles]) const;
    void offerIncumbentFromLp(const std::uint8_t (&face)[kMaxPlanSteps][kMaxPlanObstacles]);
    void rootStep();
    bool searchStep();
    void evaluateNode();
    void allocateStep();
    void finish();
    double pruneThreshold() const;
    double pairScore(std::size_t t, std::size_t i, std::size_t j, const double* mx, const double* my) const;
    std::uint32_t lpCap() const;
    bool budgetLeft() const;
    bool segmentBlocked(double px, double py, double qx, double qy);

    CcProblem problem_{};
    CcPlannerParams params_{};
    Phase phase_ = Phase::kIdle;
    CcLp lp_;
    std::size_t steps_ = 0;
    std::size_t obstacles_ = 0;
    double evenDelta_ = 0.0;   // every end's delta in the search, but the fixed ends' below
    double fixedDelta_[2][kMaxPlanObstacles] = {};  // the start's (0) and the goal's (1) ends, per obstacle
    std::uint8_t fixedEndsRaised_ = 0;
    double riskBudget_ = 0.0;  // Delta (1 - 1e-12): what a plan is certified within
    double searchBudget_ = 0.0;  // riskBudget_ x searchRiskScale: the search's Boole budget
    bool bestCertified_ = false;  // best_ is certified within riskBudget_ (plan() hands it out)
    double margin_[kMaxPlanSteps + 1][kMaxPlanObstacles][kMaxObstacleFaces] = {};
    double inflated_[kMaxPlanObstacles][kMaxObstacleFaces] = {};  // b_j + largest margin

    // Search state.
    Level level_[kMaxPairs];
    std::size_t depth_ = 0;
    std::size_t rootPairs_ = 0;  // pairs fixed at the root by the presolve
    double factorPool_[kFactorPoolDoubles] = {};
    std::size_t factorSize_ = 0;
    std::size_t factorSlots_ = 0;
    std::size_t slotOwner_[kMaxFactorSlots] = {};  // the level whose factor the slot holds
    std::uint32_t factorRestores_ = 0;
    std::uint64_t geometryWork_ = 0;
    std::uint8_t assigned_[kMaxPlanSteps][kMaxPlanObstacles] = {};
    std::uint8_t faceScratch_[kMaxPlanSteps][kMaxPlanObstacles] = {};
    double scratchX_[kMaxPlanSteps + 1] = {};
    double scratchY_[kMaxPlanSteps + 1] = {};
    bool exhausted_ = false;
    bool incomplete_ = false;      // a node was left unresolved (LP budget)
    double unresolvedBound_ = 0.0; // least parent bound of such nodes

    // Seed scratch: visibility graph nodes.
    double vx_[kMaxSeedVertices] = {};
    double vy_[kMaxSeedVertices] = {};
    double dist_[kMaxSeedVertices] = {};
    std::uint8_t prev_[kMaxSeedVertices] = {};
    bool settled_[kMaxSeedVertices] = {};
    std::size_t vertexCount_ = 0;
    std::size_t seedVariant_ = 0;   // the next seed slot (variants and the layered seed)
    std::size_t seedCurrent_ = 0;   // the visibility variant under way
    SeedStage seedStage_ = SeedStage::kIdle;
    std::size_t seedRound_ = 0;     // polish rounds done on the current seed
    std::uint8_t guideFace_[kMaxPlanSteps][kMaxPlanObstacles] = {};
    bool guideValid_ = false;
    double guideDistance_ = 0.0;
    std::uint8_t legPoint_[kMaxSeedVertices + 1] = {};
    std::uint8_t hintFace_[kMaxPlanSteps][kMaxPlanObstacles] = {};
    bool hintPending_ = false;
    bool hintRunning_ = false;  // the seed LP under way is the hint's
    double hintSeedCost_ = 0.0;

    // Layered seed: per layer the points kept (their two lines, or the start
    // or goal) and each one's predecessor; the last two layers' points.
    std::size_t layerTau_ = 0;
    std::size_t layerLineA_ = 0;    // the next first line of the layer being built
    std::size_t layerBuilt_ = 0;    // its points so far
    std::uint32_t layerFull_ = 0;
    std::uint16_t layerCount_[kMaxPlanSteps + 1] = {};
    std::uint8_t layerLines_[kMaxPlanSteps + 1][kMaxLayerPoints][2] = {};
    std::uint16_t layerPrev_[kMaxPlanSteps + 1][kMaxLayerPoints] = {};
    double reachX_[2][kMaxLayerPoints] = {};
    double reachY_[2][kMaxLayerPoints] = {};
    std::uint64_t reachMask_[2][kMaxLayerPoints] = {};

    // The LP under way (seed, root, node or allocation round), run
    // kPivotsPerUnit pivots per unit.
    bool lpRunning_ = false;
    std::uint32_t lpPivots_ = 0;
    std::uint32_t lpLimit_ = 0;
    double lpCutoff_ = 0.0;

    // Allocation state.
    double delta_[kMaxPlanSteps][kMaxPlanObstacles][2] = {};
    std::uint32_t iraDone_ = 0;
    bool iraReady_ = false;
    bool iraLastRound_ = false;  // nothing left to stretch: this round's candidate is the last
    double iraBudget_ = 0.0;   // the allocation's sum of deltas this round (may pass Delta)
    double budgetLo_ = 0.0;    // the largest budget whose plan certified within Delta
    double budgetHi_ = 0.0;    // the least budget whose plan did not (INFINITY: none yet)

    // The certified risk (plan_risk.hpp) of candidate_, one segment a unit.
    bool evalRunning_ = false;
    std::size_t evalT_ = 0;
    double evalTotal_ = 0.0;
    bool tautenDone_ = false;

    CcPlan best_{};
    CcPlan candidate_{};
    CcPlan noPlan_{};  // what plan() shows while best_ is not certified
    double evenCost_ = 0.0;
    double seedCost_ = 0.0;
    bool seedFound_ = false;
    std::uint32_t nodes_ = 0;
    std::uint32_t seedSolves_ = 0;
    std::uint32_t incumbents_ = 0;
    std::uint32_t tautenRefused_ = 0;
    std::uint32_t lastIncumbentNode_ = 0;
    std::size_t maxDepth_ = 0;
};

}  // namespace rse::deliberative

// The deliberative layer's chance-constrained path planner (cc_problem.hpp,
// docs/deliberative.md, "Parts of the planner"): a bounded, anytime branch and
// bound over face assignments, seeded from visibility graphs, then risk
// allocation. CcPlanner runs the phases in order, in units of work, over its
// parts; each part's header says how it works:
//
//   start()  the parameters and the problem checked; the risk split over the
//            ends and their margins (cc_end_margins.hpp: the fixed ends get
//            what they need with kOptimised); the LP set up (cc_lp.hpp)
//   kSeed    the hint, the visibility and layered seeds, polished
//            (cc_seeds.hpp, cc_visibility_seed.hpp, cc_layered_seed.hpp): the
//            first incumbent (cc_incumbent.hpp) and the search's guide
//   kRoot    the presolve and the root's LP (cc_face_search.hpp)
//   kSearch  depth-first branch and bound over faces (cc_face_search.hpp,
//            cc_factor_ring.hpp, cc_face_scores.hpp)
//   kAllocate  kOptimised: risk allocation rounds, each certified
//            (cc_risk_allocation.hpp, cc_risk_certifier.hpp)
//   kFinish  the plan pulled taut and certified (cc_taut_finish.hpp)
// They share a CcWorkspace (cc_workspace.hpp): the problem, the margins, the
// LP and its solve under way (cc_sliced_lp.hpp), the best plan. Every plan is
// checked (cc_plan_checks.hpp) before it is kept.
//
// Risk allocation. kEvenSplit: delta = Delta' / (2 N M) at every end, with
// Delta' = Delta (1 - 1e-12) so that the sum of the 2 N M deltas, added in any
// order in double precision, stays <= Delta. kOptimised: the fixed ends'
// needs, then iterative risk allocation stretched on the certified bound
// (cc_risk_allocation.hpp); never worse than the even split's plan.
//
// Hint. setSeedHint(): an earlier plan's faces, re-solved at this problem's
// margins, as the first seed (e.g. the plan at a looser bound).
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
// weighted by measured costs (cc_work_units.hpp): 0.45 - 0.9 ns per unit on the x86-64
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
// Memory: sizeof(CcPlanner) = 493 416 B on x86-64 (bench_cc_risk_bounds
// prints it; the start-up event's "bytes reserved" counts it): one CcLp
// (216 KiB), the factor ring (164 KiB), the search stack (192 levels with a
// basis each, 32 KiB), the layered seed's layers (37 KiB), the margin table,
// three plans (best, candidate, the empty plan shown during a wide search:
// 3 888 B each) and the problem. Static storage (a task member), never a
// stack.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/deliberative/cc_face_search.hpp"
#include "fsw/deliberative/cc_factor_ring.hpp"
#include "fsw/deliberative/cc_layered_seed.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_planner_params.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/cc_risk_allocation.hpp"
#include "fsw/deliberative/cc_seeds.hpp"
#include "fsw/deliberative/cc_sliced_lp.hpp"
#include "fsw/deliberative/cc_taut_finish.hpp"
#include "fsw/deliberative/cc_visibility_seed.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "fsw/deliberative/lp_solver.hpp"

namespace rse::deliberative {

class CcPlanner {
public:
    static constexpr std::size_t kPolishRounds = CcSeeds::kPolishRounds;
    static constexpr std::size_t kSeedVariants = CcSeeds::kSeedVariants;
    // The layered seed runs after this many visibility variants found none.
    static constexpr std::size_t kLayeredSeedSlot = CcSeeds::kLayeredSeedSlot;
    // Points kept per layer of the layered seed (the first that are reachable).
    static constexpr std::size_t kMaxLayerPoints = CcLayeredSeed::kMaxLayerPoints;
    // Slices of work per unit of step(): LP pivots, line pairs of a layer.
    static constexpr std::uint32_t kPivotsPerUnit = CcSlicedLp::kPivotsPerUnit;
    static constexpr std::size_t kLayerPairsPerUnit = CcLayeredSeed::kLayerPairsPerUnit;
    // Factors (A_B^-1) of the deepest search levels, for going back to a
    // level without refactorising: a ring of slots over the stack.
    static constexpr std::size_t kFactorPoolDoubles = CcFactorRing::kPoolDoubles;
    static constexpr std::size_t kMaxFactorSlots = CcFactorRing::kMaxSlots;
    static constexpr std::size_t kMaxSeedVertices = CcVisibilitySeed::kMaxVertices;  // start, goal and free-space corners
    // Work units charged per position tautening tries (2 M face checks).
    static constexpr std::uint64_t kTautWorkPerTry = CcTautFinish::kWorkPerTry;
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
    const CcPlan& plan() const {
        const CcPlan& best = ws_.incumbent.best();
        return ws_.incumbent.certified() || best.status == CcStatus::kBadProblem ? best : noPlan_;
    }

    // start() and step() to the end; the plan's status.
    CcStatus solve(const CcProblem& problem, const CcPlannerParams& params, CcPlan* out);

    // Work of the current plan.
    std::uint32_t nodes() const { return search_.nodes(); }           // search LPs
    std::uint32_t seedSolves() const { return seeds_.solves(); }       // seed and polish LPs
    std::uint32_t allocationRounds() const { return allocation_.rounds(); }
    std::uint32_t lpIterations() const { return ws_.lp.solver().iterations(); }
    // Work of the plan so far in LpSolver::work() units plus the seed's
    // geometry: proportional to time (see the calibration above).
    std::uint64_t work() const { return ws_.lp.solver().work() + ws_.geometryWork; }
    std::uint32_t refactorizations() const { return ws_.lp.solver().refactorizations(); }
    std::uint32_t factorRestores() const { return search_.factorRestores(); }
    std::uint32_t incumbents() const { return ws_.incumbent.improvements(); }  // improvements of the plan
    // Final plans whose tautened path (plan_tauten.hpp) failed its checks or cost more, or whose
    // evaluation the budget cut short while only the certified bound held it: kept as planned.
    std::uint32_t tautenRefused() const { return finish_.refused(); }
    std::uint32_t nodeOfLastIncumbent() const { return ws_.incumbent.lastNode(); }
    std::size_t maxDepth() const { return search_.maxDepth(); }
    bool seedFound() const { return seeds_.found(); }
    std::size_t layeredSeedLayers() const { return seeds_.layered().layers(); }  // layers the layered seed built (0: not run)
    // Layers that reached kMaxLayerPoints (points beyond were dropped: the
    // layered seed is complete only while this is 0).
    std::uint32_t layeredSeedFullLayers() const { return seeds_.layered().fullLayers(); }
    double seedCost() const { return seeds_.cost(); }                   // INFINITY without a seed
    double hintSeedCost() const { return seeds_.hintCost(); }           // the hint's seed (INFINITY: none or it failed)
    double evenSplitCost() const { return ws_.incumbent.evenCost(); }  // the search's best (INFINITY: none)
    bool searchExhausted() const { return search_.exhausted(); }      // every node resolved or pruned
    // Start or goal ends given more than the even split because they need it
    // (kOptimised; cc_end_margins.hpp): 0 when the split is even.
    std::uint8_t fixedEndsRaised() const { return ws_.margins.raised(); }
    // A lower bound on the even split's optimum (valid when the search ran):
    // the least bound of the open nodes, or the incumbent when exhausted.
    double lowerBound() const { return search_.lowerBound(ws_.incumbent.evenCost(), ws_.params.relativeGap); }

private:
    enum class Phase : std::uint8_t { kIdle, kSeed, kRoot, kSearch, kAllocate, kFinish, kDone };

    bool paramsValid(const CcPlannerParams& params) const;
    void seedUnit();
    void rootUnit();
    bool searchUnit();
    void endAllocation();
    void finishUnit();
    void finish();
    bool budgetLeft() const;
    bool workLeft(std::uint64_t percent) const;

    CcWorkspace ws_;
    Phase phase_ = Phase::kIdle;
    CcPlan noPlan_{};  // what plan() shows while the best plan is not certified
    CcSeeds seeds_;
    CcFaceSearch search_;
    CcRiskAllocation allocation_;
    CcTautFinish finish_;
};

}  // namespace rse::deliberative

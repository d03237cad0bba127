// The planner's branch and bound over face assignments (cc_planner.hpp):
// the presolve, the root, and the depth-first search.
//
// A node assigns faces to some (segment, obstacle) pairs; its bound is the LP
// (cc_lp.hpp) with only those pairs' rows, the search's margins
// (cc_end_margins.hpp) and the rest of the disjunctions dropped,
// warm-started from its parent's basis (LpSolver's dual simplex: a child only
// adds two rows) and cut off as soon as its dual bound reaches the prune
// threshold. At a node's optimum every unassigned pair is scored by
// max_j min(slack of its two ends on face j) (cc_face_scores.hpp): when no
// pair is violated the node's path is a plan (its faces are the assigned
// ones plus, for each other pair, its best face), offered to the incumbent,
// and, as the bound of its subtree, the best there. Otherwise the search
// branches on the most violated pair, one child per face, least violated face
// first (the seeds' guide face before them), depth first. A node whose bound
// reaches incumbent (1 - relativeGap) is pruned, so an exhausted search means
// optimal within relativeGap for the search's split. Going back to a level
// restores its parent's A_B^-1 from the factor ring (cc_factor_ring.hpp).
//
// Presolve. The pairs of the first and last segments have an end at the
// fixed start or goal; the faces that end misses are out. A pair with no face
// left proves that there is no plan (the search ends at once, exhausted); a
// pair with one face left is fixed at the root.
//
// A unit: a slice of a node's LP (cc_sliced_lp.hpp), or the presolve. A node
// whose LP is cut short by the budget stays unresolved: the search is then
// incomplete and its parent's bound is in lowerBound().
//
// Memory: the stack (192 levels with a basis each, 32 KiB) and the factor
// ring (164 KiB); a node's means and faces (592 B) are a local of its
// evaluation. No heap.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_face_scores.hpp"
#include "fsw/deliberative/cc_factor_ring.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "fsw/deliberative/lp_solver.hpp"

namespace rse::deliberative {

class CcFaceSearch {
public:
    // A new plan: no nodes, an empty stack, nothing proven or left open.
    void resetCounts();
    // For a problem whose LP is set up: no pair assigned, the ring emptied.
    void prepare(std::size_t variables);

    // One unit of the root: the presolve (then its LP is started), or a
    // slice of the root's LP. True when the search proper begins.
    bool rootUnit(CcWorkspace& ws, const CcFaceTable* guide);
    // One unit of the search: a slice of a node's LP, or the next child
    // started. False when no node is left (nothing was done).
    bool searchUnit(CcWorkspace& ws, const CcFaceTable* guide);
    // The node whose LP is under way (or was cut short) stays unresolved.
    void abandonNode(CcSlicedLp& run);
    // The search stopped by its budgets, or because no node is left.
    void stopIncomplete() { incomplete_ = true; }
    void stopExhausted() { exhausted_ = !incomplete_; }

    std::uint32_t nodes() const { return nodes_; }            // search LPs
    std::size_t maxDepth() const { return maxDepth_; }
    bool exhausted() const { return exhausted_; }             // every node resolved or pruned
    bool incomplete() const { return incomplete_; }
    std::uint32_t factorRestores() const { return ring_.restores(); }
    // A lower bound on the search's optimum, from its best cost: the least
    // bound of the open nodes, or the incumbent's when exhausted.
    double lowerBound(double bestCost, double relativeGap) const;

private:
    static constexpr std::uint8_t kUnassigned = 0xFF;

    struct Level {
        std::uint8_t t;
        std::uint8_t obstacle;
        std::uint8_t count;
        std::uint8_t next;
        std::uint8_t order[kMaxObstacleFaces];
        double bound;
        LpBasis basis;
    };

    bool presolve(CcWorkspace& ws);
    void rootLpUnit(CcWorkspace& ws, const CcFaceTable* guide);
    void nodeLpUnit(CcWorkspace& ws, const CcFaceTable* guide);
    void evaluateNode(CcWorkspace& ws, const CcFaceTable* guide);
    // A node's means and faces: the assigned, else each pair's best.
    struct NodePath {
        double x[kMaxPlanSteps + 1];
        double y[kMaxPlanSteps + 1];
        CcFaceTable faces;
    };
    bool mostViolatedPair(CcWorkspace& ws, NodePath* node, std::size_t* wt, std::size_t* wi) const;
    void pushLevel(CcWorkspace& ws, const CcFaceTable* guide, const NodePath& node, std::size_t t, std::size_t i,
                   double bound);
    double pruneThreshold(const CcWorkspace& ws) const;

    Level level_[kMaxPairs];
    std::size_t depth_ = 0;
    std::size_t rootPairs_ = 0;  // pairs fixed at the root by the presolve
    CcFactorRing ring_;
    std::uint8_t assigned_[kMaxPlanSteps][kMaxPlanObstacles] = {};
    bool exhausted_ = false;
    bool incomplete_ = false;      // a node was left unresolved (LP budget)
    double unresolvedBound_ = 0.0; // least parent bound of such nodes
    std::uint32_t nodes_ = 0;
    std::size_t maxDepth_ = 0;
};

}  // namespace rse::deliberative

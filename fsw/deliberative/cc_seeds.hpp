// The seeds of the planner (cc_planner.hpp): plans found before the search,
// cheapest first, the best of them its first incumbent, and the guide its
// branching follows.
//
// Order. The hint (setHint: an earlier plan's faces, e.g. the plan at a
// looser bound) first when there is one; then the visibility variants
// (cc_visibility_seed.hpp) with the obstacles inflated by their margin at
// step N and N / 2; then (only when neither gave a plan) the layered seed
// (cc_layered_seed.hpp, complete); then the variants at step 0 (margins grow
// with the step: the first is conservative, the last keeps gaps open that
// early steps can use) and front-loaded (one segment per leg, the rest
// parked at the goal: the path passes the obstacles while the margins are
// small).
//
// Each seed path gets, for every pair, the face its two ends clear best
// (cc_face_scores.hpp) and its fixed-face LP is solved (cc_sliced_lp.hpp, in
// units); at the LP's optimum the plan is offered to the incumbent, then
// "polish": each pair moves to the face its ends at the LP optimum clear best
// (the path stays feasible, so the cost cannot rise) and the LP is solved
// again, kPolishRounds (1) times. The faces of the shortest seed path (even
// if its LP was infeasible) are the search's guide (guide()): at every
// branching the guide's face is tried first.
//
// A unit: a slice of the seed under way (its LP, a Dijkstra vertex, a slice
// of a layer) or the start of the next one. Memory: 44 KiB (most of it the
// layered seed's layers). No heap.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_face_scores.hpp"
#include "fsw/deliberative/cc_layered_seed.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/cc_visibility_seed.hpp"
#include "fsw/deliberative/cc_workspace.hpp"

namespace rse::deliberative {

class CcSeeds {
public:
    static constexpr std::size_t kPolishRounds = 1;
    static constexpr std::size_t kSeedVariants = 4;
    // The layered seed runs after this many visibility variants found none.
    static constexpr std::size_t kLayeredSeedSlot = 2;

    // A new plan: its counts (solves, costs, the hint) cleared.
    void resetCounts();
    // A new plan that passed its checks: the order starts again, no guide.
    void resetOrder();

    // The hint's faces, taken only before the first seed unit and only when
    // they exist in this problem (same N, each face within its obstacle).
    bool setHint(const CcProblem& problem, const CcPlan& hint);
    bool hintPending() const { return hintPending_; }
    // The hint's unit: its LP started (run on by runUnit) when its faces
    // fit this problem's margins.
    void runHintUnit(CcWorkspace& ws);
    // One unit of the seeds; false when they are over (nothing was done).
    bool runUnit(CcWorkspace& ws);

    // The shortest seed path's faces (nullptr: no seed path).
    const CcFaceTable* guide() const { return guideValid_ ? &guideFace_ : nullptr; }

    std::uint32_t solves() const { return solves_; }     // seed and polish LPs
    bool found() const { return found_; }
    double cost() const { return cost_; }                // INFINITY without a seed
    double hintCost() const { return hintCost_; }        // the hint's (INFINITY: none or it failed)
    const CcLayeredSeed& layered() const { return layered_; }

private:
    enum class Stage : std::uint8_t { kIdle, kDijkstra, kLayered };

    void startSlot(CcWorkspace& ws);
    void layeredUnit(CcWorkspace& ws);
    void seedFromPath(CcWorkspace& ws, double distance);
    void startLp(CcWorkspace& ws);
    void lpUnit(CcWorkspace& ws);
    bool polish(CcWorkspace& ws);

    CcVisibilitySeed visibility_;
    CcLayeredSeed layered_;
    std::size_t nextSlot_ = 0;      // the next seed slot (variants and the layered seed)
    std::size_t variant_ = 0;       // the visibility variant under way
    Stage stage_ = Stage::kIdle;
    std::size_t round_ = 0;         // polish rounds done on the current seed
    CcFaceTable faces_ = {};        // the faces of the seed under way
    double pathX_[kMaxPlanSteps + 1] = {};
    double pathY_[kMaxPlanSteps + 1] = {};
    CcFaceTable guideFace_ = {};
    bool guideValid_ = false;
    double guideDistance_ = 0.0;
    CcFaceTable hintFace_ = {};
    bool hintPending_ = false;
    bool hintRunning_ = false;      // the seed LP under way is the hint's
    double hintCost_ = 0.0;
    double cost_ = 0.0;
    bool found_ = false;
    std::uint32_t solves_ = 0;
};

}  // namespace rse::deliberative

// The layered seed of the planner (cc_planner.hpp, "Seed"): a search over
// waypoints, layer by layer, complete on the problem's own constraints.
//
// For fixed faces the constraints on waypoint tau involve tau alone
// (half-planes at its margins, the site), so if any plan exists, one exists
// whose every waypoint is a vertex of its own feasible polygon: a crossing of
// two of layer tau's lines (each face moved out by its margin at tau, plus
// 2 kSafetyM; the site's sides moved in by kLayerSideM). Layer 0 is the start;
// layer tau + 1 keeps each crossing that clears some face of every obstacle
// and is one segment from a point kept in layer tau (for every obstacle one
// face holds both ends: a 64-bit AND of the two points' face masks; a
// crossing whose mask is covered by a point already kept is dropped, since a
// point's moves depend on its mask alone); the goal is tried first in every
// layer, and once reached the remaining steps park on it (the goal clears its
// margin at N, the largest). The path found has the fewest steps to the goal.
// Exact while no layer fills its kMaxLayerPoints (fullLayers() counts those),
// up to the 2 um the lines are moved (and crossings of lines within 1e-9 of
// parallel, which are skipped); it stops at the first path, so it is a
// feasibility seed, not a short one.
//
// Work: step() handles kLayerPairsPerUnit line pairs of a layer (whole rows
// of pairs); up to (8 M + 4)^2 / 2 crossings a layer, each a mask of M x 8
// face tests (kLayerPointWork a face) and an AND per point of this layer and
// the one before (kLayerEdgeWork).
// Memory: 37 KiB: per layer the points kept (two line indices, or the start
// or goal) and each one's predecessor (25 x 256); the last two layers' points
// and masks. No heap.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_problem.hpp"

namespace rse::deliberative {

class CcLayeredSeed {
public:
    // Points kept per layer (the first that are reachable).
    static constexpr std::size_t kMaxLayerPoints = 256;
    // Line pairs of a layer per step() (at least; whole rows).
    static constexpr std::size_t kLayerPairsPerUnit = 256;

    enum class Progress : std::uint8_t { kRunning, kNoPath, kFound };

    // A new search (layers() = 0); fullLayers() counts on until clear().
    void begin() { layerTau_ = 0; }
    void clear() {
        layerTau_ = 0;
        layerFull_ = 0;
    }
    // One slice of the layer being built (the first call sets layer 0).
    Progress step(const CcProblem& problem, const CcEndMargins& margins, std::uint64_t* work);
    // After kFound: the path into x[0..N], y[0..N]; its 16-gon length up to
    // the goal's first layer.
    double path(const CcProblem& problem, const CcEndMargins& margins, double* x, double* y) const;

    std::size_t layers() const { return layerTau_; }        // layers built (0: not run)
    std::uint32_t fullLayers() const { return layerFull_; } // layers that reached kMaxLayerPoints

private:
    std::size_t lineCount(const CcProblem& problem) const;
    void line(const CcProblem& problem, const CcEndMargins& margins, std::size_t tau, std::size_t k, double* nx,
              double* ny, double* c) const;
    bool point(const CcProblem& problem, const CcEndMargins& margins, std::size_t tau, std::uint8_t a,
               std::uint8_t b, double* x, double* y) const;
    std::uint64_t mask(const CcProblem& problem, const CcEndMargins& margins, std::size_t tau, double x, double y,
                       bool fixedEnd, std::uint64_t* work) const;
    void startLayers(const CcProblem& problem, const CcEndMargins& margins, std::uint64_t* work);
    void consider(const CcProblem& problem, const CcEndMargins& margins, std::uint64_t wanted, std::uint8_t a,
                  std::uint8_t b, std::uint64_t* work);
    Progress closeLayer(std::size_t steps, bool goalReached);

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
};

}  // namespace rse::deliberative

// Seeded, deterministic instances of the chance-constrained planning problem
// (fsw/deliberative/cc_problem.hpp) for the planner benchmark and the tests.
//
// A random instance: a site [0, siteLength] x [0, siteWidth] m; the start in a
// band near x = 0, the goal in a band near x = siteLength; M convex polygons of
// minFaces..maxFaces faces (vertices at sorted random angles on a randomly
// rotated ellipse, so always convex, listed counter-clockwise). The first
// ceil(onLineFraction M) obstacles are centred within onLineOffsetM of the
// straight line start -> goal (between 20 % and 80 % of the way) and must
// cut that line, so the straight path is blocked; the others keep their
// bounding circles offLineClearanceM from the line (anywhere in the site when
// that is negative). Every obstacle lies inside the site with edgeClearanceM
// to spare, its bounding circle keeps gapM from every other one's, and start
// and goal are clearanceM outside it (in the sense of cc::obstacleSlack: some
// face's half-plane holds them with that margin).
// Sigma_0 = startVar I, sigma = processSigmaM (a rover: 0.01 m^2, 0.05 m/step).
// Random numbers: std::mt19937_64 with its raw 64-bit output turned into
// doubles here (no std::*_distribution), so an instance depends only on the
// seed and the parameters.
//
// Why one obstacle across the line in the provable sets: the exact MILP
// (cc_reference_milp.hpp) proves N = 10 with one blocking obstacle in seconds
// but often not in 10 s with two; the large set has half its obstacles on the
// line and is solved to a time limit (gap reported).
#pragma once

#include <cstdint>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"

namespace rse::test::cc {

struct InstanceParams {
    std::uint8_t steps = 10;          // N
    std::uint8_t obstacles = 4;       // M
    double riskBound = 0.05;          // Delta
    double siteLengthM = 40.0;        // x extent
    double siteWidthM = 20.0;         // y extent
    double endBandM = 4.0;            // start x in [1, 1 + band], goal x in [L - 1 - band, L - 1]
    double startVarM2 = 0.01;         // Sigma_0 = startVar I
    double processSigmaM = 0.05;      // sigma per step
    std::uint8_t minFaces = 4;
    std::uint8_t maxFaces = 6;
    double minRadiusM = 1.5;          // ellipse semi-axes in [minRadius, maxRadius]
    double maxRadiusM = 3.5;
    double onLineFraction = 0.25;     // share of obstacles placed across the line start -> goal
    double onLineOffsetM = 1.0;       // their centres' distance from that line, at most
    double offLineClearanceM = 1.0;   // the others' bounding circles keep this far from the line
                                      // (negative: anywhere)
    double gapM = 1.5;                // between bounding circles
    double clearanceM = 2.0;          // start / goal outside every obstacle by this much
    double edgeClearanceM = 0.5;      // obstacle to site edge
};

// One instance from one seed. Deterministic; never fails (a seed whose
// obstacles cannot all be placed after many tries is re-drawn from a derived
// seed, deterministically). obstacles[i].id = i + 1.
CcProblem generateInstance(std::uint64_t seed, const InstanceParams& params);

// The benchmark sets. Instance k of a set is generateInstance(base + k, ...),
// with base fixed per set, so a set is the same on every run and machine.
//   provable: N = 10, M = 4 (or the M given, e.g. 8), one obstacle across the
//             line, the others off it (offLineClearanceM 1 m); `steps` gives
//             the same scenes with fewer steps (e.g. N = 8, which CBC proves
//             far sooner: its tree grows like faces^segments)
//   large:    N = 20, M = 8, four across the line, the others anywhere
constexpr std::uint64_t kProvableSeedBase = 1000;
constexpr std::uint64_t kProvable8SeedBase = 2000;
constexpr std::uint64_t kLargeSeedBase = 3000;
std::vector<CcProblem> provableSet(double riskBound, std::size_t count = 50,
                                   std::uint8_t obstacles = 4, std::uint8_t steps = 10);
std::vector<CcProblem> largeSet(double riskBound, std::size_t count = 10);

// The corner-cutting instance: start (0, 0), goal (10, 10), N = 4, site
// [-2, 12] x [-2, 12], one box [2, 6] x [-2, 4] below the diagonal whose
// top-left corner (2, 4) pokes 1.41 m across it (the diagonal runs through the
// box from (2, 2) to (4, 4)). Every path of the least 16-gon length
// (10 sqrt 2) keeps its steps within 11.25 deg of the diagonal, so it crosses
// x = 2 at y <= 3 < 4: with waypoint-only constraints the optimum steps over
// the corner and a segment cuts through the box; with segment constraints the
// path has to go around the corner and is longer. Rover noise
// (Sigma_0 = 0.01 I m^2, sigma = 0.05 m).
CcProblem diagonalBoxInstance(double riskBound = 0.05);

}  // namespace rse::test::cc

namespace rse::test::cc {

// ---------------------------------------------------------------------------
// Hard instances (issue 15 item 1): scenes where the planner's cheap seeds
// (visibility graphs of the obstacles grown by one margin) can miss the only
// way through, so that "no plan" is tested against scenes that have one.
// Every instance draws N in [minSteps, maxSteps], sigma in [0.02, 0.2] m/step,
// a correlated Sigma_0 (variances 0.005 .. 0.05 m^2, correlation -0.8 .. 0.8)
// and Delta = 10^-u, u in [1, 4]. Kinds (seed % 3):
//   kGap:     a wall across the site of two boxes, each overlapped by a
//             random convex buttress (triangle .. octagon), leaving one gap
//             only a little wider than twice the margin at step 2: it must be
//             passed early, while the margins are small. 0..2 obstacles of
//             clutter elsewhere.
//   kConcave: the start inside a U of three overlapping boxes that opens away
//             from the goal, and (half of them) the goal inside another that
//             opens away from the start; 0..2 clutter obstacles.
//   kClutter: 4..8 overlapping convex polygons of 3..8 faces (radii 1.5 ..
//             5 m) around the straight line, start and goal just clear of
//             them at their margins; no witness (the reference decides).
// kGap and kConcave instances come with a witness: a path that meets every
// segment constraint with the even split (checked here with
// segmentConstraintSlack, independent of the planner), so each HAS a plan;
// an instance whose witness fails is redrawn. Obstacles may reach beyond the
// site (walls close it off). Deterministic per seed, like generateInstance.
enum class HardKind : std::uint8_t { kGap = 0, kConcave = 1, kClutter = 2 };
struct HardInstance {
    CcProblem problem;
    HardKind kind = HardKind::kGap;
    bool hasWitness = false;
    double witnessX[kMaxPlanSteps + 1] = {};
    double witnessY[kMaxPlanSteps + 1] = {};
};
HardInstance hardInstance(std::uint64_t seed, std::uint8_t minSteps = 10, std::uint8_t maxSteps = 24);
constexpr std::uint64_t kHardSeedBase = 15000;
// Instances base + k, k < count (kHardSeedBase by default).
std::vector<HardInstance> hardSet(std::size_t count, std::uint64_t base = kHardSeedBase,
                                  std::uint8_t minSteps = 10, std::uint8_t maxSteps = 24);

}  // namespace rse::test::cc

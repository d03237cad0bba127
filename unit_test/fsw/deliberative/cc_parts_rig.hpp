// Helpers for testing the chance-constrained planner's parts alone
// (fsw/deliberative/cc_planner.hpp, docs/deliberative.md "Parts of the
// planner"): a workspace prepared as CcPlanner::start() prepares it, an LP run
// to its end, and small hand-made problems. Header-only.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_face_scores.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "unit_test/fsw/deliberative/cc_test_maps.hpp"

namespace rse::test {

// The workspace of a new plan of p (p must pass checkProblem()).
inline bool prepareWorkspace(deliberative::CcWorkspace& ws, const CcProblem& p,
                             const deliberative::CcPlannerParams& params = deliberative::CcPlannerParams{}) {
    return ws.begin(p, params) == core::Status::kOk;
}

// Runs the LP under way (CcSlicedLp) to its end; its final status.
inline deliberative::LpStatus finishLp(deliberative::CcWorkspace& ws) {
    deliberative::LpStatus st = deliberative::LpStatus::kNotSolved;
    for (int k = 0; k < 100000 && ws.run.running(); ++k) {
        (void)ws.run.resume(ws.lp, &st);
    }
    return st;
}

// The fixed-face LP of `faces` at the workspace's margins, solved (kInfeasible
// when a constant end misses its face).
inline deliberative::LpStatus solveFaces(deliberative::CcWorkspace& ws, const deliberative::CcFaceTable& faces) {
    (void)ws.lp.popPairs(0);
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            const std::size_t j = faces[t][i];
            bool feasible = false;
            if (ws.lp.addPair(t, i, j, ws.margins.margin(t, i, j), ws.margins.margin(t + 1, i, j), &feasible) !=
                    core::Status::kOk ||
                !feasible) {
                return deliberative::LpStatus::kInfeasible;
            }
        }
    }
    ws.run.begin(HUGE_VAL, 100000);
    return finishLp(ws);
}

// Every pair on face `face`.
inline void fillFaces(deliberative::CcFaceTable& faces, std::uint8_t face) {
    for (std::size_t t = 0; t < deliberative::kMaxPlanSteps; ++t) {
        for (std::size_t i = 0; i < deliberative::kMaxPlanObstacles; ++i) {
            faces[t][i] = face;
        }
    }
}

// A wall of two boxes between (0, 5) and (20, 5) with a gap at y in [4, 6];
// sigma 0.05 m a step, Sigma_0 = 0.01 m^2 I, Delta 0.01.
inline CcProblem wallWithGap(std::uint8_t steps) {
    CcProblem p = makeProblem(steps, 0.0, 5.0, 20.0, 5.0, -2.0, 22.0, -10.0, 20.0);
    p.obstacles[0] = makeBox(0, 9.0, 11.0, -10.0, 3.0);
    p.obstacles[1] = makeBox(1, 9.0, 11.0, 7.0, 20.0);
    p.obstacleCount = 2;
    p.processSigmaM = 0.05;
    p.startCov[0] = 0.01;
    p.startCov[3] = 0.01;
    return p;
}

// Start (0, 0), goal (8, 0), one box above the way (x 3..5, y 2..4);
// sigma 0.05 m a step, Sigma_0 = 0.01 m^2 I, Delta 0.01.
inline CcProblem boxAboveTheWay(std::uint8_t steps) {
    CcProblem p = makeProblem(steps, 0.0, 0.0, 8.0, 0.0, -5.0, 15.0, -5.0, 8.0);
    p.obstacles[0] = makeBox(0, 3.0, 5.0, 2.0, 4.0);
    p.obstacleCount = 1;
    p.processSigmaM = 0.05;
    p.startCov[0] = 0.01;
    p.startCov[3] = 0.01;
    return p;
}

// The goal in a closed ring of four walls: no plan.
inline CcProblem goalWalledIn() {
    CcProblem p = makeProblem(4, 0.0, 0.0, 10.0, 0.0, -5.0, 15.0, -6.0, 6.0);
    p.obstacles[0] = makeBox(0, 7.0, 8.0, -3.0, 3.0);    // west wall
    p.obstacles[1] = makeBox(1, 12.0, 13.0, -3.0, 3.0);  // east wall
    p.obstacles[2] = makeBox(2, 7.0, 13.0, 2.0, 3.0);    // north wall
    p.obstacles[3] = makeBox(3, 7.0, 13.0, -3.0, -2.0);  // south wall
    p.obstacleCount = 4;
    p.processSigmaM = 0.02;
    return p;
}

// Faces of makeBox: right, top, left, bottom.
constexpr std::uint8_t kBoxRight = 0;
constexpr std::uint8_t kBoxTop = 1;
constexpr std::uint8_t kBoxLeft = 2;
constexpr std::uint8_t kBoxBottom = 3;

}  // namespace rse::test

// How well the means of a path clear each face: the score every part of the
// planner uses to choose faces (a seed's path, the polish, the search's
// branching and its leaves).
//
// pairScore(t, i, j): min over the pair's two ends of its slack on face j at
// the end's margin (cc_end_margins.hpp); an end the LP holds (not the fixed
// start or goal) is scored against the LP's row, i.e. less kSafetyM and with
// the LP's tolerance, so that a score >= 0 means the end meets its margin
// exactly. Pure: no state.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/lp_solver.hpp"

namespace rse::deliberative {

// One face per (segment, obstacle) pair.
using CcFaceTable = std::uint8_t[kMaxPlanSteps][kMaxPlanObstacles];

// Segment t's pair with obstacle i on face j, for the means mx[0..N], my[0..N].
inline double pairScore(const CcProblem& problem, const CcEndMargins& margins, std::size_t t, std::size_t i,
                        std::size_t j, const double* mx, const double* my) {
    const PlanObstacle& o = problem.obstacles[i];
    double worst = INFINITY;
    for (std::size_t e = 0; e < 2; ++e) {
        const std::size_t tau = t + e;
        double s = endSlack(o, j, mx[tau], my[tau], margins.margin(tau, i, j));
        if (tau != 0 && tau != problem.steps) {
            s -= kSafetyM - 2.0 * LpSolver::kPrimalTol;
        }
        worst = s < worst ? s : worst;
    }
    return worst;
}

// Every pair's best-scoring face (the lowest index among ties).
void chooseFacesAt(const CcProblem& problem, const CcEndMargins& margins, const double* mx, const double* my,
                   CcFaceTable& face);

}  // namespace rse::deliberative

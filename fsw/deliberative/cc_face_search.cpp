#include "fsw/deliberative/cc_face_search.hpp"

#include <cmath>

#include "fsw/deliberative/cc_work_units.hpp"

namespace rse::deliberative {

void CcFaceSearch::resetCounts() {
    nodes_ = 0;
    maxDepth_ = 0;
    depth_ = 0;
    exhausted_ = false;
    incomplete_ = false;
    unresolvedBound_ = INFINITY;
}

void CcFaceSearch::prepare(std::size_t variables) {
    for (std::size_t t = 0; t < kMaxPlanSteps; ++t) {
        for (std::size_t i = 0; i < kMaxPlanObstacles; ++i) {
            assigned_[t][i] = kUnassigned;
        }
    }
    ring_.reset(variables);
}

double CcFaceSearch::pruneThreshold(const CcWorkspace& ws) const {
    const double best = ws.incumbent.evenCost();
    if (!std::isfinite(best)) {
        return INFINITY;
    }
    return best * (1.0 - ws.params.relativeGap) - 1e-9;
}

double CcFaceSearch::lowerBound(double bestCost, double relativeGap) const {
    double lb = std::isfinite(bestCost) ? bestCost * (1.0 - relativeGap) : HUGE_VAL;
    if (exhausted_) {
        return lb;
    }
    for (std::size_t d = 0; d < depth_; ++d) {
        if (level_[d].next < level_[d].count && level_[d].bound < lb) {
            lb = level_[d].bound;
        }
    }
    return unresolvedBound_ < lb ? unresolvedBound_ : lb;
}

bool CcFaceSearch::rootUnit(CcWorkspace& ws, const CcFaceTable* guide) {
    if (ws.run.running()) {
        rootLpUnit(ws, guide);
        return !ws.run.running();
    }
    if (!presolve(ws)) {
        return true;  // depth 0: the search ends at once, exhausted, with no plan
    }
    ws.run.begin(HUGE_VAL, ws.lpCap());
    return false;
}

// A pair of the first or last segment has an end at the fixed start or goal,
// which rules out the faces it misses. A pair with no face left proves there
// is no plan (false); a pair with one is fixed at the root.
bool CcFaceSearch::presolve(CcWorkspace& ws) {
    const CcProblem& p = ws.problem;
    const std::size_t steps = ws.steps();
    (void)ws.lp.popPairs(0);
    depth_ = 0;
    rootPairs_ = 0;
    for (std::size_t t = 0; t < steps; t += (steps > 1 ? steps - 1 : 1)) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            const PlanObstacle& o = p.obstacles[i];
            std::size_t count = 0;
            std::size_t only = 0;
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                const bool startOk = t != 0 || endSlack(o, j, p.startX, p.startY, ws.margins.margin(0, i, j)) >= 0.0;
                const bool goalOk =
                    t + 1 != steps || endSlack(o, j, p.goalX, p.goalY, ws.margins.margin(steps, i, j)) >= 0.0;
                if (startOk && goalOk) {
                    ++count;
                    only = j;
                }
            }
            if (count == 0) {
                return false;
            }
            if (count == 1) {
                bool feasible = false;
                if (ws.lp.addPair(t, i, only, ws.margins.margin(t, i, only), ws.margins.margin(t + 1, i, only),
                                  &feasible) == core::Status::kOk &&
                    feasible) {
                    assigned_[t][i] = static_cast<std::uint8_t>(only);
                    ++rootPairs_;
                }
            }
        }
    }
    return true;
}

// One unit of the root's LP; at its end the search starts from it.
void CcFaceSearch::rootLpUnit(CcWorkspace& ws, const CcFaceTable* guide) {
    LpStatus st = LpStatus::kNotSolved;
    if (!ws.run.resume(ws.lp, &st)) {
        return;
    }
    ++nodes_;
    if (st == LpStatus::kOptimal) {
        evaluateNode(ws, guide);
    } else if (st != LpStatus::kInfeasible) {
        incomplete_ = true;
        unresolvedBound_ = 0.0;
    }
}

// The most violated unassigned pair at the LP's optimum into *wt, *wi (false:
// none, node->faces is then a plan's), every pair's best face into
// node->faces.
bool CcFaceSearch::mostViolatedPair(CcWorkspace& ws, NodePath* node, std::size_t* wt, std::size_t* wi) const {
    for (std::size_t tau = 0; tau <= ws.steps(); ++tau) {
        node->x[tau] = ws.lp.meanX(tau);
        node->y[tau] = ws.lp.meanY(tau);
    }
    ws.geometryWork += kScoreWork * ws.steps() * ws.obstacles() * kMaxObstacleFaces;
    double worst = 0.0;
    *wt = kMaxPlanSteps;
    *wi = 0;
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            if (assigned_[t][i] != kUnassigned) {
                node->faces[t][i] = assigned_[t][i];
                continue;
            }
            double best = -INFINITY;
            std::uint8_t bestFace = 0;
            for (std::size_t j = 0; j < ws.problem.obstacles[i].faceCount; ++j) {
                const double s = pairScore(ws.problem, ws.margins, t, i, j, node->x, node->y);
                if (s > best) {
                    best = s;
                    bestFace = static_cast<std::uint8_t>(j);
                }
            }
            node->faces[t][i] = bestFace;
            if (best < worst) {
                worst = best;
                *wt = t;
                *wi = i;
            }
        }
    }
    return *wt != kMaxPlanSteps;
}

void CcFaceSearch::evaluateNode(CcWorkspace& ws, const CcFaceTable* guide) {
    const double cost = ws.lp.cost();
    if (cost >= pruneThreshold(ws)) {
        return;
    }
    NodePath node;
    std::size_t wt = 0;
    std::size_t wi = 0;
    if (!mostViolatedPair(ws, &node, &wt, &wi)) {
        ws.incumbent.offerFromLp(ws.problem, ws.margins, ws.lp, node.faces, ws.searchScale(), nodes_, &ws.candidate,
                                 &ws.geometryWork);
        return;
    }
    if (rootPairs_ + depth_ >= kMaxPairs) {
        incomplete_ = true;  // cannot happen: every level assigns a new pair
        return;
    }
    pushLevel(ws, guide, node, wt, wi, cost);
}

// A level branching on pair (wt, wi): its faces by descending score (least
// violated first, the guide's face before them).
void CcFaceSearch::pushLevel(CcWorkspace& ws, const CcFaceTable* guide, const NodePath& node, std::size_t wt,
                             std::size_t wi, double bound) {
    Level& l = level_[depth_];
    l.t = static_cast<std::uint8_t>(wt);
    l.obstacle = static_cast<std::uint8_t>(wi);
    l.next = 0;
    l.bound = bound;
    const PlanObstacle& o = ws.problem.obstacles[wi];
    double score[kMaxObstacleFaces];
    l.count = 0;
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        score[j] = pairScore(ws.problem, ws.margins, wt, wi, j, node.x, node.y);
        if (guide != nullptr && (*guide)[wt][wi] == j) {
            score[j] = HUGE_VAL;  // the guide's face first
        }
        // Insertion by descending score: least violated face first.
        std::size_t pos = l.count;
        while (pos > 0 && score[l.order[pos - 1]] < score[j]) {
            l.order[pos] = l.order[pos - 1];
            --pos;
        }
        l.order[pos] = static_cast<std::uint8_t>(j);
        ++l.count;
    }
    ring_.save(ws.lp.solver(), depth_, &l.basis);
    ++depth_;
    maxDepth_ = depth_ > maxDepth_ ? depth_ : maxDepth_;
}

bool CcFaceSearch::searchUnit(CcWorkspace& ws, const CcFaceTable* guide) {
    if (ws.run.running()) {
        nodeLpUnit(ws, guide);
        return true;
    }
    // Each pass consumes one child (or pops a level), so kMaxPairs levels of
    // at most kMaxObstacleFaces children bound it.
    const std::size_t passes = kMaxPairs * (kMaxObstacleFaces + 1) + 1;
    for (std::size_t pass = 0; pass < passes && depth_ > 0; ++pass) {
        Level& l = level_[depth_ - 1];
        if (l.next >= l.count || l.bound >= pruneThreshold(ws)) {
            assigned_[l.t][l.obstacle] = kUnassigned;
            --depth_;
            continue;
        }
        const std::uint8_t face = l.order[l.next++];
        (void)ws.lp.popPairs(rootPairs_ + depth_ - 1);
        if (!ws.lp.solver().basisValid()) {
            ring_.restore(ws.lp.solver(), depth_ - 1, &l.basis);
        }
        assigned_[l.t][l.obstacle] = face;
        bool feasible = false;
        if (ws.lp.addPair(l.t, l.obstacle, face, ws.margins.margin(l.t, l.obstacle, face),
                          ws.margins.margin(l.t + 1U, l.obstacle, face), &feasible) != core::Status::kOk ||
            !feasible) {
            continue;
        }
        ws.run.begin(pruneThreshold(ws), ws.lpCap());
        nodeLpUnit(ws, guide);
        return true;
    }
    return false;
}

// One unit of a node's LP; at its end the node is evaluated.
void CcFaceSearch::nodeLpUnit(CcWorkspace& ws, const CcFaceTable* guide) {
    LpStatus st = LpStatus::kNotSolved;
    if (!ws.run.resume(ws.lp, &st)) {
        return;
    }
    ++nodes_;
    if (st == LpStatus::kOptimal) {
        evaluateNode(ws, guide);
    } else if (st != LpStatus::kInfeasible && st != LpStatus::kCutoff) {
        abandonNode(ws.run);
    }
}

void CcFaceSearch::abandonNode(CcSlicedLp& run) {
    run.stop();
    incomplete_ = true;
    const double bound = depth_ > 0 ? level_[depth_ - 1].bound : 0.0;
    unresolvedBound_ = bound < unresolvedBound_ ? bound : unresolvedBound_;
}

}  // namespace rse::deliberative

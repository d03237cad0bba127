#include "fsw/deliberative/cc_seeds.hpp"

#include "fsw/deliberative/cc_work_units.hpp"

namespace rse::deliberative {

namespace {
// Visibility variants: obstacles inflated by the margin at step
// N * kSeedStepsNumerator / 2; the segments shared among the legs by length,
// or one per leg and the rest parked at the goal ("front-loaded").
constexpr std::size_t kSeedStepsNumerator[] = {2, 1, 0, 0};
constexpr bool kSeedFrontLoaded[] = {false, false, false, true};
}  // namespace

void CcSeeds::resetCounts() {
    solves_ = 0;
    cost_ = INFINITY;
    found_ = false;
    hintPending_ = false;
    hintCost_ = INFINITY;
}

void CcSeeds::resetOrder() {
    nextSlot_ = 0;
    stage_ = Stage::kIdle;
    layered_.clear();
    guideValid_ = false;
    guideDistance_ = HUGE_VAL;
}

bool CcSeeds::setHint(const CcProblem& problem, const CcPlan& hint) {
    bool fits = nextSlot_ == 0 && solves_ == 0 && hint.steps == problem.steps;
    for (std::size_t t = 0; t < problem.steps && fits; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount && fits; ++i) {
            fits = hint.face[t][i] < problem.obstacles[i].faceCount;
        }
    }
    if (!fits) {
        return false;
    }
    for (std::size_t t = 0; t < problem.steps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
            hintFace_[t][i] = hint.face[t][i];
        }
    }
    hintPending_ = true;
    return true;
}

void CcSeeds::runHintUnit(CcWorkspace& ws) {
    // An earlier plan's faces (setHint), e.g. the plan at a looser bound:
    // re-solved at this problem's margins they give at once a plan close to
    // that one's route when it still fits, where the visibility seeds and a
    // search cut short by the budget may only find a longer one (issue 15
    // item 5: a 1e-9 plan 1 m longer than the 1e-8 one). Its LP and polish
    // run in units like any seed's (runUnit); lpUnit records its cost.
    hintPending_ = false;
    hintRunning_ = true;
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            faces_[t][i] = hintFace_[t][i];
        }
    }
    round_ = 0;
    startLp(ws);
    if (!ws.run.running()) {
        hintRunning_ = false;  // the hint's faces do not fit this problem's margins
    }
}

bool CcSeeds::runUnit(CcWorkspace& ws) {
    // One unit: a slice of the current seed (its LP, a Dijkstra vertex, a
    // slice of a layer), else the start of the next one.
    if (ws.run.running()) {
        lpUnit(ws);
        return true;
    }
    hintRunning_ = false;  // the hint's LP and polish, if any, are over
    if (stage_ == Stage::kDijkstra) {
        if (visibility_.settleOne(ws.problem, &ws.geometryWork)) {
            stage_ = Stage::kIdle;
            if (visibility_.cutPath(ws.problem, kSeedFrontLoaded[variant_], pathX_, pathY_)) {
                seedFromPath(ws, visibility_.distance());
            }
        }
        return true;
    }
    if (stage_ == Stage::kLayered) {
        layeredUnit(ws);
        return true;
    }
    if (nextSlot_ > kSeedVariants) {
        return false;
    }
    startSlot(ws);
    return true;
}

// The next slot. Order: the visibility variants from the most conservative
// inflation; the layered search (complete, dearer) once they have failed;
// then the remaining variants, which may shorten its plan.
void CcSeeds::startSlot(CcWorkspace& ws) {
    const std::size_t slot = nextSlot_++;
    if (slot == kLayeredSeedSlot) {
        if (!found_ && ws.params.layeredSeed) {
            layered_.begin();
            stage_ = Stage::kLayered;
        }
        return;
    }
    variant_ = slot < kLayeredSeedSlot ? slot : slot - 1;
    // Variant v inflates every face by its margin at step N kSeedStepsNumerator[v] / 2
    // (margins grow with the step: N is the conservative inflation, 0 the
    // optimistic one that keeps gaps open for the early steps).
    const std::size_t tauInflate = ws.steps() * kSeedStepsNumerator[variant_] / 2U;
    if (visibility_.build(ws.problem, ws.margins, tauInflate, &ws.geometryWork)) {
        stage_ = Stage::kDijkstra;
    }
}

void CcSeeds::layeredUnit(CcWorkspace& ws) {
    const CcLayeredSeed::Progress progress = layered_.step(ws.problem, ws.margins, &ws.geometryWork);
    if (progress == CcLayeredSeed::Progress::kRunning) {
        return;
    }
    stage_ = Stage::kIdle;
    if (progress == CcLayeredSeed::Progress::kFound) {
        seedFromPath(ws, layered_.path(ws.problem, ws.margins, pathX_, pathY_));
    }
}

// The faces the path in pathX_ / pathY_ clears best, the fixed-face LP and
// the polish rounds; `distance` is the path's length for the guide.
void CcSeeds::seedFromPath(CcWorkspace& ws, double distance) {
    chooseFacesAt(ws.problem, ws.margins, pathX_, pathY_, faces_);
    if (distance < guideDistance_) {
        // The search tries these faces first: the shortest visibility path's,
        // even when its own LP turns out infeasible (the margins grow along
        // the path; the search's dives then find the waypoints that fit, near
        // that path).
        for (std::size_t t = 0; t < ws.steps(); ++t) {
            for (std::size_t i = 0; i < ws.obstacles(); ++i) {
                guideFace_[t][i] = faces_[t][i];
            }
        }
        guideDistance_ = distance;
        guideValid_ = true;
    }
    // The fixed-face LP, then polish rounds (each one LP), in units.
    round_ = 0;
    startLp(ws);
}

// The fixed-face LP of faces_, started (its pivots run in units).
void CcSeeds::startLp(CcWorkspace& ws) {
    (void)ws.lp.popPairs(0);
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            const std::size_t j = faces_[t][i];
            bool feasible = false;
            if (ws.lp.addPair(t, i, j, ws.margins.margin(t, i, j), ws.margins.margin(t + 1, i, j), &feasible) !=
                    core::Status::kOk ||
                !feasible) {
                return;
            }
        }
    }
    ++solves_;
    ws.run.begin(HUGE_VAL, ws.lpCap());
}

// One unit of the seed's LP; at its optimum the plan is offered, then
// polished.
void CcSeeds::lpUnit(CcWorkspace& ws) {
    LpStatus st = LpStatus::kNotSolved;
    if (!ws.run.resume(ws.lp, &st) || st != LpStatus::kOptimal) {
        return;
    }
    ws.incumbent.offerFromLp(ws.problem, ws.margins, ws.lp, faces_, ws.searchScale(), 0U, &ws.candidate,
                             &ws.geometryWork);
    const double best = ws.incumbent.evenCost();
    if (std::isfinite(best)) {
        found_ = true;
        cost_ = best;
        if (hintRunning_) {
            hintCost_ = best;
        }
    }
    if (round_ >= kPolishRounds) {
        return;
    }
    ++round_;
    if (polish(ws)) {
        startLp(ws);
    }
}

// Each pair to the face its ends at the LP's optimum clear best (the path
// stays feasible, so the cost cannot rise); true when any moved.
bool CcSeeds::polish(CcWorkspace& ws) {
    for (std::size_t k = 0; k <= ws.steps(); ++k) {
        pathX_[k] = ws.lp.meanX(k);
        pathY_[k] = ws.lp.meanY(k);
    }
    bool changed = false;
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            const std::uint8_t old = faces_[t][i];
            double best = pairScore(ws.problem, ws.margins, t, i, old, pathX_, pathY_);
            for (std::size_t j = 0; j < ws.problem.obstacles[i].faceCount; ++j) {
                const double sc = pairScore(ws.problem, ws.margins, t, i, j, pathX_, pathY_);
                if (sc > best + 1e-9) {
                    best = sc;
                    faces_[t][i] = static_cast<std::uint8_t>(j);
                }
            }
            changed = changed || faces_[t][i] != old;
        }
    }
    ws.geometryWork += kScoreWork * ws.steps() * ws.obstacles() * kMaxObstacleFaces;
    return changed;
}

}  // namespace rse::deliberative

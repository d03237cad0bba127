#include "fsw/deliberative/cc_risk_allocation.hpp"

#include <cmath>

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_work_units.hpp"
#include "fsw/deliberative/gaussian.hpp"

namespace rse::deliberative {

namespace {
// A slack end keeps this share of its old delta (the rest moves towards its
// need), and no delta goes below evenDelta * kIraFloor.
constexpr double kIraKeep = 0.3;
constexpr double kIraFloor = 1e-6;
// Stretching the allocation: a round that certifies r <= Delta raises the
// allocation's budget by (Delta / r) x kStretchAim, at most x kMaxStretch a round.
constexpr double kStretchAim = 0.97;
constexpr double kMaxStretch = 8.0;
// The stretch has converged when the certified risk is this close below Delta.
constexpr double kStretchClose = 0.9;
}  // namespace

void CcRiskAllocation::reset() {
    rounds_ = 0;
    lastRound_ = false;
    ready_ = false;
}

bool CcRiskAllocation::step(CcWorkspace& ws, bool workLeft) {
    if (ws.certifier.running()) {
        return certifyUnit(ws, workLeft);
    }
    if (ws.run.running()) {
        return lpUnit(ws, workLeft);
    }
    if (ws.incumbent.best().status == CcStatus::kNoPlan || ws.obstacles() == 0 ||
        ws.problem.allocation != RiskAllocation::kOptimised || rounds_ >= ws.params.iraRounds || lastRound_ ||
        !workLeft) {
        return true;
    }
    if (!ready_) {
        return startRounds(ws);
    }
    nextRound(ws);
    return false;
}

// One segment of the round's candidate certified; at the last it is judged.
bool CcRiskAllocation::certifyUnit(CcWorkspace& ws, bool workLeft) {
    if (!workLeft) {
        ws.certifier.stop();
        return true;
    }
    if (ws.certifier.unit(ws.problem, &ws.candidate, &ws.geometryWork)) {
        return judge(ws);
    }
    return false;
}

// One slice of a round's LP: the best plan's (then the rounds start), or a
// round's (then its candidate is certified).
bool CcRiskAllocation::lpUnit(CcWorkspace& ws, bool workLeft) {
    if (!workLeft) {
        ws.run.stop();
        return true;
    }
    LpStatus st = LpStatus::kNotSolved;
    if (!ws.run.resume(ws.lp, &st)) {
        return false;  // runs on in the next unit
    }
    if (st != LpStatus::kOptimal) {
        return true;
    }
    if (!ready_) {
        ready_ = true;
    } else {
        candidate(ws);
    }
    return false;
}

// The best plan's faces, all pairs, its (even) deltas, from the search's
// budget; a budget certified so far: Delta when the search's plan is
// certified by Boole, none when it is not. True (over) when its LP cannot be
// built.
bool CcRiskAllocation::startRounds(CcWorkspace& ws) {
    const CcPlan& best = ws.incumbent.best();
    const bool certified = ws.incumbent.certified();
    budget_ = certified ? ws.riskBudget : ws.searchBudget;
    budgetLo_ = certified ? ws.riskBudget : 0.0;
    budgetHi_ = INFINITY;
    (void)ws.lp.popPairs(0);
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            const std::size_t j = best.face[t][i];
            delta_[t][i][0] = best.delta[t][i][0];
            delta_[t][i][1] = best.delta[t][i][1];
            bool feasible = false;
            if (ws.lp.addPair(t, i, j, ws.margins.margin(t, i, j), ws.margins.margin(t + 1, i, j), &feasible) !=
                    core::Status::kOk ||
                !feasible) {
                return true;
            }
        }
    }
    ws.run.begin(HUGE_VAL, ws.params.perLpIterations);
    return false;
}

// New deltas at the current solution and the round's LP started; or, with
// nothing to stretch, the LP's path as this round's candidate, the last.
void CcRiskAllocation::nextRound(CcWorkspace& ws) {
    ++rounds_;
    ws.geometryWork += 3U * kMarginWork * 2U * ws.steps() * ws.obstacles();  // risks, margins, the check
    EndFlags active;
    std::size_t activeCount = 0;
    double activeSum = 0.0;
    const double fixedSum = relaxSlackEnds(ws, active, &activeCount, &activeSum);
    const double residual = budget_ - fixedSum - activeSum;
    if (activeCount == 0 || !(residual > 0.0)) {
        // Nothing to stretch: the LP's path already meets the slack ends' new
        // deltas (each is at least its need there), so it is this round's
        // candidate as it stands, the last one (an uncertified search plan
        // still gets its evaluation).
        lastRound_ = true;
        candidate(ws);
        return;
    }
    const double add = shareFor(ws, active, residual / static_cast<double>(activeCount));
    applyDeltas(ws, active, add);
    ws.run.begin(HUGE_VAL, ws.params.perLpIterations);
}

// Every slack end's delta moved towards its need at the LP's path; the
// active ends flagged, counted and summed. Returns the slack ends' sum.
double CcRiskAllocation::relaxSlackEnds(CcWorkspace& ws, EndFlags& active, std::size_t* activeCount,
                                        double* activeSum) {
    const CcProblem& p = ws.problem;
    const CcPlan& best = ws.incumbent.best();
    const double floor = ws.margins.evenDelta() * kIraFloor;
    double fixedSum = 0.0;
    std::size_t k = 0;
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i, ++k) {
            const PlanObstacle& o = p.obstacles[i];
            const std::size_t j = best.face[t][i];
            for (std::size_t e = 0; e < 2; ++e) {
                const std::size_t tau = t + e;
                active[t][i][e] = ws.lp.pairActive(k, e);
                if (active[t][i][e]) {
                    *activeSum += delta_[t][i][e];
                    ++*activeCount;
                    continue;
                }
                const double raw = endSlack(o, j, ws.lp.meanX(tau), ws.lp.meanY(tau), 0.0) - 2.0 * kSafetyM;
                const double variance = faceVariance(o.normalX[j], o.normalY[j], p.startCov, p.processSigmaM,
                                                     static_cast<unsigned>(tau));
                double need = endRisk(raw, variance);
                need = need > floor ? need : floor;
                double next = kIraKeep * delta_[t][i][e] + (1.0 - kIraKeep) * need;
                next = next < delta_[t][i][e] ? next : delta_[t][i][e];
                delta_[t][i][e] = next;
                fixedSum += next;
            }
        }
    }
    return fixedSum;
}

// Each active end's share of the residual, shaved until the deltas summed in
// plan order fit the budget (rounding only).
double CcRiskAllocation::shareFor(const CcWorkspace& ws, const EndFlags& active, double add) const {
    for (int attempt = 0; attempt < 8; ++attempt) {
        double sum = 0.0;
        for (std::size_t t = 0; t < ws.steps(); ++t) {
            for (std::size_t i = 0; i < ws.obstacles(); ++i) {
                for (std::size_t e = 0; e < 2; ++e) {
                    sum += active[t][i][e] ? delta_[t][i][e] + add : delta_[t][i][e];
                }
            }
        }
        if (sum <= budget_) {
            break;
        }
        add *= 1.0 - 1e-9 * static_cast<double>(attempt + 1);
        if (attempt == 7) {
            add = 0.0;
        }
    }
    return add;
}

// The active ends get their share (below 0.49); every pair's new margins.
void CcRiskAllocation::applyDeltas(CcWorkspace& ws, const EndFlags& active, double add) {
    const CcPlan& best = ws.incumbent.best();
    std::size_t k = 0;
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i, ++k) {
            const std::size_t j = best.face[t][i];
            for (std::size_t e = 0; e < 2; ++e) {
                if (active[t][i][e]) {
                    double d = delta_[t][i][e] + add;
                    d = d < 0.49 ? d : 0.49;
                    delta_[t][i][e] = d;
                }
            }
            (void)ws.lp.setPairMargins(k, faceMargin(ws.problem, i, j, t, delta_[t][i][0]),
                                       faceMargin(ws.problem, i, j, t + 1, delta_[t][i][1]));
        }
    }
}

// The candidate of a round: its LP's path with its deltas; its certified
// risk is evaluated next (one segment a unit), then judged.
void CcRiskAllocation::candidate(CcWorkspace& ws) {
    CcPlan& c = ws.candidate;
    c = ws.incumbent.best();
    c.status = CcStatus::kFeasible;
    for (std::size_t tau = 0; tau <= ws.steps(); ++tau) {
        c.meanX[tau] = ws.lp.meanX(tau);
        c.meanY[tau] = ws.lp.meanY(tau);
    }
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            for (std::size_t e = 0; e < 2; ++e) {
                c.delta[t][i][e] = delta_[t][i][e];
            }
        }
    }
    measurePath(ws.steps(), &c);
    ws.certifier.start();
}

// Keeps the candidate when it is certified within Delta and shorter, and sets
// the next round's budget: raised towards Delta / (certified risk) when it
// certified, halfway back to the last certified budget when it did not. True
// when the rounds have converged.
bool CcRiskAllocation::judge(CcWorkspace& ws) {
    const CcPlan& c = ws.candidate;
    const double certified = c.riskUsed;
    double deltaSum = 0.0;
    const bool ok = checkPlanShape(ws.problem, c, ws.problem.riskBound, &deltaSum) == core::Status::kOk &&
                    certified <= ws.riskBudget;
    const double previous = ws.incumbent.best().cost;
    const bool gain = ok && (!ws.incumbent.certified() || c.cost < previous);
    if (gain) {
        ws.incumbent.keep(c, true);
    }
    if (ok) {
        budgetLo_ = budget_ > budgetLo_ ? budget_ : budgetLo_;
        const double aim = certified > 0.0 ? kStretchAim * ws.riskBudget / certified : kMaxStretch;
        double next = budget_ * (aim < kMaxStretch ? aim : kMaxStretch);
        if (std::isfinite(budgetHi_)) {
            const double half = 0.5 * (budget_ + budgetHi_);
            next = next < half ? next : half;
        }
        budget_ = next > budget_ ? next : budget_;
    } else {
        budgetHi_ = budget_ < budgetHi_ ? budget_ : budgetHi_;
        budget_ = 0.5 * (budgetLo_ + budgetHi_);
        restartFromBest(ws);
    }
    const bool close = ok && certified >= kStretchClose * ws.riskBudget;
    const bool narrow = std::isfinite(budgetHi_) && budgetHi_ <= budgetLo_ * 1.02;
    const bool gained = gain && c.cost < previous - 1e-9 * (1.0 + previous);
    return !gained && rounds_ > 2 && (close || narrow);
}

// Back to the best plan's deltas, scaled down to the new budget when they
// pass it (an uncertified search plan's do).
void CcRiskAllocation::restartFromBest(const CcWorkspace& ws) {
    const CcPlan& best = ws.incumbent.best();
    double sum = 0.0;
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            sum += best.delta[t][i][0] + best.delta[t][i][1];
        }
    }
    const double scale = sum > budget_ ? budget_ / sum * (1.0 - kRiskSafety) : 1.0;
    for (std::size_t t = 0; t < ws.steps(); ++t) {
        for (std::size_t i = 0; i < ws.obstacles(); ++i) {
            delta_[t][i][0] = best.delta[t][i][0] * scale;
            delta_[t][i][1] = best.delta[t][i][1] * scale;
        }
    }
}

}  // namespace rse::deliberative

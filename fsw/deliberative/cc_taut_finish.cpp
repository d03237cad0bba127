#include "fsw/deliberative/cc_taut_finish.hpp"

#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/plan_tauten.hpp"

namespace rse::deliberative {

bool CcTautFinish::step(CcWorkspace& ws, bool workLeft) {
    CcPlan& taut = ws.candidate;
    if (!tautened_) {
        // The taut path keeps every face and delta: its deltas' sum is the
        // plan's, and its risk bound is evaluated next.
        tautened_ = true;
        taut = ws.incumbent.best();
        ws.geometryWork += kWorkPerTry * tautenPlan(ws.problem, &taut);
        claimBooleRisk(ws.problem, &taut);
        ws.certifier.start();
        return false;
    }
    bool evaluated = false;
    if (ws.certifier.running() && workLeft) {
        evaluated = ws.certifier.unit(ws.problem, &taut, &ws.geometryWork);
        if (!evaluated) {
            return false;
        }
    }
    // Evaluated, or cut short by the budget (then the deltas' sum stands).
    ws.certifier.stop();
    if (!evaluated) {
        claimBooleRisk(ws.problem, &taut);
    }
    double deltaSum = 0.0;
    const bool shape = checkPlanShape(ws.problem, taut, ws.problem.riskBound, &deltaSum) == core::Status::kOk;
    if (shape && taut.riskUsed <= ws.riskBudget && taut.cost <= ws.incumbent.best().cost) {
        ws.incumbent.keep(taut, ws.incumbent.certified());
    } else {
        ++refused_;
    }
    return true;
}

}  // namespace rse::deliberative

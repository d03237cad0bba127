#include "fsw/deliberative/cc_workspace.hpp"

namespace rse::deliberative {

core::Status CcWorkspace::begin(const CcProblem& given, const CcPlannerParams& settings) {
    incumbent.reset();
    certifier.stop();
    run.stop();
    problem = given;
    params = settings;
    incumbent.setSteps(problem.steps);
    riskBudget = problem.riskBound * (1.0 - kRiskSafety);
    searchBudget = riskBudget * searchScale();
    geometryWork = 0;
    margins.build(problem, searchBudget, &geometryWork);
    // The LP keeps a pointer to the problem: this copy.
    return lp.setup(problem);
}

}  // namespace rse::deliberative

#include "fsw/deliberative/cc_risk_certifier.hpp"

#include "fsw/deliberative/cc_work_units.hpp"
#include "fsw/deliberative/plan_risk.hpp"

namespace rse::deliberative {

bool CcRiskCertifier::unit(const CcProblem& problem, CcPlan* plan, std::uint64_t* work) {
    RiskWork w;
    const double r = certifiedSegmentRisk(problem, *plan, segment_, &w);
    *work += kTailWork * w.tails + kOrthantWork * w.orthants + kScoreWork * w.lineSolves;
    plan->segmentRisk[segment_] = r;
    total_ += r;
    if (++segment_ < problem.steps) {
        return false;
    }
    running_ = false;
    plan->riskUsed = total_;
    return true;
}

}  // namespace rse::deliberative

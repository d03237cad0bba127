// A plan's certified risk (plan_risk.hpp) evaluated one segment a unit of
// the planner's work (cc_planner.hpp, "Bounded and sliceable"): per
// (segment, obstacle) the smaller of its deltas' sum and the bound from the
// means, summed into each segment's share and riskUsed. A segment is M pairs:
// at most 8 x (18 tails and 9 + 32 bivariate orthants), charged kTailWork a
// tail and kOrthantWork an orthant (cc_work_units.hpp). The risk allocation
// certifies each round's candidate with it, the finish the taut plan.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"

namespace rse::deliberative {

class CcRiskCertifier {
public:
    void start() {
        segment_ = 0;
        total_ = 0.0;
        running_ = true;
    }
    // One segment of *plan: its segmentRisk; true when the last is done
    // (then riskUsed is their sum and the certifier stops).
    bool unit(const CcProblem& problem, CcPlan* plan, std::uint64_t* work);
    bool running() const { return running_; }
    void stop() { running_ = false; }

private:
    bool running_ = false;
    std::size_t segment_ = 0;
    double total_ = 0.0;
};

}  // namespace rse::deliberative

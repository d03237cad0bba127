// The planner's best plan so far (cc_planner.hpp): what the seeds and the
// search offer at their LPs' optima, what the risk allocation and the taut
// finish improve, and what CcPlanner::plan() shows once it is certified.
//
// offerFromLp: the plan at the LP's optimum with the given faces and the
// search's deltas (cc_end_margins.hpp), verified at the search's budget
// (checkPlanShape, the deltas' sum within Delta x the search scale) and kept
// when it is shorter than the search's best (evenCost(): the even split's
// incumbent, which prunes the search). It is certified when its deltas' sum
// is within Delta itself (Boole); a wide search's plans are not until the
// allocation certifies one.
#pragma once

#include <cmath>
#include <cstdint>

#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_face_scores.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_problem.hpp"

namespace rse::deliberative {

class CcIncumbent {
public:
    // No plan (status kNoPlan, no steps), no search cost, counts cleared.
    void reset();
    void setSteps(std::uint8_t steps) { best_.steps = steps; }

    // Builds the LP's plan in *scratch and keeps it when it verifies and
    // beats evenCost(); `node` is the search's node count (0 for a seed).
    void offerFromLp(const CcProblem& problem, const CcEndMargins& margins, const CcLp& lp, const CcFaceTable& face,
                     double searchScale, std::uint32_t node, CcPlan* scratch, std::uint64_t* work);

    const CcPlan& best() const { return best_; }
    bool certified() const { return certified_; }
    // The allocation's or the finish's better plan, or no plan at the end.
    void keep(const CcPlan& plan, bool certified) {
        best_ = plan;
        certified_ = certified;
    }
    void setStatus(CcStatus status) { best_.status = status; }

    double evenCost() const { return evenCost_; }            // the search's best (INFINITY: none)
    std::uint32_t improvements() const { return improvements_; }
    std::uint32_t lastNode() const { return lastNode_; }      // node count at the last improvement

private:
    CcPlan best_{};
    bool certified_ = false;  // best_ is certified within Delta (plan() hands it out)
    double evenCost_ = 0.0;
    std::uint32_t improvements_ = 0;
    std::uint32_t lastNode_ = 0;
};

}  // namespace rse::deliberative

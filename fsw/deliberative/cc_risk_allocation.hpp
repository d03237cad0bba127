// The planner's risk allocation (cc_planner.hpp; kOptimised only): iterative
// risk allocation (Ono & Williams 2008) on the best plan's faces, stretched
// on the certified bound (issue 15 item 3).
//
// Each round: every end whose constraint is slack at the LP's optimum moves
// 70 % of the way from its delta to the risk it has at the plan (computed
// 2 kSafetyM inside its slack, so the plan stays feasible; never below
// evenDelta x kIraFloor), the budget B minus the deltas is shared equally by
// the active ends, and the LP is solved again (warm: only right-hand sides
// change). Each round's plan is then certified (cc_risk_certifier.hpp, one
// segment a unit): per (segment, obstacle) the smaller of its two deltas and
// the bound from the means, summed. Kept when that is within Delta' and the
// plan is shorter.
//
// Stretch: B starts at Delta' (at the search's budget when its plan is not
// certified: a wide search); a round that certifies r raises it to
// B (Delta' / r) x 0.97 (at most x 8, and at most halfway to the least B that
// failed); a round that fails halves the way back to the largest B that
// certified and restarts from the best plan's deltas (scaled to B). So the
// deltas' own sum may pass Delta while the certified risk does not. At most
// iraRounds rounds; the rounds end once one gains nothing while the certified
// risk is within 90 % of Delta or B's bracket is within 2 %. Never worse than
// the search's plan.
//
// A unit: a slice of a round's LP (cc_sliced_lp.hpp), a segment of its
// certification, or a round's new deltas. Memory: 3.1 KiB. No heap.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/cc_workspace.hpp"

namespace rse::deliberative {

class CcRiskAllocation {
public:
    // A new plan: no rounds.
    void reset();
    // One unit; workLeft false when the allocation's share of the work
    // budget is spent. True when the allocation is over (the best plan is
    // the incumbent's).
    bool step(CcWorkspace& ws, bool workLeft);
    std::uint32_t rounds() const { return rounds_; }

private:
    using EndFlags = bool[kMaxPlanSteps][kMaxPlanObstacles][2];

    bool certifyUnit(CcWorkspace& ws, bool workLeft);
    bool lpUnit(CcWorkspace& ws, bool workLeft);
    bool startRounds(CcWorkspace& ws);
    void nextRound(CcWorkspace& ws);
    double relaxSlackEnds(CcWorkspace& ws, EndFlags& active, std::size_t* activeCount, double* activeSum);
    double shareFor(const CcWorkspace& ws, const EndFlags& active, double add) const;
    void applyDeltas(CcWorkspace& ws, const EndFlags& active, double add);
    void candidate(CcWorkspace& ws);
    bool judge(CcWorkspace& ws);
    void restartFromBest(const CcWorkspace& ws);

    double delta_[kMaxPlanSteps][kMaxPlanObstacles][2] = {};
    std::uint32_t rounds_ = 0;
    bool ready_ = false;       // the best plan's LP is solved: rounds may start
    bool lastRound_ = false;   // nothing left to stretch: this round's candidate is the last
    double budget_ = 0.0;      // the deltas' sum this round (may pass Delta)
    double budgetLo_ = 0.0;    // the largest budget whose plan certified within Delta
    double budgetHi_ = 0.0;    // the least budget whose plan did not (INFINITY: none yet)
};

}  // namespace rse::deliberative

// The planner's finish (cc_planner.hpp): the best plan pulled taut
// (plan_tauten.hpp) and its certified risk evaluated (cc_risk_certifier.hpp,
// one segment a unit, while the work budget lasts; cut short, the deltas' sum
// is its claim). The taut plan keeps every face and delta; it replaces the
// best plan when it passes the checks (cc_plan_checks.hpp) within Delta' and
// costs no more; else the plan is kept as planned (refused() counts those).
//
// A unit: the tautening (kWorkPerTry a position tried), or a segment of the
// certification.
#pragma once

#include <cstdint>

#include "fsw/deliberative/cc_workspace.hpp"

namespace rse::deliberative {

class CcTautFinish {
public:
    // Work units charged per position tautening tries (2 M face checks).
    static constexpr std::uint64_t kWorkPerTry = 64;

    // A new plan: nothing refused.
    void reset() {
        refused_ = 0;
        tautened_ = false;
    }
    // The finish begins (the allocation is over and the best plan certified).
    void begin() { tautened_ = false; }
    // One unit; workLeft false once the plan's work budget is spent. True
    // when the finish is over (the incumbent holds the final plan; its
    // status is the caller's).
    bool step(CcWorkspace& ws, bool workLeft);
    std::uint32_t refused() const { return refused_; }

private:
    bool tautened_ = false;
    std::uint32_t refused_ = 0;
};

}  // namespace rse::deliberative

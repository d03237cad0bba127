// One LP solve of the planner run in slices (cc_planner.hpp, "Bounded and
// sliceable"): each unit of work runs at most kPivotsPerUnit pivots and the
// next resumes from the basis LpSolver keeps on kIterationLimit, until the LP
// ends or its own pivot cap (limit) runs out. Seeds, the search's root and
// nodes, and the allocation rounds each run their LPs through it; only one
// LP is under way at a time.
#pragma once

#include <cstdint>

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/lp_solver.hpp"

namespace rse::deliberative {

class CcSlicedLp {
public:
    static constexpr std::uint32_t kPivotsPerUnit = 16;

    // The LP as it stands in the CcLp becomes the one under way: at most
    // `limit` pivots in all, stopped once its bound reaches `cutoff`.
    void begin(double cutoff, std::uint32_t limit) {
        running_ = true;
        pivots_ = 0;
        limit_ = limit;
        cutoff_ = cutoff;
    }

    // At most kPivotsPerUnit pivots; false while the LP runs on (the next
    // call continues it), true when it has ended (*status: its outcome;
    // kIterationLimit when its pivot cap ran out).
    bool resume(CcLp& lp, LpStatus* status) {
        const std::uint32_t left = limit_ > pivots_ ? limit_ - pivots_ : 0U;
        *status = lp.solve(left < kPivotsPerUnit ? left : kPivotsPerUnit, cutoff_);
        pivots_ += lp.solver().lastIterations();
        if (*status == LpStatus::kIterationLimit && pivots_ < limit_) {
            return false;
        }
        running_ = false;
        return true;
    }

    bool running() const { return running_; }
    // Drops the LP under way (budget spent, or its phase ended).
    void stop() { running_ = false; }

private:
    bool running_ = false;
    std::uint32_t pivots_ = 0;
    std::uint32_t limit_ = 0;
    double cutoff_ = 0.0;
};

}  // namespace rse::deliberative

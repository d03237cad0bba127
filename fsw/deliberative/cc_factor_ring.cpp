#include "fsw/deliberative/cc_factor_ring.hpp"

namespace rse::deliberative {

void CcFactorRing::reset(std::size_t variables) {
    size_ = LpSolver::factorDoubles(variables);
    slots_ = kPoolDoubles / size_;
    slots_ = slots_ < kMaxSlots ? slots_ : kMaxSlots;
    for (std::size_t k = 0; k < kMaxSlots; ++k) {
        owner_[k] = kNoLevel;
    }
    restores_ = 0;
}

void CcFactorRing::save(const LpSolver& lp, std::size_t level, LpBasis* basis) {
    if (slots_ == 0) {
        lp.saveBasis(basis);
        return;
    }
    const std::size_t slot = level % slots_;
    if (lp.saveFactor(basis, &pool_[slot * size_], size_) == core::Status::kOk) {
        owner_[slot] = level;
    } else {
        lp.saveBasis(basis);
    }
}

void CcFactorRing::restore(LpSolver& lp, std::size_t level, LpBasis* basis) {
    if (slots_ > 0) {
        const std::size_t slot = level % slots_;
        if (owner_[slot] == level && lp.restoreFactor(*basis, &pool_[slot * size_], size_) == core::Status::kOk) {
            ++restores_;
            return;
        }
    }
    (void)lp.restoreBasis(*basis);
    // The slot is free again once the levels above this one are gone.
    if (lp.basisValid()) {
        save(lp, level, basis);
    }
}

}  // namespace rse::deliberative

// The factors (A_B^-1) of the deepest levels of the planner's search
// (cc_face_search.hpp), kept so that going back to a level copies its factor
// instead of refactorising its basis: a ring of slots over the search stack,
// level d in slot d mod slots (the deepest levels win; an older level whose
// slot was taken is refactorised from its saved basis, and then takes its
// slot again). Without slots (a factor too large for the pool) every level
// keeps its basis only.
//
// Memory: the pool, 4 factors of the largest LP (72 x 73 doubles): 164 KiB.
// No heap.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/lp_solver.hpp"

namespace rse::deliberative {

class CcFactorRing {
public:
    static constexpr std::size_t kPoolDoubles = 4 * LpSolver::factorDoubles(kLpMaxVariables);
    static constexpr std::size_t kMaxSlots = 64;

    // Empty slots sized for an LP of `variables` variables; restores() = 0.
    void reset(std::size_t variables);
    // Saves the solver's basis for level `level` into *basis, and its factor
    // into the level's slot when it fits.
    void save(const LpSolver& lp, std::size_t level, LpBasis* basis);
    // Takes the solver back to level `level`: its factor when its slot still
    // holds it, else its basis (refactorised; the slot is then saved again).
    void restore(LpSolver& lp, std::size_t level, LpBasis* basis);

    std::size_t slots() const { return slots_; }
    std::uint32_t restores() const { return restores_; }  // levels restored from their factor

private:
    static constexpr std::size_t kNoLevel = static_cast<std::size_t>(-1);

    double pool_[kPoolDoubles] = {};
    std::size_t size_ = 0;   // doubles per factor
    std::size_t slots_ = 0;
    std::size_t owner_[kMaxSlots] = {};  // the level whose factor the slot holds
    std::uint32_t restores_ = 0;
};

}  // namespace rse::deliberative

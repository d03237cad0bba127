// LpSolver's refactorisation (lp_solver.hpp, "Numerics"): A_B^-1 computed
// from scratch every kRefactorPeriod pivots, after a drift, and when a basis
// is restored; the rest of the solver is in lp_solver.cpp.
#include <cmath>

#include "fsw/deliberative/lp_solver.hpp"

namespace rse::deliberative {

// A_B^-1 from scratch: LU with partial pivoting (P A_B = L U) that skips
// zeros, then A_B^-1 column by column by sparse triangular solves. A_B's rows
// have a few nonzeros each; when the variables are ordered so that each row's
// nonzeros are near each other (the planner orders them by time step) L and U
// stay banded and this costs O(n^2 b) for bandwidth b instead of O(n^3).
bool LpSolver::refactor() {
    ++refactorizations_;
    sinceRefactor_ = 0;
    const std::size_t n = n_;
    work_ += 5 * n * n;  // building A_B, the pivot searches
    loadBasisMatrix();
    if (!factorLu()) {
        basisValid_ = false;
        return false;
    }
    recordLuPatterns();
    invertFromLu();
    basisValid_ = true;
    recomputePrimal();
    recomputeDual();
    for (std::size_t p = 0; p < n; ++p) {
        if (y_[p] < -1e-7) {
            return false;  // not a dual feasible basis (should not happen)
        }
    }
    return true;
}

// lu_ = A_B (row p: basis row p), perm_ the identity.
void LpSolver::loadBasisMatrix() {
    const std::size_t n = n_;
    for (std::size_t p = 0; p < n; ++p) {
        for (std::size_t k = 0; k < n; ++k) {
            lu_[p][k] = 0.0;
        }
        const Row& row = row_[basis_[p]];
        for (std::size_t e = 0; e < row.count; ++e) {
            lu_[p][row.index[e]] = row.value[e];
        }
        perm_[p] = static_cast<std::uint8_t>(p);
    }
}

// P A_B = L U in place in lu_ (L's unit diagonal implied); false when a pivot
// is below kSingularTol (a singular basis).
bool LpSolver::factorLu() {
    const std::size_t n = n_;
    std::uint8_t rowNz[kLpMaxVariables];
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t best = k;
        double bestAbs = std::fabs(lu_[k][k]);
        for (std::size_t i = k + 1; i < n; ++i) {
            const double a = std::fabs(lu_[i][k]);
            if (a > bestAbs) {
                bestAbs = a;
                best = i;
            }
        }
        if (bestAbs < kSingularTol) {
            return false;
        }
        if (best != k) {
            for (std::size_t j = 0; j < n; ++j) {
                const double t = lu_[k][j];
                lu_[k][j] = lu_[best][j];
                lu_[best][j] = t;
            }
            const std::uint8_t t = perm_[k];
            perm_[k] = perm_[best];
            perm_[best] = t;
        }
        // The pivot row's nonzeros right of the diagonal.
        std::size_t nz = 0;
        for (std::size_t j = k + 1; j < n; ++j) {
            if (lu_[k][j] != 0.0) {
                rowNz[nz++] = static_cast<std::uint8_t>(j);
            }
        }
        const double inv = 1.0 / lu_[k][k];
        for (std::size_t i = k + 1; i < n; ++i) {
            if (lu_[i][k] == 0.0) {
                continue;
            }
            const double f = lu_[i][k] * inv;
            lu_[i][k] = f;
            for (std::size_t e = 0; e < nz; ++e) {
                lu_[i][rowNz[e]] -= f * lu_[k][rowNz[e]];
            }
        }
    }
    return true;
}

// Nonzero patterns: L by column (below the diagonal), U by column (above).
void LpSolver::recordLuPatterns() {
    const std::size_t n = n_;
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t lc = 0;
        for (std::size_t i = k + 1; i < n; ++i) {
            if (lu_[i][k] != 0.0) {
                lIndex_[k][lc++] = static_cast<std::uint8_t>(i);
            }
        }
        lCount_[k] = static_cast<std::uint8_t>(lc);
        std::size_t uc = 0;
        for (std::size_t i = 0; i < k; ++i) {
            if (lu_[i][k] != 0.0) {
                uIndex_[k][uc++] = static_cast<std::uint8_t>(i);
            }
        }
        uCount_[k] = static_cast<std::uint8_t>(uc);
    }
}

// Column p of A_B^-1 solves A_B z = e_p, i.e. L U z = P e_p.
void LpSolver::invertFromLu() {
    const std::size_t n = n_;
    std::size_t factorNonzeros = 0;
    for (std::size_t k = 0; k < n; ++k) {
        factorNonzeros += lCount_[k] + uCount_[k];
    }
    work_ += 5 * n * (factorNonzeros + 2 * n) / 2;
    double z[kLpMaxVariables];
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t p = perm_[i];  // P e_p = e_i
        for (std::size_t k = 0; k < n; ++k) {
            z[k] = 0.0;
        }
        z[i] = 1.0;
        for (std::size_t k = i; k < n; ++k) {
            const double zk = z[k];
            if (zk == 0.0) {
                continue;
            }
            for (std::size_t e = 0; e < lCount_[k]; ++e) {
                z[lIndex_[k][e]] -= lu_[lIndex_[k][e]][k] * zk;
            }
        }
        for (std::size_t k = n; k-- > 0;) {
            if (z[k] == 0.0) {
                continue;
            }
            const double zk = z[k] / lu_[k][k];
            z[k] = zk;
            for (std::size_t e = 0; e < uCount_[k]; ++e) {
                z[uIndex_[k][e]] -= lu_[uIndex_[k][e]][k] * zk;
            }
        }
        for (std::size_t k = 0; k < n; ++k) {
            binv_[k][p] = z[k];
        }
    }
}

}  // namespace rse::deliberative

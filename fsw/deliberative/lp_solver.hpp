// A small dense linear program solver for the deliberative planner: the dual
// simplex method on the inequality form, statically allocated, with a warm
// start when rows are added or right-hand sides change (what branch and bound
// and iterative risk allocation do between solves).
//
//   minimise c . x   subject to   a_r . x <= b_r  (r = 0 .. rows - 1),   lo <= x <= hi
//
// Method. A basis is a set of n rows (bound rows and general rows) whose
// matrix A_B is nonsingular; its vertex is x = A_B^-1 b_B and its multipliers
// are y_B = -A_B^-T c (the KKT condition c + A' y = 0). The basis is dual
// feasible when y_B >= 0; it is optimal when its vertex also satisfies every
// other row. Each dual simplex pivot takes a violated row r, computes
// w = A_B^-T a_r, and removes the basis row p that keeps y >= 0 longest as
// r's multiplier grows (ratio test y_p / w_p over w_p > 0, Harris's two
// passes with the largest w_p among near-ties); no w_p > 0 proves the LP
// infeasible (a dual ray). This is the dual simplex of the standard-form dual,
// whose basis is n x n: n <= 72 here, so A_B^-1 is kept explicitly (an n^2
// update per pivot). Rows are stored scaled to a largest coefficient of 1.
// Pricing: the most violated row; a full scan keeps the 8 most violated rows
// as candidates for the next pivots (multiple pricing) until none of them is
// violated; optimality is only declared after a full scan.
//
// Warm start. Dual feasibility depends on A_B and c only, so after rows are
// added, or right-hand sides or bounds change, the last basis is still dual
// feasible and solve() simply continues from it (typically a few pivots). Rows
// can be dropped from the end (truncateRows); a basis that used a dropped row
// is no longer a basis of the LP, so callers save a basis before adding rows
// and go back to it: saveBasis/restoreBasis (one refactorisation) or
// saveFactor/restoreFactor (a copy of A_B^-1, n^2 doubles). Without a valid
// basis solve() starts cold from the bound rows.
//
// Cutoff. Every basis the dual simplex visits is dual feasible, so its
// objective c . x = -b . y is a lower bound on the LP's optimum that never
// decreases: solve(maxIterations, cutoff) stops with kCutoff as soon as it
// reaches the cutoff (branch and bound prunes without finishing the LP).
//
// Start and unboundedness (artificial bounding). The cold basis is one bound
// row per variable: the lower bound where c_k > 0, the upper where c_k < 0,
// the lower where c_k = 0; it is dual feasible by construction. An infinite
// bound is replaced by +-artificialBound (default 1e6): the LP then always has
// a bounded optimum, and an optimum whose multiplier on an artificial bound is
// positive means the real LP is unbounded (kUnbounded). So the box
// [-artificialBound, artificialBound] is the solver's world: a feasible region
// wholly outside it reads as infeasible. Callers with real bounds on every
// variable (the planner) never meet this.
//
// Degeneracy. A run of kBlandAfterDegeneratePivots pivots that do not move
// the dual objective switches to Bland's rule (lowest-index violated row,
// lowest-index leaving row among exact ratio ties), which cannot cycle; the
// first nondegenerate pivot switches back.
//
// Numerics. A_B^-1 is recomputed from scratch every kRefactorPeriod pivots
// (lp_solver_refactor.cpp): LU with partial pivoting that skips zeros, then
// the inverse column by column by sparse triangular solves; with variables
// ordered so that each row's nonzeros are close (the planner orders them by
// time step) L and U stay banded and this costs O(n^2 b), not O(n^3).
// Before optimality is declared x and y are recomputed from A_B^-1, and a
// basis row that x misses by more than kResidualTol triggers a
// refactorisation. A singular basis (pivot below
// kSingularTol) falls back to the cold basis. Tolerances: a row is violated
// when (a_r . x - b_r) / max|a_r| > kPrimalTol (1e-9); pivots need
// w_p > kPivotTol (1e-9); y >= -kDualTol (1e-12). Callers that need a strict
// inequality tighten their right-hand side by more than kPrimalTol (the
// planner does, by 1e-6 m).
//
// Sizes and memory: at most kLpMaxVariables = 72 variables (3 N - 2 = 70 for
// the planner's N = 24), kLpMaxRows = 1024 general rows (the planner's
// 16 N + 2 N M = 768 at N = 24, M = 8) of at most kLpMaxRowEntries = 8
// nonzeros each, plus the 2 n bound rows. The rows take 1168 x 96 B = 110 KiB,
// A_B^-1 and the LU scratch 2 x 72 x 72 doubles = 81 KiB, the LU's patterns
// 10 KiB: sizeof(LpSolver) = 211 680 B (x86-64 and aarch64). No heap, no
// recursion; every loop is bounded by the sizes and the iteration limit given
// to solve().
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"

namespace rse::deliberative {

constexpr std::size_t kLpMaxVariables = 72;  // a multiple of 4: the SIMD loops run over n rounded up to 4
static_assert(kLpMaxVariables % 4 == 0, "padded loops");
constexpr std::size_t kLpMaxRows = 1024;
constexpr std::size_t kLpMaxRowEntries = 8;
constexpr std::size_t kLpMaxAllRows = 2 * kLpMaxVariables + kLpMaxRows;

enum class LpStatus : std::uint8_t {
    kNotSolved = 0,
    kOptimal = 1,
    kInfeasible = 2,      // proven by a dual ray (no w_p > 0 in a ratio test)
    kUnbounded = 3,       // the optimum leans on an artificial bound
    kIterationLimit = 4,  // the pivot budget ran out; the basis is kept, solve() continues
    kNumericalFailure = 5, // a singular basis after falling back to the cold start
    kCutoff = 6            // the objective reached the cutoff: the LP's optimum is >= cutoff
};

const char* toString(LpStatus status);

// A basis to go back to: the n row ids (internal numbering, see rowIdOfBound).
struct LpBasis {
    std::uint16_t count = 0;
    std::uint16_t sincePivots = 0;  // pivots since the factor was computed (saveFactor)
    std::uint16_t row[kLpMaxVariables] = {};
};

class LpSolver {
public:
    static constexpr double kPrimalTol = 1e-9;
    static constexpr double kDualTol = 1e-12;
    static constexpr double kPivotTol = 1e-9;
    static constexpr double kSingularTol = 1e-11;
    static constexpr std::uint32_t kRefactorPeriod = 256;
    static constexpr double kResidualTol = 1e-10;
    static constexpr std::uint32_t kBlandAfterDegeneratePivots = 40;

    // A new LP over `variables` variables: no rows, c = 0, every variable free
    // (artificially bounded). kNoCapacity if variables is 0 or > kLpMaxVariables.
    core::Status reset(std::size_t variables);

    // kInvalidArgument for an index out of range or a non-finite value.
    core::Status setObjective(std::size_t variable, double c);
    // lo <= hi, either may be infinite (then +-artificialBound applies).
    core::Status setBounds(std::size_t variable, double lo, double hi);
    // The artificial bound (> 0, finite) for infinite bounds; default 1e6.
    core::Status setArtificialBound(double bound);
    // Degenerate pivots in a row before Bland's rule takes over (default
    // kBlandAfterDegeneratePivots; 0 = Bland's rule always, for tests).
    void setBlandThreshold(std::uint32_t pivots) { blandThreshold_ = pivots; }

    // Appends the row sum value[e] x[index[e]] <= rhs (count <= kLpMaxRowEntries,
    // distinct indices < variables). kFull when kLpMaxRows rows are held. A row
    // whose coefficients are all zero is allowed (it is feasible iff rhs >= 0).
    core::Status addRow(const std::uint8_t* index, const double* value, std::size_t count, double rhs,
                        std::size_t* rowId);
    // A new right-hand side; keeps the basis (warm start).
    core::Status setRhs(std::size_t row, double rhs);
    // Drops rows >= count. If the basis used one of them it is invalid until
    // restoreBasis() (else solve() starts cold).
    core::Status truncateRows(std::size_t count);
    std::size_t rowCount() const { return rows_ - 2 * n_; }
    std::size_t variableCount() const { return n_; }

    // Runs at most maxIterations pivots from the current basis. With a
    // cutoff, stops with kCutoff as soon as c . x >= cutoff: every dual
    // simplex basis is dual feasible, so c . x = -b . y is a lower bound on
    // the optimum and it never decreases (branch and bound prunes a node
    // without finishing its LP).
    LpStatus solve(std::uint32_t maxIterations, double cutoff = HUGE_VAL);
    LpStatus status() const { return status_; }

    // Basis snapshots for going back to an earlier LP (fewer rows).
    void saveBasis(LpBasis* out) const;
    // kInvalidArgument when the snapshot names a row the LP no longer has or
    // does not match the variable count; the current basis is then unchanged.
    core::Status restoreBasis(const LpBasis& basis);
    // The same with the factor A_B^-1 and the multipliers: restoring copies
    // them back instead of refactorising (n^2 copies instead of ~n^3 flops).
    // The buffer holds factorDoubles(n) doubles.
    static constexpr std::size_t factorDoubles(std::size_t n) { return n * n + n; }
    core::Status saveFactor(LpBasis* basis, double* buffer, std::size_t capacity) const;
    core::Status restoreFactor(const LpBasis& basis, const double* buffer, std::size_t size);
    // Forget the basis: the next solve() starts cold.
    void invalidateBasis() { basisValid_ = false; }
    bool basisValid() const { return basisValid_; }

    // Results of the last solve (meaningful after kOptimal).
    double objectiveValue() const;
    const double* solution() const { return x_; }
    double value(std::size_t variable) const { return variable < n_ ? x_[variable] : 0.0; }
    // a_r . x and its multiplier y_r >= 0 (0 unless the row is in the basis).
    double rowActivity(std::size_t row) const;
    double rowRhs(std::size_t row) const;
    double rowDual(std::size_t row) const;
    bool rowInBasis(std::size_t row) const;

    // Work counters since reset().
    std::uint32_t iterations() const { return iterations_; }
    // Work done since reset(), in units of about 1 ns on the x86-64
    // development host: each part (pricing a row, a pivot's update, a
    // refactorisation, a factor copy) is charged by its size, weighted by its
    // measured cost per operation (least squares over N = 5 .. 24 plans).
    // Time is proportional to it whatever n and the row count (CcPlanner's
    // budget).
    std::uint64_t work() const { return work_; }
    std::uint32_t lastIterations() const { return lastIterations_; }
    std::uint32_t refactorizations() const { return refactorizations_; }
    std::uint32_t blandPivots() const { return blandPivots_; }
    std::uint32_t coldStarts() const { return coldStarts_; }

    // Internal id of a variable's bound row (upper: x <= hi, lower: -x <= -lo)
    // and of a general row, for reading LpBasis.
    std::size_t rowIdOfBound(std::size_t variable, bool upper) const { return 2 * variable + (upper ? 0U : 1U); }
    std::size_t rowIdOfRow(std::size_t row) const { return 2 * n_ + row; }

private:
    struct Row {
        double value[kLpMaxRowEntries];
        std::uint8_t index[kLpMaxRowEntries];
        std::uint8_t count;
        std::uint8_t padded;  // 4 or 8: entries from count on are zero
        bool artificial;   // a bound row whose bound is artificial
        double rhs;        // stored, like the values, divided by scale
        double scale;      // max |value| as given, or 1 for an all-zero row
    };

    void setBoundRow(std::size_t variable, bool upper);
    bool validBasisRows(const LpBasis& basis) const;
    void installBasis(const LpBasis& basis);
    // The state of one solve() between pivots: the last x and y were
    // recomputed from A_B^-1 (fresh), Bland's rule is on, degenerate pivots
    // in a row.
    struct PivotState {
        bool fresh = false;
        bool bland = false;
        std::uint32_t degenerate = 0;
    };

    bool coldStart();
    bool refactor();
    void loadBasisMatrix();
    bool factorLu();
    void recordLuPatterns();
    void invertFromLu();
    void confirmVertex();
    LpStatus optimalOrUnbounded(double cmax) const;
    void recomputePrimal();
    void recomputeDual();
    double activity(const Row& row) const;
    static void padRow(Row& row);
    static void axpy(double* __restrict dst, double f, const double* __restrict src, std::size_t nPad);
    std::size_t paddedCount() const { return (n_ + 3U) & ~static_cast<std::size_t>(3U); }
    double basisResidual() const;
    // The row to enter, or kNone when the vertex is feasible.
    std::size_t priceRow(bool bland);
    // w = A_B^-T a_r for the entering row; returns the pivot tolerance.
    double enteringDirection(const Row& row);
    std::size_t leavingRow(bool bland, double pivotTol) const;
    LpStatus pivotAndCount(std::size_t enter, std::size_t leave, double cutoff, PivotState* state);
    void pivot(std::size_t enter, std::size_t leavePos, double theta);

    static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

    Row row_[kLpMaxAllRows];
    double binv_[kLpMaxVariables][kLpMaxVariables];  // A_B^-1: [variable][basis position]
    double lu_[kLpMaxVariables][kLpMaxVariables];    // refactor() scratch: P A_B = L U
    std::uint8_t perm_[kLpMaxVariables];
    std::uint8_t lIndex_[kLpMaxVariables][kLpMaxVariables];
    std::uint8_t uIndex_[kLpMaxVariables][kLpMaxVariables];
    std::uint8_t lCount_[kLpMaxVariables];
    std::uint8_t uCount_[kLpMaxVariables];
    double c_[kLpMaxVariables];
    double lo_[kLpMaxVariables];
    double hi_[kLpMaxVariables];
    double x_[kLpMaxVariables];
    double y_[kLpMaxVariables];      // multiplier of basis position p
    double w_[kLpMaxVariables];      // scratch: A_B^-T a_r
    static constexpr std::size_t kCandidates = 8;
    std::uint16_t candidate_[kCandidates] = {};
    std::size_t candidateCount_ = 0;
    std::uint16_t basis_[kLpMaxVariables];
    std::int16_t basisPos_[kLpMaxAllRows];  // position in the basis, -1 when not basic
    std::size_t n_ = 0;
    std::size_t rows_ = 0;           // bound rows + general rows
    double artificialBound_ = 1e6;
    std::uint32_t blandThreshold_ = kBlandAfterDegeneratePivots;
    bool basisValid_ = false;
    LpStatus status_ = LpStatus::kNotSolved;
    std::uint32_t sinceRefactor_ = 0;
    std::uint32_t iterations_ = 0;
    std::uint64_t work_ = 0;
    std::uint32_t lastIterations_ = 0;
    std::uint32_t refactorizations_ = 0;
    std::uint32_t blandPivots_ = 0;
    std::uint32_t coldStarts_ = 0;
};

}  // namespace rse::deliberative

#include "fsw/deliberative/lp_solver.hpp"

#include <cmath>

namespace rse::deliberative {

const char* toString(LpStatus status) {
    switch (status) {
        case LpStatus::kNotSolved:
            return "not solved";
        case LpStatus::kOptimal:
            return "optimal";
        case LpStatus::kInfeasible:
            return "infeasible";
        case LpStatus::kUnbounded:
            return "unbounded";
        case LpStatus::kIterationLimit:
            return "iteration limit";
        case LpStatus::kNumericalFailure:
            return "numerical failure";
        case LpStatus::kCutoff:
            return "cutoff";
    }
    return "?";
}

core::Status LpSolver::reset(std::size_t variables) {
    if (variables == 0 || variables > kLpMaxVariables) {
        return core::Status::kNoCapacity;
    }
    n_ = variables;
    rows_ = 2 * n_;
    for (std::size_t k = 0; k < n_; ++k) {
        c_[k] = 0.0;
        lo_[k] = -INFINITY;
        hi_[k] = INFINITY;
        x_[k] = 0.0;
        y_[k] = 0.0;
        setBoundRow(k, true);
        setBoundRow(k, false);
    }
    for (std::size_t r = 0; r < kLpMaxAllRows; ++r) {
        basisPos_[r] = -1;
    }
    // A_B^-1's columns n .. paddedCount() stay zero (axpy runs over them).
    for (std::size_t k = 0; k < kLpMaxVariables; ++k) {
        w_[k] = 0.0;
        for (std::size_t q = 0; q < kLpMaxVariables; ++q) {
            binv_[k][q] = 0.0;
        }
    }
    candidateCount_ = 0;
    basisValid_ = false;
    status_ = LpStatus::kNotSolved;
    sinceRefactor_ = 0;
    iterations_ = 0;
    work_ = 0;
    lastIterations_ = 0;
    refactorizations_ = 0;
    blandPivots_ = 0;
    coldStarts_ = 0;
    return core::Status::kOk;
}

void LpSolver::setBoundRow(std::size_t variable, bool upper) {
    Row& row = row_[rowIdOfBound(variable, upper)];
    row.count = 1;
    row.index[0] = static_cast<std::uint8_t>(variable);
    row.value[0] = upper ? 1.0 : -1.0;
    row.scale = 1.0;
    padRow(row);
    const double bound = upper ? hi_[variable] : lo_[variable];
    row.artificial = !std::isfinite(bound);
    if (row.artificial) {
        row.rhs = artificialBound_;  // x <= A, or -x <= A
    } else {
        row.rhs = upper ? bound : -bound;
    }
}

core::Status LpSolver::setObjective(std::size_t variable, double c) {
    if (variable >= n_ || !std::isfinite(c)) {
        return core::Status::kInvalidArgument;
    }
    c_[variable] = c;
    // A different objective can make the basis dual infeasible: start cold.
    basisValid_ = false;
    return core::Status::kOk;
}

core::Status LpSolver::setBounds(std::size_t variable, double lo, double hi) {
    if (variable >= n_ || std::isnan(lo) || std::isnan(hi) || lo > hi || (std::isinf(lo) && lo > 0.0) ||
        (std::isinf(hi) && hi < 0.0)) {
        return core::Status::kInvalidArgument;
    }
    lo_[variable] = lo;
    hi_[variable] = hi;
    setBoundRow(variable, true);
    setBoundRow(variable, false);
    return core::Status::kOk;
}

core::Status LpSolver::setArtificialBound(double bound) {
    if (!(bound > 0.0) || !std::isfinite(bound)) {
        return core::Status::kInvalidArgument;
    }
    artificialBound_ = bound;
    for (std::size_t k = 0; k < n_; ++k) {
        setBoundRow(k, true);
        setBoundRow(k, false);
    }
    return core::Status::kOk;
}

core::Status LpSolver::addRow(const std::uint8_t* index, const double* value, std::size_t count, double rhs,
                              std::size_t* rowId) {
    if (n_ == 0) {
        return core::Status::kNotInitialized;
    }
    if (count > kLpMaxRowEntries || (count > 0 && (index == nullptr || value == nullptr)) || !std::isfinite(rhs)) {
        return core::Status::kInvalidArgument;
    }
    if (rows_ >= 2 * n_ + kLpMaxRows) {
        return core::Status::kFull;
    }
    Row& row = row_[rows_];
    double scale = 0.0;
    for (std::size_t e = 0; e < count; ++e) {
        if (index[e] >= n_ || !std::isfinite(value[e])) {
            return core::Status::kInvalidArgument;
        }
        for (std::size_t f = 0; f < e; ++f) {
            if (index[f] == index[e]) {
                return core::Status::kInvalidArgument;
            }
        }
        row.index[e] = index[e];
        row.value[e] = value[e];
        const double a = std::fabs(value[e]);
        scale = a > scale ? a : scale;
    }
    // Stored scaled to a largest coefficient of 1: violations compare across
    // rows without a division (the accessors undo the scaling).
    row.count = static_cast<std::uint8_t>(count);
    row.artificial = false;
    row.scale = scale > 0.0 ? scale : 1.0;
    for (std::size_t e = 0; e < count; ++e) {
        row.value[e] /= row.scale;
    }
    padRow(row);
    row.rhs = rhs / row.scale;
    basisPos_[rows_] = -1;
    if (rowId != nullptr) {
        *rowId = rows_ - 2 * n_;
    }
    ++rows_;
    return core::Status::kOk;
}

core::Status LpSolver::setRhs(std::size_t row, double rhs) {
    if (row >= rowCount() || !std::isfinite(rhs)) {
        return core::Status::kInvalidArgument;
    }
    Row& r = row_[2 * n_ + row];
    r.rhs = rhs / r.scale;
    return core::Status::kOk;
}

core::Status LpSolver::truncateRows(std::size_t count) {
    if (count > rowCount()) {
        return core::Status::kInvalidArgument;
    }
    const std::size_t end = 2 * n_ + count;
    for (std::size_t r = end; r < rows_; ++r) {
        if (basisPos_[r] >= 0) {
            basisValid_ = false;
        }
        basisPos_[r] = -1;
    }
    rows_ = end;
    return core::Status::kOk;
}

void LpSolver::saveBasis(LpBasis* out) const {
    if (out == nullptr) {
        return;
    }
    if (!basisValid_) {
        out->count = 0;
        return;
    }
    out->count = static_cast<std::uint16_t>(n_);
    for (std::size_t p = 0; p < n_; ++p) {
        out->row[p] = basis_[p];
    }
}

core::Status LpSolver::restoreBasis(const LpBasis& basis) {
    if (!validBasisRows(basis)) {
        return core::Status::kInvalidArgument;
    }
    installBasis(basis);
    if (!refactor()) {
        (void)coldStart();
    }
    return core::Status::kOk;
}

bool LpSolver::validBasisRows(const LpBasis& basis) const {
    if (basis.count != n_) {
        return false;
    }
    for (std::size_t p = 0; p < n_; ++p) {
        if (basis.row[p] >= rows_) {
            return false;
        }
        for (std::size_t q = 0; q < p; ++q) {
            if (basis.row[q] == basis.row[p]) {
                return false;
            }
        }
    }
    return true;
}

void LpSolver::installBasis(const LpBasis& basis) {
    if (basisValid_) {
        for (std::size_t p = 0; p < n_; ++p) {
            basisPos_[basis_[p]] = -1;
        }
    } else {
        for (std::size_t r = 0; r < rows_; ++r) {
            basisPos_[r] = -1;
        }
    }
    for (std::size_t p = 0; p < n_; ++p) {
        basis_[p] = basis.row[p];
        basisPos_[basis_[p]] = static_cast<std::int16_t>(p);
    }
    basisValid_ = true;
}

core::Status LpSolver::saveFactor(LpBasis* basis, double* buffer, std::size_t capacity) const {
    if (basis == nullptr || buffer == nullptr || !basisValid_ || capacity < factorDoubles(n_)) {
        return core::Status::kInvalidArgument;
    }
    saveBasis(basis);
    basis->sincePivots = static_cast<std::uint16_t>(sinceRefactor_);
    std::size_t k = 0;
    for (std::size_t i = 0; i < n_; ++i) {
        for (std::size_t j = 0; j < n_; ++j) {
            buffer[k++] = binv_[i][j];
        }
    }
    for (std::size_t i = 0; i < n_; ++i) {
        buffer[k++] = y_[i];
    }
    return core::Status::kOk;
}

core::Status LpSolver::restoreFactor(const LpBasis& basis, const double* buffer, std::size_t size) {
    if (buffer == nullptr || size < factorDoubles(n_) || !validBasisRows(basis)) {
        return core::Status::kInvalidArgument;
    }
    work_ += 6 * n_ * n_;
    installBasis(basis);
    std::size_t k = 0;
    for (std::size_t i = 0; i < n_; ++i) {
        for (std::size_t j = 0; j < n_; ++j) {
            binv_[i][j] = buffer[k++];
        }
    }
    for (std::size_t i = 0; i < n_; ++i) {
        y_[i] = buffer[k++];
    }
    sinceRefactor_ = basis.sincePivots;
    recomputePrimal();
    return core::Status::kOk;
}

bool LpSolver::coldStart() {
    ++coldStarts_;
    for (std::size_t r = 0; r < rows_; ++r) {
        basisPos_[r] = -1;
    }
    for (std::size_t k = 0; k < n_; ++k) {
        const bool upper = c_[k] < 0.0;
        basis_[k] = static_cast<std::uint16_t>(rowIdOfBound(k, upper));
        basisPos_[basis_[k]] = static_cast<std::int16_t>(k);
        for (std::size_t q = 0; q < n_; ++q) {
            binv_[k][q] = 0.0;
        }
        binv_[k][k] = upper ? 1.0 : -1.0;
    }
    basisValid_ = true;
    sinceRefactor_ = 0;
    recomputePrimal();
    recomputeDual();
    return true;
}

// refactor(): lp_solver_refactor.cpp.

void LpSolver::recomputePrimal() {
    work_ += n_ * n_;
    for (std::size_t k = 0; k < n_; ++k) {
        double s = 0.0;
        for (std::size_t p = 0; p < n_; ++p) {
            s += binv_[k][p] * row_[basis_[p]].rhs;
        }
        x_[k] = s;
    }
}

double LpSolver::basisResidual() const {
    double worst = 0.0;
    for (std::size_t p = 0; p < n_; ++p) {
        const Row& row = row_[basis_[p]];
        const double r = std::fabs(activity(row) - row.rhs);
        worst = r > worst ? r : worst;
    }
    return worst;
}

void LpSolver::recomputeDual() {
    work_ += n_ * n_;
    for (std::size_t p = 0; p < n_; ++p) {
        y_[p] = 0.0;
    }
    for (std::size_t k = 0; k < n_; ++k) {
        const double ck = c_[k];
        if (ck == 0.0) {
            continue;
        }
        for (std::size_t p = 0; p < n_; ++p) {
            y_[p] -= binv_[k][p] * ck;
        }
    }
    for (std::size_t p = 0; p < n_; ++p) {
        if (y_[p] < 0.0 && y_[p] > -1e-7) {
            y_[p] = 0.0;
        }
    }
}

// Rows are zero-padded to 4 or 8 entries: a fixed-length dot product.
double LpSolver::activity(const Row& row) const {
    const double* v = row.value;
    const std::uint8_t* i = row.index;
    double s = v[0] * x_[i[0]] + v[1] * x_[i[1]] + v[2] * x_[i[2]] + v[3] * x_[i[3]];
    if (row.padded > 4) {
        s += v[4] * x_[i[4]] + v[5] * x_[i[5]] + v[6] * x_[i[6]] + v[7] * x_[i[7]];
    }
    return s;
}

void LpSolver::padRow(Row& row) {
    row.padded = row.count <= 4 ? 4 : 8;
    for (std::size_t e = row.count; e < kLpMaxRowEntries; ++e) {
        row.index[e] = 0;
        row.value[e] = 0.0;
    }
}

// Multiple pricing: a full scan keeps the kCandidates most violated rows;
// the next pivots choose among those (their violations recomputed) until none
// is violated, then scan again. Optimality is only declared by a full scan.
// Bland's rule always scans in full (lowest index).
std::size_t LpSolver::priceRow(bool bland) {
    if (!bland) {
        std::size_t best = kNone;
        double bestViolation = kPrimalTol;
        for (std::size_t c = 0; c < candidateCount_; ++c) {
            const std::size_t r = candidate_[c];
            if (r >= rows_ || basisPos_[r] >= 0) {
                continue;
            }
            const Row& row = row_[r];
            const double v = activity(row) - row.rhs;
            if (v > bestViolation) {
                bestViolation = v;
                best = r;
            }
        }
        work_ += 8 * candidateCount_;
        if (best != kNone) {
            return best;
        }
    }
    work_ += 8 * rows_;
    candidateCount_ = 0;
    double candViolation[kCandidates];
    for (std::size_t r = 0; r < rows_; ++r) {
        if (basisPos_[r] >= 0) {
            continue;
        }
        const Row& row = row_[r];
        const double v = activity(row) - row.rhs;
        if (v <= kPrimalTol) {
            continue;
        }
        if (bland) {
            return r;
        }
        // Insert into the candidates, most violated first.
        if (candidateCount_ == kCandidates && v <= candViolation[kCandidates - 1]) {
            continue;
        }
        std::size_t pos = candidateCount_ < kCandidates ? candidateCount_++ : kCandidates - 1;
        while (pos > 0 && candViolation[pos - 1] < v) {
            candViolation[pos] = candViolation[pos - 1];
            candidate_[pos] = candidate_[pos - 1];
            --pos;
        }
        candViolation[pos] = v;
        candidate_[pos] = static_cast<std::uint16_t>(r);
    }
    return candidateCount_ > 0 ? candidate_[0] : kNone;
}

// dst -= f src over nPad (a multiple of 4) entries, unrolled by 4 so that
// the compiler's SLP vectoriser uses SIMD at -O2.
void LpSolver::axpy(double* __restrict dst, double f, const double* __restrict src, std::size_t nPad) {
    for (std::size_t q = 0; q < nPad; q += 4) {
        dst[q] -= f * src[q];
        dst[q + 1] -= f * src[q + 1];
        dst[q + 2] -= f * src[q + 2];
        dst[q + 3] -= f * src[q + 3];
    }
}

void LpSolver::pivot(std::size_t enter, std::size_t leavePos, double theta) {
    const std::size_t n = n_;
    const Row& row = row_[enter];
    const double wp = w_[leavePos];
    // Primal step: keep the other basis rows tight, make row `enter` tight.
    const double alpha = (activity(row) - row.rhs) / wp;
    for (std::size_t k = 0; k < n; ++k) {
        x_[k] -= alpha * binv_[k][leavePos];
    }
    // Dual step.
    for (std::size_t p = 0; p < n; ++p) {
        const double v = y_[p] - theta * w_[p];
        y_[p] = v > 0.0 ? v : 0.0;
    }
    y_[leavePos] = theta;
    // A_B^-1 update for row leavePos replaced by a_enter (w = A_B^-T a_enter):
    // column p / w_p, column q - (w_q / w_p) column p.
    const std::size_t nPad = paddedCount();
    for (std::size_t k = 0; k < n; ++k) {
        const double f = binv_[k][leavePos] / wp;
        if (f != 0.0) {
            axpy(binv_[k], f, w_, nPad);
        }
        binv_[k][leavePos] = f;
    }
    basisPos_[basis_[leavePos]] = -1;
    basis_[leavePos] = static_cast<std::uint16_t>(enter);
    basisPos_[enter] = static_cast<std::int16_t>(leavePos);
}

LpStatus LpSolver::solve(std::uint32_t maxIterations, double cutoff) {
    lastIterations_ = 0;
    if (n_ == 0) {
        status_ = LpStatus::kNotSolved;
        return status_;
    }
    if (!basisValid_) {
        (void)coldStart();
    } else {
        recomputePrimal();  // right-hand sides or bounds may have changed
    }
    PivotState state;
    state.fresh = sinceRefactor_ == 0;
    state.bland = blandThreshold_ == 0;
    double cmax = 0.0;
    for (std::size_t k = 0; k < n_; ++k) {
        const double a = std::fabs(c_[k]);
        cmax = a > cmax ? a : cmax;
    }
    const std::uint64_t guard = 2ULL * maxIterations + 8ULL;
    for (std::uint64_t pass = 0; pass < guard; ++pass) {
        const std::size_t enter = priceRow(state.bland);
        if (enter == kNone) {
            if (!state.fresh) {
                confirmVertex();
                state.fresh = true;
                continue;
            }
            status_ = optimalOrUnbounded(cmax);
            return status_;
        }
        if (lastIterations_ >= maxIterations) {
            status_ = LpStatus::kIterationLimit;
            return status_;
        }
        const std::size_t leave = leavingRow(state.bland, enteringDirection(row_[enter]));
        if (leave == kNone) {
            if (!state.fresh) {
                if (!refactor()) {
                    (void)coldStart();
                }
                state.fresh = true;
                continue;
            }
            status_ = LpStatus::kInfeasible;
            return status_;
        }
        const LpStatus after = pivotAndCount(enter, leave, cutoff, &state);
        if (after != LpStatus::kNotSolved) {
            status_ = after;
            return status_;
        }
    }
    status_ = LpStatus::kIterationLimit;
    return status_;
}

// No row is violated, but x and y come from the pivots' updates: recompute
// them from A_B^-1 (drift of the updates); a basis row that x no longer
// meets means A_B^-1 has drifted: refactorise.
void LpSolver::confirmVertex() {
    recomputePrimal();
    recomputeDual();
    if (basisResidual() > kResidualTol) {
        if (!refactor()) {
            (void)coldStart();
        }
    }
}

// A confirmed vertex: optimal, unless it leans on an artificial bound.
LpStatus LpSolver::optimalOrUnbounded(double cmax) const {
    for (std::size_t p = 0; p < n_; ++p) {
        if (row_[basis_[p]].artificial && y_[p] > 1e-9 * (1.0 + cmax)) {
            return LpStatus::kUnbounded;
        }
    }
    return LpStatus::kOptimal;
}

// w = A_B^-T a_enter; returns the pivot tolerance: below kPivotTol (or 1e-11
// of the largest w_p) a pivot is noise.
double LpSolver::enteringDirection(const Row& row) {
    const std::size_t nPad = paddedCount();
    for (std::size_t p = 0; p < nPad; ++p) {
        w_[p] = 0.0;
    }
    for (std::size_t e = 0; e < row.count; ++e) {
        axpy(w_, -row.value[e], binv_[row.index[e]], nPad);
    }
    double wmax = 0.0;
    for (std::size_t p = 0; p < n_; ++p) {
        wmax = w_[p] > wmax ? w_[p] : wmax;
    }
    return kPivotTol > 1e-11 * wmax ? kPivotTol : 1e-11 * wmax;
}

// The ratio test: the basis position to leave, kNone when no w_p passes the
// tolerance (a dual ray: the LP is infeasible).
std::size_t LpSolver::leavingRow(bool bland, double pivotTol) const {
    std::size_t leave = kNone;
    if (bland) {
        // Exact minimum ratio; ties to the lowest row id.
        double bestRatio = INFINITY;
        for (std::size_t p = 0; p < n_; ++p) {
            if (w_[p] <= pivotTol) {
                continue;
            }
            const double ratio = y_[p] / w_[p];
            const double tie = 1e-14 * (1.0 + std::fabs(ratio));
            if (leave == kNone || ratio < bestRatio - tie) {
                bestRatio = ratio;
                leave = p;
            } else if (ratio <= bestRatio + tie && basis_[p] < basis_[leave]) {
                bestRatio = ratio < bestRatio ? ratio : bestRatio;
                leave = p;
            }
        }
        return leave;
    }
    // Harris: the largest pivot among the ratios within the tolerance.
    double thetaMax = INFINITY;
    for (std::size_t p = 0; p < n_; ++p) {
        if (w_[p] > pivotTol) {
            const double bound = (y_[p] + kDualTol) / w_[p];
            thetaMax = bound < thetaMax ? bound : thetaMax;
        }
    }
    double bestW = 0.0;
    for (std::size_t p = 0; p < n_; ++p) {
        if (w_[p] > pivotTol && y_[p] / w_[p] <= thetaMax && w_[p] > bestW) {
            bestW = w_[p];
            leave = p;
        }
    }
    return leave;
}

// One pivot and its accounting: the cutoff, the switch to and from Bland's
// rule, the periodic refactorisation. kNotSolved: the solve goes on.
LpStatus LpSolver::pivotAndCount(std::size_t enter, std::size_t leave, double cutoff, PivotState* state) {
    const Row& row = row_[enter];
    double theta = y_[leave] / w_[leave];
    theta = theta > 0.0 ? theta : 0.0;
    pivot(enter, leave, theta);
    ++lastIterations_;
    ++iterations_;
    work_ += n_ * paddedCount() + row.count * paddedCount();  // A_B^-1 update, x, y, w
    if (state->bland) {
        ++blandPivots_;
    }
    state->fresh = false;
    if (cutoff < HUGE_VAL && objectiveValue() >= cutoff) {
        return LpStatus::kCutoff;
    }
    if (theta <= 1e-14) {
        ++state->degenerate;
        if (state->degenerate >= blandThreshold_) {
            state->bland = true;
        }
    } else {
        state->degenerate = 0;
        state->bland = blandThreshold_ == 0;
    }
    if (++sinceRefactor_ >= kRefactorPeriod) {
        if (!refactor()) {
            if (!coldStart()) {
                return LpStatus::kNumericalFailure;
            }
        }
        state->fresh = true;
    }
    return LpStatus::kNotSolved;
}

double LpSolver::objectiveValue() const {
    double s = 0.0;
    for (std::size_t k = 0; k < n_; ++k) {
        s += c_[k] * x_[k];
    }
    return s;
}

double LpSolver::rowActivity(std::size_t row) const {
    if (row >= rowCount()) {
        return 0.0;
    }
    const Row& r = row_[2 * n_ + row];
    return activity(r) * r.scale;
}

double LpSolver::rowRhs(std::size_t row) const {
    if (row >= rowCount()) {
        return 0.0;
    }
    const Row& r = row_[2 * n_ + row];
    return r.rhs * r.scale;
}

double LpSolver::rowDual(std::size_t row) const {
    if (row >= rowCount() || !basisValid_) {
        return 0.0;
    }
    const std::int16_t pos = basisPos_[2 * n_ + row];
    return pos >= 0 ? y_[static_cast<std::size_t>(pos)] / row_[2 * n_ + row].scale : 0.0;
}

bool LpSolver::rowInBasis(std::size_t row) const {
    return row < rowCount() && basisValid_ && basisPos_[2 * n_ + row] >= 0;
}

}  // namespace rse::deliberative

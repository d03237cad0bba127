// The dense dual simplex: closed-form LPs, infeasible and unbounded detection,
// degenerate LPs (Beale's cycling example, many rows through one vertex,
// Bland's rule forced on), warm starts (rows added, right-hand sides changed,
// a basis saved and restored) against cold solves, random small LPs against
// brute-force vertex enumeration done here, and no heap use.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <random>
#include <vector>

#include "fsw/deliberative/lp_solver.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using rse::deliberative::kLpMaxRows;
using rse::deliberative::kLpMaxVariables;
using rse::deliberative::LpBasis;
using rse::deliberative::LpSolver;
using rse::deliberative::LpStatus;

namespace {

LpSolver lp;     // 147 KB each: static storage, as in flight
LpSolver cold;

// A dense row helper: coefficients for x0..x(n-1), zeros skipped.
std::size_t addDense(LpSolver& s, const std::vector<double>& a, double rhs) {
    std::uint8_t idx[8];
    double val[8];
    std::size_t count = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        if (a[k] != 0.0) {
            idx[count] = static_cast<std::uint8_t>(k);
            val[count] = a[k];
            ++count;
        }
    }
    std::size_t id = 0;
    CHECK(s.addRow(idx, val, count, rhs, &id) == Status::kOk);
    return id;
}

struct DenseLp {
    std::size_t n = 0;
    std::vector<double> c;
    std::vector<double> lo, hi;
    std::vector<std::vector<double>> a;
    std::vector<double> b;
};

void load(LpSolver& s, const DenseLp& d) {
    CHECK(s.reset(d.n) == Status::kOk);
    for (std::size_t k = 0; k < d.n; ++k) {
        CHECK(s.setObjective(k, d.c[k]) == Status::kOk);
        CHECK(s.setBounds(k, d.lo[k], d.hi[k]) == Status::kOk);
    }
    for (std::size_t r = 0; r < d.a.size(); ++r) {
        addDense(s, d.a[r], d.b[r]);
    }
}

constexpr std::size_t kBruteMax = 6;

// Solves the n x n system M z = v (n <= kBruteMax) by Gaussian elimination
// with partial pivoting; false when (nearly) singular.
bool solveSquare(double m[kBruteMax][kBruteMax], double v[kBruteMax], std::size_t n, double z[kBruteMax]) {
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t best = k;
        for (std::size_t i = k + 1; i < n; ++i) {
            if (std::fabs(m[i][k]) > std::fabs(m[best][k])) {
                best = i;
            }
        }
        if (std::fabs(m[best][k]) < 1e-9) {
            return false;
        }
        for (std::size_t j = 0; j < n; ++j) {
            std::swap(m[k][j], m[best][j]);
        }
        std::swap(v[k], v[best]);
        for (std::size_t i = k + 1; i < n; ++i) {
            const double f = m[i][k] / m[k][k];
            for (std::size_t j = k; j < n; ++j) {
                m[i][j] -= f * m[k][j];
            }
            v[i] -= f * v[k];
        }
    }
    for (std::size_t k = n; k-- > 0;) {
        double s = v[k];
        for (std::size_t j = k + 1; j < n; ++j) {
            s -= m[k][j] * z[j];
        }
        z[k] = s / m[k][k];
    }
    return true;
}

// Brute force: every n-subset of rows (general and bound rows) that meets in
// one point; the best feasible one. Bounds must be finite (a polytope).
bool bruteForce(const DenseLp& d, double* best) {
    std::vector<std::vector<double>> rows = d.a;
    std::vector<double> rhs = d.b;
    for (std::size_t k = 0; k < d.n; ++k) {
        std::vector<double> up(d.n, 0.0), down(d.n, 0.0);
        up[k] = 1.0;
        down[k] = -1.0;
        rows.push_back(up);
        rhs.push_back(d.hi[k]);
        rows.push_back(down);
        rhs.push_back(-d.lo[k]);
    }
    const std::size_t m = rows.size();
    const std::size_t n = d.n;
    std::size_t pick[kBruteMax];
    for (std::size_t k = 0; k < n; ++k) {
        pick[k] = k;
    }
    bool found = false;
    *best = INFINITY;
    while (true) {
        double sq[kBruteMax][kBruteMax];
        double v[kBruteMax];
        double z[kBruteMax];
        for (std::size_t k = 0; k < n; ++k) {
            for (std::size_t j = 0; j < n; ++j) {
                sq[k][j] = rows[pick[k]][j];
            }
            v[k] = rhs[pick[k]];
        }
        if (solveSquare(sq, v, n, z)) {
            bool feasible = true;
            for (std::size_t r = 0; r < m && feasible; ++r) {
                double s = 0.0;
                for (std::size_t k = 0; k < n; ++k) {
                    s += rows[r][k] * z[k];
                }
                feasible = s <= rhs[r] + 1e-7;
            }
            if (feasible) {
                double obj = 0.0;
                for (std::size_t k = 0; k < n; ++k) {
                    obj += d.c[k] * z[k];
                }
                *best = obj < *best ? obj : *best;
                found = true;
            }
        }
        // Next combination.
        std::size_t i = n;
        while (i > 0 && pick[i - 1] == m - n + i - 1) {
            --i;
        }
        if (i == 0) {
            break;
        }
        ++pick[i - 1];
        for (std::size_t j = i; j < n; ++j) {
            pick[j] = pick[j - 1] + 1;
        }
    }
    return found;
}

// Every row and bound holds at the solver's point, within tol.
void checkFeasible(const LpSolver& s, const DenseLp& d, double tol) {
    for (std::size_t r = 0; r < d.a.size(); ++r) {
        CHECK(s.rowActivity(r) <= d.b[r] + tol);
        double act = 0.0;
        for (std::size_t k = 0; k < d.n; ++k) {
            act += d.a[r][k] * s.value(k);
        }
        DOUBLES_EQUAL(act, s.rowActivity(r), 1e-9);
    }
    for (std::size_t k = 0; k < d.n; ++k) {
        CHECK(s.value(k) >= d.lo[k] - tol && s.value(k) <= d.hi[k] + tol);
    }
}

// Dual check: y >= 0 on rows, zero off the basis, and complementary slackness.
void checkDuals(const LpSolver& s, const DenseLp& d) {
    for (std::size_t r = 0; r < d.a.size(); ++r) {
        const double y = s.rowDual(r);
        CHECK(y >= 0.0);
        if (!s.rowInBasis(r)) {
            DOUBLES_EQUAL(0.0, y, 0.0);
        }
        if (y > 1e-9) {
            DOUBLES_EQUAL(d.b[r], s.rowActivity(r), 1e-7);
        }
    }
}

DenseLp randomLp(std::mt19937_64& rng, std::size_t n, std::size_t m, bool integer) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> small(-2, 2);
    DenseLp d;
    d.n = n;
    for (std::size_t k = 0; k < n; ++k) {
        d.c.push_back(integer ? small(rng) : u(rng));
        d.lo.push_back(integer ? -3.0 : -2.0 - u(rng));
        d.hi.push_back(integer ? 3.0 : 2.0 + u(rng));
    }
    for (std::size_t r = 0; r < m; ++r) {
        std::vector<double> a(n);
        for (std::size_t k = 0; k < n; ++k) {
            a[k] = integer ? small(rng) : u(rng);
        }
        d.a.push_back(a);
        // Integer LPs: right-hand sides from a small set, many rows through
        // the same points (degenerate vertices). Else rows at random offsets,
        // some of which cut the origin off (so some LPs are infeasible).
        d.b.push_back(integer ? static_cast<double>(small(rng)) : 1.2 * u(rng) + 0.3);
    }
    return d;
}

void compareWithBruteForce(std::uint64_t seed, int count, bool integer, std::uint32_t blandThreshold) {
    std::mt19937_64 rng(seed);
    int infeasible = 0;
    int optimal = 0;
    for (int i = 0; i < count; ++i) {
        const std::size_t n = 2 + static_cast<std::size_t>(i % 4);      // 2 .. 5
        const std::size_t m = 3 + static_cast<std::size_t>(i % 5) * 2;  // 3 .. 11
        const DenseLp d = randomLp(rng, n, m, integer);
        load(lp, d);
        lp.setBlandThreshold(blandThreshold);
        const LpStatus st = lp.solve(1000);
        double best = 0.0;
        const bool feasible = bruteForce(d, &best);
        if (!feasible) {
            CHECK_EQUAL(static_cast<int>(LpStatus::kInfeasible), static_cast<int>(st));
            ++infeasible;
            continue;
        }
        CHECK_EQUAL(static_cast<int>(LpStatus::kOptimal), static_cast<int>(st));
        DOUBLES_EQUAL(best, lp.objectiveValue(), 1e-7 * (1.0 + std::fabs(best)));
        checkFeasible(lp, d, 1e-8);
        checkDuals(lp, d);
        ++optimal;
    }
    // Both outcomes are exercised.
    CHECK(optimal > count / 4);
    CHECK(infeasible > 0);
}

}  // namespace

TEST_GROUP(LpSolver){};

TEST(LpSolver, SizesAndArguments) {
    CHECK(lp.reset(0) == Status::kNoCapacity);
    CHECK(lp.reset(kLpMaxVariables + 1) == Status::kNoCapacity);
    CHECK(lp.reset(3) == Status::kOk);
    CHECK(lp.setObjective(3, 1.0) == Status::kInvalidArgument);
    CHECK(lp.setObjective(0, NAN) == Status::kInvalidArgument);
    CHECK(lp.setBounds(0, 2.0, 1.0) == Status::kInvalidArgument);
    CHECK(lp.setBounds(0, INFINITY, INFINITY) == Status::kInvalidArgument);
    const std::uint8_t dup[2] = {1, 1};
    const std::uint8_t out[1] = {3};
    const double v[2] = {1.0, 2.0};
    CHECK(lp.addRow(dup, v, 2, 0.0, nullptr) == Status::kInvalidArgument);
    CHECK(lp.addRow(out, v, 1, 0.0, nullptr) == Status::kInvalidArgument);
    const std::uint8_t one[1] = {0};
    for (std::size_t r = 0; r < kLpMaxRows; ++r) {
        CHECK(lp.addRow(one, v, 1, static_cast<double>(r), nullptr) == Status::kOk);
    }
    CHECK(lp.addRow(one, v, 1, 0.0, nullptr) == Status::kFull);
    CHECK_EQUAL(kLpMaxRows, lp.rowCount());
}

// max 3x + 2y s.t. x + y <= 4, x + 3y <= 6, x <= 3, x, y >= 0: (3, 1), 11.
TEST(LpSolver, ClosedFormVertex) {
    CHECK(lp.reset(2) == Status::kOk);
    CHECK(lp.setObjective(0, -3.0) == Status::kOk);
    CHECK(lp.setObjective(1, -2.0) == Status::kOk);
    CHECK(lp.setBounds(0, 0.0, INFINITY) == Status::kOk);
    CHECK(lp.setBounds(1, 0.0, INFINITY) == Status::kOk);
    const std::size_t r0 = addDense(lp, {1.0, 1.0}, 4.0);
    addDense(lp, {1.0, 3.0}, 6.0);
    const std::size_t r2 = addDense(lp, {1.0, 0.0}, 3.0);
    CHECK(lp.solve(100) == LpStatus::kOptimal);
    DOUBLES_EQUAL(-11.0, lp.objectiveValue(), 1e-12);
    DOUBLES_EQUAL(3.0, lp.value(0), 1e-12);
    DOUBLES_EQUAL(1.0, lp.value(1), 1e-12);
    // Multipliers: c + A'y = 0 with rows 0 and 2 active: y0 = 2, y2 = 1.
    DOUBLES_EQUAL(2.0, lp.rowDual(r0), 1e-12);
    DOUBLES_EQUAL(1.0, lp.rowDual(r2), 1e-12);
    DOUBLES_EQUAL(0.0, lp.rowDual(1), 0.0);
}

// min |x - 2| + |y + 1| as an epigraph LP (free x, y): 0 at (2, -1); then a
// row x + y >= 3 moves the optimum to cost 2.
TEST(LpSolver, EpigraphOfAbsoluteValues) {
    CHECK(lp.reset(4) == Status::kOk);  // x, y, s, t
    CHECK(lp.setObjective(2, 1.0) == Status::kOk);
    CHECK(lp.setObjective(3, 1.0) == Status::kOk);
    addDense(lp, {1.0, 0.0, -1.0, 0.0}, 2.0);    //  x - s <= 2
    addDense(lp, {-1.0, 0.0, -1.0, 0.0}, -2.0);  // -x - s <= -2
    addDense(lp, {0.0, 1.0, 0.0, -1.0}, -1.0);   //  y - t <= -1
    addDense(lp, {0.0, -1.0, 0.0, -1.0}, 1.0);   // -y - t <= 1
    CHECK(lp.solve(100) == LpStatus::kOptimal);
    DOUBLES_EQUAL(0.0, lp.objectiveValue(), 1e-12);
    DOUBLES_EQUAL(2.0, lp.value(0), 1e-12);
    DOUBLES_EQUAL(-1.0, lp.value(1), 1e-12);
    addDense(lp, {-1.0, -1.0, 0.0, 0.0}, -3.0);
    CHECK(lp.solve(100) == LpStatus::kOptimal);
    DOUBLES_EQUAL(2.0, lp.objectiveValue(), 1e-12);
    DOUBLES_EQUAL(3.0, lp.value(0) + lp.value(1), 1e-12);
}

TEST(LpSolver, InfeasibleRowsAndBounds) {
    CHECK(lp.reset(2) == Status::kOk);
    CHECK(lp.setObjective(0, 1.0) == Status::kOk);
    addDense(lp, {1.0, 1.0}, 1.0);     // x + y <= 1
    addDense(lp, {-1.0, -1.0}, -2.0);  // x + y >= 2
    CHECK(lp.solve(100) == LpStatus::kInfeasible);
    // Bounds against a row.
    CHECK(lp.reset(1) == Status::kOk);
    CHECK(lp.setBounds(0, 0.0, 1.0) == Status::kOk);
    addDense(lp, {-1.0}, -1.5);
    CHECK(lp.solve(100) == LpStatus::kInfeasible);
    // An all-zero row with a negative right-hand side.
    CHECK(lp.reset(1) == Status::kOk);
    CHECK(lp.addRow(nullptr, nullptr, 0, -1e-6, nullptr) == Status::kOk);
    CHECK(lp.solve(100) == LpStatus::kInfeasible);
    CHECK(lp.reset(1) == Status::kOk);
    CHECK(lp.addRow(nullptr, nullptr, 0, 0.0, nullptr) == Status::kOk);
    CHECK(lp.solve(100) == LpStatus::kOptimal);
}

TEST(LpSolver, Unbounded) {
    // min -x - y s.t. x - y <= 1, x >= 0, y >= 0: the ray (1, 1).
    CHECK(lp.reset(2) == Status::kOk);
    CHECK(lp.setObjective(0, -1.0) == Status::kOk);
    CHECK(lp.setObjective(1, -1.0) == Status::kOk);
    CHECK(lp.setBounds(0, 0.0, INFINITY) == Status::kOk);
    CHECK(lp.setBounds(1, 0.0, INFINITY) == Status::kOk);
    addDense(lp, {1.0, -1.0}, 1.0);
    CHECK(lp.solve(100) == LpStatus::kUnbounded);
    // The same with a finite bound on y is bounded: (4, 3), -7.
    CHECK(lp.setBounds(1, 0.0, 3.0) == Status::kOk);
    lp.invalidateBasis();
    CHECK(lp.solve(100) == LpStatus::kOptimal);
    DOUBLES_EQUAL(-7.0, lp.objectiveValue(), 1e-9);
    // A free variable with no cost is not unbounded: its value is arbitrary.
    CHECK(lp.reset(2) == Status::kOk);
    CHECK(lp.setObjective(0, 1.0) == Status::kOk);
    addDense(lp, {-1.0, 0.0}, -2.0);
    CHECK(lp.solve(100) == LpStatus::kOptimal);
    DOUBLES_EQUAL(2.0, lp.objectiveValue(), 1e-12);
}

// Beale's example (Beale 1955), the classic LP on which the textbook simplex
// cycles: max 3/4 x0 - 20 x1 + 1/2 x2 - 6 x3 s.t. 1/4 x0 - 8 x1 - x2 + 9 x3 <= 0,
// 1/2 x0 - 12 x1 - 1/2 x2 + 3 x3 <= 0, x2 <= 1, x >= 0.
// (1, 0, 1, 0) is the optimum, 5/4. Solved with the default rule and with Bland's rule forced.
TEST(LpSolver, BealeCyclingExample) {
    for (std::uint32_t threshold : {LpSolver::kBlandAfterDegeneratePivots, 0U}) {
        CHECK(lp.reset(4) == Status::kOk);
        lp.setBlandThreshold(threshold);
        const double c[4] = {-0.75, 20.0, -0.5, 6.0};
        for (std::size_t k = 0; k < 4; ++k) {
            CHECK(lp.setObjective(k, c[k]) == Status::kOk);
            CHECK(lp.setBounds(k, 0.0, INFINITY) == Status::kOk);
        }
        addDense(lp, {0.25, -8.0, -1.0, 9.0}, 0.0);
        addDense(lp, {0.5, -12.0, -0.5, 3.0}, 0.0);
        addDense(lp, {0.0, 0.0, 1.0, 0.0}, 1.0);
        CHECK(lp.solve(200) == LpStatus::kOptimal);
        DOUBLES_EQUAL(-1.25, lp.objectiveValue(), 1e-12);
        DOUBLES_EQUAL(1.0, lp.value(0), 1e-12);
        DOUBLES_EQUAL(1.0, lp.value(2), 1e-12);
    }
}

// A pyramid whose apex lies on 60 facets: min -z over z <= 1 - cos(a) x -
// sin(a) y for 60 angles a (plus the same rows again, exact duplicates): every
// row is tight at the optimum (0, 0, 1), a maximally degenerate vertex.
TEST(LpSolver, HighlyDegenerateVertex) {
    for (std::uint32_t threshold : {LpSolver::kBlandAfterDegeneratePivots, 0U}) {
        CHECK(lp.reset(3) == Status::kOk);
        lp.setBlandThreshold(threshold);
        CHECK(lp.setObjective(2, -1.0) == Status::kOk);
        for (int copy = 0; copy < 2; ++copy) {
            for (int k = 0; k < 60; ++k) {
                const double a = 2.0 * M_PI * k / 60.0;
                addDense(lp, {std::cos(a), std::sin(a), 1.0}, 1.0);
            }
        }
        CHECK(lp.solve(500) == LpStatus::kOptimal);
        DOUBLES_EQUAL(-1.0, lp.objectiveValue(), 1e-12);
        DOUBLES_EQUAL(0.0, lp.value(0), 1e-12);
        DOUBLES_EQUAL(0.0, lp.value(1), 1e-12);
    }
}

TEST(LpSolver, IterationLimitKeepsTheBasis) {
    std::mt19937_64 rng(7);
    DenseLp d = randomLp(rng, 5, 15, false);
    for (double& b : d.b) {
        b = std::fabs(b) + 0.5;  // the origin is feasible
    }
    d.c = {1.0, -1.0, 0.5, -0.25, 1.0};
    load(cold, d);
    CHECK(cold.solve(1000) == LpStatus::kOptimal);
    CHECK(cold.lastIterations() > 2);
    load(lp, d);
    std::uint32_t calls = 0;
    LpStatus st = LpStatus::kIterationLimit;
    while (st == LpStatus::kIterationLimit && calls < 100) {
        st = lp.solve(1);
        CHECK(lp.lastIterations() <= 1);
        ++calls;
    }
    CHECK(st == LpStatus::kOptimal);
    CHECK(calls > 2);
    DOUBLES_EQUAL(cold.objectiveValue(), lp.objectiveValue(), 1e-9);
}

// Random LPs against enumeration of every vertex.
TEST(LpSolver, RandomAgainstVertexEnumeration) {
    compareWithBruteForce(1, 400, false, LpSolver::kBlandAfterDegeneratePivots);
}
TEST(LpSolver, RandomDegenerateAgainstVertexEnumeration) {
    compareWithBruteForce(2, 400, true, LpSolver::kBlandAfterDegeneratePivots);
}
TEST(LpSolver, RandomDegenerateBlandAgainstVertexEnumeration) { compareWithBruteForce(3, 400, true, 0); }

// Adding rows to a solved LP continues from its basis and ends where a cold
// solve of the larger LP ends; so do right-hand side changes; a saved basis
// brings the smaller LP back with no pivot.
TEST(LpSolver, WarmStartsMatchColdSolves) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int warmCheaper = 0;
    for (int trial = 0; trial < 50; ++trial) {
        const std::size_t n = 12;
        DenseLp d = randomLp(rng, n, 0, false);
        for (std::size_t k = 0; k < n; ++k) {
            d.c[k] = u(rng);
        }
        load(lp, d);
        // Rows with up to 8 nonzeros, loose around the origin.
        auto randomRow = [&](std::vector<double>* a) {
            a->assign(n, 0.0);
            for (std::size_t e = 0; e < 6; ++e) {
                (*a)[static_cast<std::size_t>(rng() % n)] = u(rng);
            }
            return 0.5 + 0.5 * u(rng);
        };
        for (int r = 0; r < 30; ++r) {
            std::vector<double> a;
            const double b = randomRow(&a);
            d.a.push_back(a);
            d.b.push_back(b);
            addDense(lp, a, b);
        }
        CHECK(lp.solve(1000) == LpStatus::kOptimal);
        const double before = lp.objectiveValue();
        LpBasis saved;
        lp.saveBasis(&saved);
        const std::size_t mark = lp.rowCount();
        // Five more rows: warm.
        DenseLp bigger = d;
        for (int r = 0; r < 5; ++r) {
            std::vector<double> a;
            const double b = randomRow(&a) - 0.6;
            bigger.a.push_back(a);
            bigger.b.push_back(b);
            addDense(lp, a, b);
        }
        const LpStatus warmStatus = lp.solve(1000);
        const std::uint32_t warmPivots = lp.lastIterations();
        load(cold, bigger);
        const LpStatus coldStatus = cold.solve(1000);
        CHECK_EQUAL(static_cast<int>(coldStatus), static_cast<int>(warmStatus));
        if (coldStatus == LpStatus::kOptimal) {
            DOUBLES_EQUAL(cold.objectiveValue(), lp.objectiveValue(), 1e-8);
            checkFeasible(lp, bigger, 1e-8);
            warmCheaper += warmPivots < cold.lastIterations() ? 1 : 0;
        }
        // Back to the smaller LP: truncate, restore, no pivot needed.
        CHECK(lp.truncateRows(mark) == Status::kOk);
        CHECK(lp.restoreBasis(saved) == Status::kOk);
        CHECK(lp.solve(1000) == LpStatus::kOptimal);
        CHECK_EQUAL(0U, lp.lastIterations());
        DOUBLES_EQUAL(before, lp.objectiveValue(), 1e-9);
        // New right-hand sides: warm against cold.
        for (std::size_t r = 0; r < d.a.size(); r += 3) {
            d.b[r] += 0.2 * u(rng);
            CHECK(lp.setRhs(r, d.b[r]) == Status::kOk);
        }
        const LpStatus rhsStatus = lp.solve(1000);
        load(cold, d);
        CHECK_EQUAL(static_cast<int>(cold.solve(1000)), static_cast<int>(rhsStatus));
        if (rhsStatus == LpStatus::kOptimal) {
            DOUBLES_EQUAL(cold.objectiveValue(), lp.objectiveValue(), 1e-8);
        }
    }
    CHECK(warmCheaper > 25);
}

TEST(LpSolver, TruncatingABasicRowInvalidatesTheBasis) {
    CHECK(lp.reset(1) == Status::kOk);
    CHECK(lp.setObjective(0, 1.0) == Status::kOk);
    addDense(lp, {-1.0}, -1.0);  // x >= 1
    CHECK(lp.solve(10) == LpStatus::kOptimal);
    LpBasis atOne;
    lp.saveBasis(&atOne);
    addDense(lp, {-1.0}, -2.0);  // x >= 2
    CHECK(lp.solve(10) == LpStatus::kOptimal);
    DOUBLES_EQUAL(2.0, lp.objectiveValue(), 1e-12);
    CHECK(lp.rowInBasis(1));
    LpBasis atTwo;
    lp.saveBasis(&atTwo);
    CHECK(lp.truncateRows(1) == Status::kOk);
    CHECK_FALSE(lp.basisValid());
    CHECK(lp.restoreBasis(atTwo) == Status::kInvalidArgument);  // names the dropped row
    CHECK(lp.solve(10) == LpStatus::kOptimal);                  // cold
    DOUBLES_EQUAL(1.0, lp.objectiveValue(), 1e-12);
    CHECK(lp.restoreBasis(atOne) == Status::kOk);
    CHECK(lp.solve(10) == LpStatus::kOptimal);
    CHECK_EQUAL(0U, lp.lastIterations());
}

TEST(LpSolver, NoHeapUse) {
    std::mt19937_64 rng(5);
    const DenseLp d = randomLp(rng, 5, 15, false);
    rse::test::AllocationWatch watch;
    load(lp, d);
    (void)lp.solve(1000);
    LpBasis b;
    lp.saveBasis(&b);
    CHECK(lp.restoreBasis(b) == Status::kOk);
    (void)lp.solve(1000);
    CHECK_EQUAL(0U, watch.count());
}

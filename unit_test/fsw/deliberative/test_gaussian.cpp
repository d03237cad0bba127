// The Gaussian helpers of the chance constraints: known quantiles (50-digit
// references from mpmath), tails down to 1e-300, the Phi / PhiInv round trip,
// the tail-accurate upper quantile, and the tightening margin and end risk.
#include <cmath>
#include <cstddef>
#include <initializer_list>

#include "fsw/deliberative/gaussian.hpp"

#include "CppUTest/TestHarness.h"

using rse::deliberative::endRisk;
using rse::deliberative::faceVariance;
using rse::deliberative::Phi;
using rse::deliberative::PhiComplement;
using rse::deliberative::PhiInv;
using rse::deliberative::tighteningMargin;
using rse::deliberative::upperQuantile;

namespace {

struct Quantile {
    double p;
    double z;
};

// PhiInv(p) to 20 digits, by mpmath (findroot on ncdf at 50 digits).
constexpr Quantile kQuantiles[] = {
    {0.975, 1.9599639845400542355},    {0.025, -1.9599639845400542355},  {0.9, 1.281551565544600467},
    {0.999, 3.0902323061678135415},    {1e-3, -3.0902323061678135415},   {1e-6, -4.7534243088228989482},
    {1e-9, -5.9978070150076868716},    {1e-12, -7.0344838253011319298},  {1e-100, -21.273453560965324295},
    {1e-200, -30.205594179579643063},  {1e-300, -37.047096299361199237},
};

}  // namespace

TEST_GROUP(Gaussian){};

TEST(Gaussian, KnownQuantiles) {
    for (const Quantile& q : kQuantiles) {
        DOUBLES_EQUAL(q.z, PhiInv(q.p), 2e-15 * std::fabs(q.z));
    }
    // The figure, to the last printed digit.
    DOUBLES_EQUAL(1.959963984540054, PhiInv(0.975), 1e-15);
    DOUBLES_EQUAL(0.0, PhiInv(0.5), 0.0);
}

TEST(Gaussian, SymmetricAndMonotone) {
    double previous = -INFINITY;
    for (int k = 1; k < 2000; ++k) {
        const double p = static_cast<double>(k) / 2000.0;
        const double z = PhiInv(p);
        CHECK(z > previous);
        previous = z;
        DOUBLES_EQUAL(-z, PhiInv(1.0 - p), 1e-14 * (1.0 + std::fabs(z)));
    }
}

TEST(Gaussian, EdgesAndOutsideTheDomain) {
    CHECK(std::isinf(PhiInv(0.0)) && PhiInv(0.0) < 0.0);
    CHECK(std::isinf(PhiInv(1.0)) && PhiInv(1.0) > 0.0);
    CHECK(std::isnan(PhiInv(-1e-300)));
    CHECK(std::isnan(PhiInv(1.0000001)));
    CHECK(std::isnan(PhiInv(NAN)));
    DOUBLES_EQUAL(0.5, Phi(0.0), 0.0);
    DOUBLES_EQUAL(0.0, Phi(-40.0), 1e-300);
    DOUBLES_EQUAL(1.0, Phi(40.0), 0.0);
}

// Phi(PhiInv(p)) = p over the whole range: the central range to a few ulp, the
// tails relative to p (the tail's conditioning, z^2, bounds the error there).
TEST(Gaussian, RoundTrip) {
    for (int k = 1; k < 1000; ++k) {
        const double p = static_cast<double>(k) / 1000.0;
        DOUBLES_EQUAL(p, Phi(PhiInv(p)), 4e-16);
    }
    for (int e = 1; e <= 300; ++e) {
        for (double mant : {1.0, 2.5, 7.0}) {
            const double p = mant * std::pow(10.0, -static_cast<double>(e));
            const double z = PhiInv(p);
            const double tol = 1e-15 * (1.0 + z * z);
            DOUBLES_EQUAL(1.0, Phi(z) / p, tol);
            // The upper tail through the complement: no cancellation.
            DOUBLES_EQUAL(1.0, PhiComplement(upperQuantile(p)) / p, tol);
        }
    }
}

// PhiInv(1 - delta) from 1 - delta loses delta entirely below 1.1e-16 (and
// digits well above); upperQuantile keeps it.
TEST(Gaussian, UpperQuantileKeepsTinyDeltas) {
    DOUBLES_EQUAL(7.0344838253011319298, upperQuantile(1e-12), 2e-15 * 7.03);
    DOUBLES_EQUAL(21.273453560965324295, upperQuantile(1e-100), 2e-15 * 21.3);
    CHECK(std::isinf(PhiInv(1.0 - 1e-17)));
    CHECK(std::isfinite(upperQuantile(1e-17)));
    DOUBLES_EQUAL(1.9599639845400542355, upperQuantile(0.025), 4e-15);
}

TEST(Gaussian, FaceVarianceGrowsWithTime) {
    const double cov[4] = {0.04, 0.01, 0.01, 0.09};  // anisotropic, correlated
    const double c = std::sqrt(0.5);
    // a' Sigma_0 a for a = (c, c): 0.5 (0.04 + 0.01 + 0.01 + 0.09) = 0.075.
    DOUBLES_EQUAL(0.075, faceVariance(c, c, cov, 0.1, 0), 1e-15);
    DOUBLES_EQUAL(0.075 + 3 * 0.01, faceVariance(c, c, cov, 0.1, 3), 1e-15);
    DOUBLES_EQUAL(0.04 + 7 * 0.25, faceVariance(1.0, 0.0, cov, 0.5, 7), 1e-15);
    DOUBLES_EQUAL(0.09 + 7 * 0.25, faceVariance(0.0, -1.0, cov, 0.5, 7), 1e-15);
}

TEST(Gaussian, MarginAndEndRiskAreInverse) {
    // delta = 0.025 and a variance of 4: 1.96 sigma = 3.92 m.
    DOUBLES_EQUAL(2.0 * 1.9599639845400542355, tighteningMargin(0.025, 4.0), 1e-14);
    DOUBLES_EQUAL(0.0, tighteningMargin(0.025, 0.0), 0.0);
    DOUBLES_EQUAL(0.0, tighteningMargin(0.0, 0.0), 0.0);  // no 0 * inf
    CHECK(tighteningMargin(0.4, 1.0) > 0.0);
    CHECK(tighteningMargin(0.6, 1.0) < 0.0);
    for (double delta : {0.3, 1e-2, 1e-5, 1e-9, 1e-12, 1e-30}) {
        for (double variance : {1e-4, 0.3, 25.0}) {
            const double m = tighteningMargin(delta, variance);
            DOUBLES_EQUAL(1.0, endRisk(m, variance) / delta, 1e-13);
        }
    }
    DOUBLES_EQUAL(0.5, endRisk(0.0, 1.0), 1e-16);
    DOUBLES_EQUAL(0.0, endRisk(0.0, 0.0), 0.0);
    DOUBLES_EQUAL(0.0, endRisk(1.0, 0.0), 0.0);
    DOUBLES_EQUAL(1.0, endRisk(-1e-9, 0.0), 0.0);
}

// The bivariate orthant P(X > h, Y > k), correlation rho.
namespace {

using rse::deliberative::bivariateUpperTail;

// Simpson on P = int_h^inf phi(x) Phi^c((k - rho x) / sqrt(1 - rho^2)) dx.
double orthantByQuadrature(double h, double k, double rho) {
    const double lo = h;
    const double hi = (h > 0.0 ? h : 0.0) + 12.0;
    const int n = 40000;
    const double dx = (hi - lo) / n;
    const double s = std::sqrt(1.0 - rho * rho);
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
        const double x = lo + dx * i;
        const double f = std::exp(-0.5 * x * x) / std::sqrt(2.0 * M_PI) * PhiComplement((k - rho * x) / s);
        sum += f * (i == 0 || i == n ? 1.0 : (i % 2 != 0 ? 4.0 : 2.0));
    }
    return sum * dx / 3.0;
}

// Correlations on both sides of the rule's switches (0.3, 0.75, 0.925).
constexpr double kRhos[] = {-0.999, -0.95, -0.93, -0.92, -0.8, -0.5, -0.29, 0.0,
                            0.1,    0.31,  0.7,   0.76,  0.9,  0.924, 0.926, 0.97, 0.9999};

}  // namespace

TEST(Gaussian, OrthantAtTheOriginIsSheppards) {
    // P(X > 0, Y > 0) = 1/4 + asin(rho) / (2 pi).
    for (double rho : kRhos) {
        DOUBLES_EQUAL(0.25 + std::asin(rho) / (2.0 * M_PI), bivariateUpperTail(0.0, 0.0, rho), 1e-15);
    }
}

TEST(Gaussian, UncorrelatedOrthantIsTheProductOfTails) {
    for (double h : {-3.0, -0.4, 0.0, 1.3, 4.0, 7.5}) {
        for (double k : {-1.0, 0.2, 2.5, 6.0}) {
            const double want = PhiComplement(h) * PhiComplement(k);
            DOUBLES_EQUAL(want, bivariateUpperTail(h, k, 0.0), 1e-16 + 1e-13 * want);
        }
    }
}

TEST(Gaussian, OrthantMatchesQuadratureAndIsSymmetric) {
    for (double h : {-2.0, -0.5, 0.7, 2.5, 4.0}) {
        for (double k : {-1.5, 0.0, 1.1, 3.0, 5.0}) {
            for (double rho : kRhos) {
                const double p = bivariateUpperTail(h, k, rho);
                DOUBLES_EQUAL(orthantByQuadrature(h, k, rho), p, 1e-10);
                DOUBLES_EQUAL(bivariateUpperTail(k, h, rho), p, 1e-15);
                // P(X > h, Y > k) + P(X > h, Y <= k) = P(X > h), across the branches.
                DOUBLES_EQUAL(PhiComplement(h), p + bivariateUpperTail(h, -k, -rho), 1e-15);
                CHECK(p >= 0.0 && p <= PhiComplement(h > k ? h : k) + 1e-15);
            }
        }
    }
}

TEST(Gaussian, OrthantTailsKeepTheirRelativeAccuracy) {
    // Deep in the tail with positive correlation (the certified risk's case:
    // one face's two ends): against quadrature, relative.
    for (double rho : {0.5, 0.8, 0.95, 0.99}) {
        const double q = orthantByQuadrature(5.0, 5.5, rho);
        DOUBLES_EQUAL(q, bivariateUpperTail(5.0, 5.5, rho), 1e-8 * q);
    }
}

TEST(Gaussian, OrthantDegenerateCorrelationsAndNaN) {
    DOUBLES_EQUAL(PhiComplement(1.5), bivariateUpperTail(1.5, -0.3, 1.0), 0.0);
    DOUBLES_EQUAL(Phi(0.3) - Phi(-1.0), bivariateUpperTail(-1.0, -0.3, -1.0), 1e-16);
    DOUBLES_EQUAL(0.0, bivariateUpperTail(1.0, 1.0, -1.0), 0.0);
    CHECK(std::isnan(bivariateUpperTail(NAN, 0.0, 0.5)));
    CHECK(std::isnan(bivariateUpperTail(0.0, 0.0, NAN)));
}

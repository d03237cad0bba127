// The standard normal distribution for the chance constraints: its CDF, the
// upper tail, the quantile (Wichura's AS241 / PPND16, relative error about
// 1e-16 over (0, 1), tails down to the smallest normal double), and the
// tightening margin of one face end (cc_problem.hpp):
//
//   a . mu_t >= b + PhiInv(1 - delta) sqrt(a' Sigma_t a),   Sigma_t = Sigma_0 + t sigma^2 I
//
// PhiInv(1 - delta) is computed as -PhiInv(delta): 1 - delta rounds to 1 once
// delta < 1.1e-16, and even at delta = 1e-9 the subtraction would throw away
// seven of its digits. Pure functions, no state, no allocation; std::erfc and
// std::log from <cmath> are the only library calls.
#pragma once

namespace rse::deliberative {

// Phi(x) = P(Z <= x), Z ~ N(0, 1): 0.5 erfc(-x / sqrt 2), full relative
// precision in the lower tail (down to the smallest double). NaN for NaN.
double Phi(double x);

// 1 - Phi(x) = P(Z > x) without the cancellation: 0.5 erfc(x / sqrt 2).
double PhiComplement(double x);

// The quantile: Phi(PhiInv(p)) = p. p in (0, 1); -inf at 0, +inf at 1, NaN
// outside [0, 1] or for NaN. AS241 (Wichura 1988, Appl. Statist. 37, 477-484):
// rational approximations in three ranges, relative accuracy about 1e-16.
double PhiInv(double p);

// PhiInv(1 - delta) for delta in (0, 1), accurate for tiny delta (see above).
double upperQuantile(double delta);

// P(X > h, Y > k) for standard normals X, Y with correlation rho in [-1, 1]:
// the bivariate normal upper orthant, by Drezner and Wesolowsky's integral in
// Genz's form (Genz 2004, "Numerical computation of rectangular bivariate
// and trivariate normal and t probabilities", Stat. Comput. 14, 251-260):
// Gauss-Legendre with 6, 12 or 20 points by |rho|, and for |rho| >= 0.925 the
// asymptotic expansion of the integrand near |rho| = 1. Absolute error about
// 1e-15 (kBivariateAbsError bounds it for callers that need a certified
// upper bound); |rho| = 1 exactly gives the degenerate answers. NaN in, NaN
// out. About 20 - 40 exp() calls; no state, no allocation.
double bivariateUpperTail(double h, double k, double rho);
constexpr double kBivariateAbsError = 1e-14;

// Variance of a . x for x ~ N(., Sigma_0 + t sigma^2 I) and a unit normal a:
// a' Sigma_0 a + t sigma^2. cov is Sigma_0 row major (symmetric).
double faceVariance(double ax, double ay, const double cov[4], double sigma, unsigned t);

// The tightening of one face end, in metres: PhiInv(1 - delta) sqrt(variance).
// 0 when variance <= 0 (a deterministic end needs no margin at any delta; this
// also keeps 0 * inf out for delta = 0). delta in (0, 1); at delta = 0 and a
// positive variance the margin is +inf (no plan can meet it).
double tighteningMargin(double delta, double variance);

// Risk of one face end: P(a . x < b) for a . x ~ N(a . mu, variance), given
// slack = a . mu - b: PhiComplement(slack / sqrt(variance)); for variance <= 0,
// 0 when slack >= 0 and 1 otherwise. The "need" of iterative risk allocation:
// tighteningMargin(endRisk(s, v), v) == s up to rounding.
double endRisk(double slack, double variance);

}  // namespace rse::deliberative

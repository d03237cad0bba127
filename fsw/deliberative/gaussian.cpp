#include "fsw/deliberative/gaussian.hpp"

#include <cmath>

namespace rse::deliberative {

namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;

// AS241 PPND16 coefficients (Wichura 1988), ascending powers; the denominators'
// constant term is 1.
constexpr double kA[8] = {3.3871328727963666080e0, 1.3314166789178437745e+2, 1.9715909503065514427e+3,
                          1.3731693765509461125e+4, 4.5921953931549871457e+4, 6.7265770927008700853e+4,
                          3.3430575583588128105e+4, 2.5090809287301226727e+3};
constexpr double kB[8] = {1.0,
                          4.2313330701600911252e+1,
                          6.8718700749205790830e+2,
                          5.3941960214247511077e+3,
                          2.1213794301586595867e+4,
                          3.9307895800092710610e+4,
                          2.8729085735721942674e+4,
                          5.2264952788528545610e+3};
constexpr double kC[8] = {1.42343711074968357734e0, 4.63033784615654529590e0, 5.76949722146069140550e0,
                          3.64784832476320460504e0, 1.27045825245236838258e0, 2.41780725177450611770e-1,
                          2.27238449892691845833e-2, 7.74545014278341407640e-4};
constexpr double kD[8] = {1.0,
                          2.05319162663775882187e0,
                          1.67638483018380384940e0,
                          6.89767334985100004550e-1,
                          1.48103976427480074590e-1,
                          1.51986665636164571966e-2,
                          5.47593808499534494600e-4,
                          1.05075007164441684324e-9};
constexpr double kE[8] = {6.65790464350110377720e0, 5.46378491116411436990e0, 1.78482653991729133580e0,
                          2.96560571828504891230e-1, 2.65321895265761230930e-2, 1.24266094738807843860e-3,
                          2.71155556874348757815e-5, 2.01033439929228813265e-7};
constexpr double kF[8] = {1.0,
                          5.99832206555887937690e-1,
                          1.36929880922735805310e-1,
                          1.48753612908506148525e-2,
                          7.86869131145613259100e-4,
                          1.84631831751005468180e-5,
                          1.42151175831644588870e-7,
                          2.04426310338993978564e-15};

// Gauss-Legendre nodes (one sign; the rule is symmetric) and weights on
// [-1, 1]: 6, 12 and 20 points.
constexpr double kGl6X[3] = {0.9324695142031521, 0.6612093864662645, 0.2386191860831969};
constexpr double kGl6W[3] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910};
constexpr double kGl12X[6] = {0.9815606342467192, 0.9041172563704749, 0.7699026741943047,
                              0.5873179542866175, 0.3678314989981802, 0.1252334085114689};
constexpr double kGl12W[6] = {0.04717533638651183, 0.1069393259953184, 0.1600783285433462,
                              0.2031674267230659, 0.2334925365383548, 0.2491470458134028};
constexpr double kGl20X[10] = {0.9931285991850949, 0.9639719272779138, 0.9122344282513259, 0.8391169718222188,
                               0.7463319064601508, 0.6360536807265150, 0.5108670019508271, 0.3737060887154195,
                               0.2277858511416451, 0.07652652113349734};
constexpr double kGl20W[10] = {0.01761400713915212, 0.04060142980038694, 0.06267204833410907, 0.08327674157670475,
                               0.1019301198172404,  0.1181945319615184,  0.1316886384491766,  0.1420961093183820,
                               0.1491729864726037,  0.1527533871307258};
constexpr double kPi = 3.14159265358979323846;

double horner(const double (&c)[8], double x) {
    double acc = c[7];
    for (int k = 6; k >= 0; --k) {
        acc = acc * x + c[k];
    }
    return acc;
}

}  // namespace

double Phi(double x) { return 0.5 * std::erfc(-x * kInvSqrt2); }

double PhiComplement(double x) { return 0.5 * std::erfc(x * kInvSqrt2); }

double PhiInv(double p) {
    if (!(p >= 0.0 && p <= 1.0)) {
        return NAN;
    }
    if (p == 0.0) {
        return -INFINITY;
    }
    if (p == 1.0) {
        return INFINITY;
    }
    const double q = p - 0.5;
    if (std::fabs(q) <= 0.425) {
        const double r = 0.180625 - q * q;
        return q * horner(kA, r) / horner(kB, r);
    }
    const double tail = q < 0.0 ? p : 1.0 - p;
    double r = std::sqrt(-std::log(tail));
    double value = 0.0;
    if (r <= 5.0) {
        r -= 1.6;
        value = horner(kC, r) / horner(kD, r);
    } else {
        r -= 5.0;
        value = horner(kE, r) / horner(kF, r);
    }
    return q < 0.0 ? -value : value;
}

double upperQuantile(double delta) { return -PhiInv(delta); }

double bivariateUpperTail(double h, double k, double rho) {
    if (std::isnan(h) || std::isnan(k) || std::isnan(rho)) {
        return NAN;
    }
    rho = rho > 1.0 ? 1.0 : (rho < -1.0 ? -1.0 : rho);
    if (rho == 1.0) {
        return PhiComplement(h > k ? h : k);
    }
    if (rho == -1.0) {
        // X > h and -X > k: h < X < -k.
        const double p = Phi(-k) - Phi(h);
        return p > 0.0 ? p : 0.0;
    }
    const double* x = kGl6X;
    const double* w = kGl6W;
    int points = 3;
    if (std::fabs(rho) >= 0.75) {
        x = kGl20X;
        w = kGl20W;
        points = 10;
    } else if (std::fabs(rho) >= 0.3) {
        x = kGl12X;
        w = kGl12W;
        points = 6;
    }
    double hk = h * k;
    double sum = 0.0;
    if (std::fabs(rho) < 0.925) {
        // P = Phi(-h) Phi(-k) + 1 / (2 pi) int_0^asin(rho) exp(-(h^2 + k^2 - 2 hk sin t) / (2 cos^2 t)) dt
        const double hs = 0.5 * (h * h + k * k);
        const double asr = std::asin(rho);
        for (int i = 0; i < points; ++i) {
            for (int sign = -1; sign <= 1; sign += 2) {
                const double sn = std::sin(0.5 * asr * (static_cast<double>(sign) * x[i] + 1.0));
                sum += w[i] * std::exp((sn * hk - hs) / (1.0 - sn * sn));
            }
        }
        const double p = sum * asr / (4.0 * kPi) + PhiComplement(h) * PhiComplement(k);
        return p > 0.0 ? p : 0.0;
    }
    // |rho| near 1: integrate in sqrt(1 - r^2), the singular part in closed form.
    double kk = k;
    if (rho < 0.0) {
        kk = -kk;
        hk = -hk;
    }
    const double as = (1.0 - rho) * (1.0 + rho);
    double a = std::sqrt(as);
    const double bs = (h - kk) * (h - kk);
    const double c = (4.0 - hk) / 8.0;
    const double d = (12.0 - hk) / 16.0;
    double asr = -0.5 * (bs / as + hk);
    if (asr > -100.0) {
        sum = a * std::exp(asr) * (1.0 - c * (bs - as) * (1.0 - d * bs / 5.0) / 3.0 + c * d * as * as / 5.0);
    }
    if (-hk < 100.0) {
        const double b = std::sqrt(bs);
        sum -= std::exp(-0.5 * hk) * std::sqrt(2.0 * kPi) * Phi(-b / a) * b * (1.0 - c * bs * (1.0 - d * bs / 5.0) / 3.0);
    }
    a *= 0.5;
    for (int i = 0; i < points; ++i) {
        for (int sign = -1; sign <= 1; sign += 2) {
            const double xs0 = a * (static_cast<double>(sign) * x[i] + 1.0);
            const double xs = xs0 * xs0;
            const double rs = std::sqrt(1.0 - xs);
            const double e = -0.5 * (bs / xs + hk);
            if (e > -100.0) {
                sum += a * w[i] * std::exp(e) *
                       (std::exp(-hk * (1.0 - rs) / (2.0 * (1.0 + rs))) / rs - (1.0 + c * xs * (1.0 + d * xs)));
            }
        }
    }
    double p = -sum / (2.0 * kPi);
    if (rho > 0.0) {
        p += PhiComplement(h > kk ? h : kk);
    } else {
        p = -p;
        if (kk > h) {
            p += Phi(kk) - Phi(h);
        }
    }
    return p > 0.0 ? p : 0.0;
}

double faceVariance(double ax, double ay, const double cov[4], double sigma, unsigned t) {
    const double quad = ax * (cov[0] * ax + cov[1] * ay) + ay * (cov[2] * ax + cov[3] * ay);
    return quad + static_cast<double>(t) * sigma * sigma;
}

double tighteningMargin(double delta, double variance) {
    if (!(variance > 0.0)) {
        return 0.0;
    }
    return upperQuantile(delta) * std::sqrt(variance);
}

double endRisk(double slack, double variance) {
    if (!(variance > 0.0)) {
        return slack >= 0.0 ? 0.0 : 1.0;
    }
    return PhiComplement(slack / std::sqrt(variance));
}

}  // namespace rse::deliberative

// Monte Carlo consistency of the pose EKF against a truth model with exactly
// the filter's noise model: the normalised estimation error squared (NEES) of
// (x, y, heading), averaged over the runs, must lie inside the two-sided 95 %
// chi-square bounds. This is the filter's own honesty, before the full-system
// benchmark (unit_test/bench/bench_estimator.cpp) judges it against rse-sim.
//
// Truth per 10 ms step: body speed and yaw rate (a smooth seeded profile),
// exact unicycle motion; gyro bias drawn from the filter's prior, then a random
// walk. Measurements: speed + white noise of density q_v, IMU rate + bias +
// white noise of density q_w (wheel density and no bias during an IMU outage
// from 20 to 30 s), a fix every second with sigmas 0.05 m and 0.005 rad.
#include <Eigen/Cholesky>
#include <cmath>
#include <cstdint>
#include <random>

#include "fsw/estimator/pose_ekf.hpp"

#include "unit_test/fsw/estimator/default_noise.hpp"
#include "unit_test/fsw/estimator/gaussian.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using namespace rse::estimator;

namespace {

constexpr int kRuns = 50;
constexpr double kDt = 0.01;
constexpr int kSteps = 6000;  // 60 s
constexpr double kFixSigmaM = 0.05;
constexpr double kFixHeadingSigma = 0.005;
constexpr double kGate = 16.27;
constexpr double kInitialBiasSigma = 0.01;
// NEES sample instants (step index after which the sample is taken): half-way
// between fixes in the IMU outage and at the end, and straight after the last fix.
constexpr int kSampleSteps[] = {2550, 5950, 6000};
constexpr int kSampleCount = 3;

PoseProcessNoise tableNoise() {
    static const PoseProcessNoise noise = rse::test::defaultTableNoise();
    return noise;
}

PoseProcessNoise scaled(const PoseProcessNoise& n, double k) {
    PoseProcessNoise out = n;
    out.speedNoiseDensity *= k;
    out.speedNoiseFracDensity *= k;
    out.imuYawRateNoiseDensity *= k;
    out.wheelYawRateNoiseDensity *= k;
    out.gyroBiasWalk *= k;
    return out;
}

using rse::test::Gaussian;

double nees(const PoseState& truth, const PoseEkf& ekf) {
    const Eigen::Vector3d e(truth(kPoseX) - ekf.x(), truth(kPoseY) - ekf.y(),
                            wrapAngle(truth(kPoseTheta) - ekf.heading()));
    const Eigen::Matrix3d p = ekf.covariance().topLeftCorner<3, 3>();
    const Eigen::LLT<Eigen::Matrix3d> llt(p);
    return e.dot(llt.solve(e));
}

// Chi-square quantile, Wilson-Hilferty (within 0.1 % at 150 dof).
double chiSquareQuantile(double dof, double z) {
    const double a = 2.0 / (9.0 * dof);
    const double c = 1.0 - a + z * std::sqrt(a);
    return dof * c * c * c;
}
constexpr double kZ975 = 1.959963985;

struct MonteCarlo {
    double meanNees[kSampleCount] = {};
    unsigned gated = 0;
};

// filterNoise is what the filter believes; the truth always uses tableNoise().
MonteCarlo runMonteCarlo(std::uint64_t seed, const PoseProcessNoise& filterNoise) {
    const PoseProcessNoise truthNoise = tableNoise();
    MonteCarlo out;
    Gaussian g(seed);
    for (int run = 0; run < kRuns; ++run) {
        const double phase = 2.0 * M_PI * g.uniform();
        PoseState truth;
        truth << 10.0 * g(), 10.0 * g(), wrapAngle(M_PI * (2.0 * g.uniform() - 1.0)), 0.0;
        double bias = kInitialBiasSigma * g();
        PoseEkf ekf;
        CHECK_TRUE(Status::kOk == ekf.init(truth(0) + kFixSigmaM * g(), truth(1) + kFixSigmaM * g(),
                                           truth(2) + kFixHeadingSigma * g(), kFixSigmaM, kFixHeadingSigma,
                                           kInitialBiasSigma));
        int sample = 0;
        for (int step = 1; step <= kSteps; ++step) {
            const double t = step * kDt;
            const double v = 0.2 + 0.1 * std::sin(0.3 * t + phase);
            const double w = 0.25 * std::sin(0.11 * t + 2.0 * phase);
            const bool imuUp = t <= 20.0 || t > 30.0;
            const double qv = truthNoise.speedNoiseDensity * truthNoise.speedNoiseDensity +
                              std::pow(truthNoise.speedNoiseFracDensity * v, 2.0);
            const double yawDensity = imuUp ? truthNoise.imuYawRateNoiseDensity : truthNoise.wheelYawRateNoiseDensity;
            // White noise of density q held over dt: variance q / dt.
            const double speedMeasured = v + std::sqrt(qv / kDt) * g();
            const double rateMeasured = w + (imuUp ? bias : 0.0) + yawDensity / std::sqrt(kDt) * g();
            truth = unicycleStep(truth, kDt, v, w, false).next;
            bias += truthNoise.gyroBiasWalk * std::sqrt(kDt) * g();
            CHECK_TRUE(Status::kOk == ekf.predict(kDt, speedMeasured, rateMeasured, imuUp, filterNoise));
            if (step % 100 == 0) {
                FixUpdateResult r;
                CHECK_TRUE(Status::kOk == ekf.updateFix(truth(0) + kFixSigmaM * g(), truth(1) + kFixSigmaM * g(),
                                                        wrapAngle(truth(2) + kFixHeadingSigma * g()), kFixSigmaM,
                                                        kFixHeadingSigma, kGate, &r));
                out.gated += r.accepted ? 0U : 1U;
            }
            if (sample < kSampleCount && step == kSampleSteps[sample]) {
                out.meanNees[sample] += nees(truth, ekf) / kRuns;
                ++sample;
            }
        }
    }
    return out;
}

}  // namespace

TEST_GROUP(PoseEkfConsistency) {
    // Average NEES of N runs, 3 dof each: N * mean ~ chi-square(3N).
    const double lower = chiSquareQuantile(3.0 * kRuns, -kZ975) / kRuns;
    const double upper = chiSquareQuantile(3.0 * kRuns, kZ975) / kRuns;
};

TEST(PoseEkfConsistency, BoundsAreTheChiSquare95PercentInterval) {
    // chi-square(150): 2.5 % and 97.5 % quantiles are 117.98 and 185.80.
    DOUBLES_EQUAL(117.98 / kRuns, lower, 0.01);
    DOUBLES_EQUAL(185.80 / kRuns, upper, 0.01);
}

TEST(PoseEkfConsistency, MeanNeesOfFiftyRunsLiesWithinTheBounds) {
    const MonteCarlo mc = runMonteCarlo(20240601, tableNoise());
    for (int i = 0; i < kSampleCount; ++i) {
        CHECK_TRUE(mc.meanNees[i] > lower);
        CHECK_TRUE(mc.meanNees[i] < upper);
    }
    CHECK_TRUE(mc.gated <= 10);  // 3000 honest fixes through a 99.9 % gate: about 3
}

// The check has teeth: a filter that believes the noise is 5x smaller (or
// larger) than it is falls outside the bounds.
TEST(PoseEkfConsistency, AnOverconfidentFilterFailsTheCheck) {
    const MonteCarlo mc = runMonteCarlo(20240601, scaled(tableNoise(), 0.2));
    CHECK_TRUE(mc.meanNees[0] > upper);
    CHECK_TRUE(mc.meanNees[1] > upper);
}

TEST(PoseEkfConsistency, AnUnderconfidentFilterFailsTheCheck) {
    const MonteCarlo mc = runMonteCarlo(20240601, scaled(tableNoise(), 5.0));
    CHECK_TRUE(mc.meanNees[0] < lower);
    CHECK_TRUE(mc.meanNees[1] < lower);
}

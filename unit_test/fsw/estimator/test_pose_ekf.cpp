// The pose EKF's mathematics: exact unicycle propagation, analytic Jacobians,
// process-noise growth, the fix update (Joseph form, gate, heading wrap), bias
// observability and refusals.
#include <Eigen/Eigenvalues>
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

PoseProcessNoise tableNoise() {
    static const PoseProcessNoise noise = rse::test::defaultTableNoise();
    return noise;
}

PoseState stateOf(double x, double y, double theta, double bias) {
    PoseState s;
    s << x, y, theta, bias;
    return s;
}

void checkSymmetricPsd(const PoseCovariance& p) {
    CHECK_TRUE(p == p.transpose());
    const Eigen::SelfAdjointEigenSolver<PoseCovariance> eig(p);
    CHECK_TRUE(eig.eigenvalues().minCoeff() >= -1e-15 * (1.0 + eig.eigenvalues().maxCoeff()));
}

using rse::test::Gaussian;

}  // namespace

TEST_GROUP(PoseEkfPropagation){};

TEST(PoseEkfPropagation, StraightLineMatchesTheAnalyticSolution) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(1.0, 2.0, 0.3, 0.1, 0.01, 0.01));
    for (int i = 0; i < 200; ++i) {
        CHECK_TRUE(Status::kOk == ekf.predict(0.01, 0.5, 0.0, false, tableNoise()));
    }
    DOUBLES_EQUAL(1.0 + 0.5 * 2.0 * std::cos(0.3), ekf.x(), 1e-12);
    DOUBLES_EQUAL(2.0 + 0.5 * 2.0 * std::sin(0.3), ekf.y(), 1e-12);
    DOUBLES_EQUAL(0.3, ekf.heading(), 0.0);  // straight driving keeps the heading exactly
}

TEST(PoseEkfPropagation, ConstantTurnMatchesTheAnalyticUnicycleAndWraps) {
    const double v = 0.4, w = 0.2, theta0 = 2.0, t = 10.0;
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(-3.0, 5.0, theta0, 0.1, 0.01, 0.01));
    for (int i = 0; i < 1000; ++i) {
        CHECK_TRUE(Status::kOk == ekf.predict(0.01, v, w, true, tableNoise()));
    }
    const double x = -3.0 + v / w * (std::sin(theta0 + w * t) - std::sin(theta0));
    const double y = 5.0 - v / w * (std::cos(theta0 + w * t) - std::cos(theta0));
    DOUBLES_EQUAL(x, ekf.x(), 1e-9);
    DOUBLES_EQUAL(y, ekf.y(), 1e-9);
    DOUBLES_EQUAL(theta0 + w * t - 2.0 * M_PI, ekf.heading(), 1e-9);  // 4.0 rad wrapped

    // Exact, not merely convergent: one 10 s step lands on the same pose.
    const UnicycleStep one = unicycleStep(stateOf(-3.0, 5.0, theta0, 0.0), t, v, w, true);
    DOUBLES_EQUAL(x, one.next(kPoseX), 1e-12);
    DOUBLES_EQUAL(y, one.next(kPoseY), 1e-12);
}

TEST(PoseEkfPropagation, TheImuRateIsCorrectedByTheBiasAndTheWheelRateIsNot) {
    const PoseState s = stateOf(0.0, 0.0, 0.0, 0.05);
    const UnicycleStep imu = unicycleStep(s, 1.0, 0.0, 0.25, true);
    const UnicycleStep wheels = unicycleStep(s, 1.0, 0.0, 0.25, false);
    DOUBLES_EQUAL(0.20, imu.yawRateRadS, 1e-15);
    DOUBLES_EQUAL(0.20, imu.next(kPoseTheta), 1e-15);
    DOUBLES_EQUAL(0.25, wheels.next(kPoseTheta), 1e-15);
    DOUBLES_EQUAL(0.0, wheels.F(kPoseTheta, kPoseBias), 0.0);
    DOUBLES_EQUAL(-1.0, imu.F(kPoseTheta, kPoseBias), 0.0);
}

TEST(PoseEkfPropagation, JacobiansMatchFiniteDifferences) {
    struct Case {
        PoseState s;
        double dt, v, w;
        bool imu;
    };
    const Case cases[] = {
        {stateOf(1.0, -2.0, 2.5, 0.02), 0.5, 0.4, 0.3, true},     // a real turn
        {stateOf(0.0, 0.0, -0.7, 0.01), 0.01, 0.3, 0.01, true},   // straight: h in the series branch
        {stateOf(0.0, 0.0, 1.2, 0.0), 0.2, 0.25, 0.0, false},     // exactly straight, wheel yaw
        {stateOf(5.0, 5.0, 0.1, -0.03), 4.0, 0.2, 1.5, true},     // more than a half turn in one step
    };
    const double eps = 1e-6;
    for (const Case& c : cases) {
        const UnicycleStep step = unicycleStep(c.s, c.dt, c.v, c.w, c.imu);
        for (int j = 0; j < 4; ++j) {
            PoseState plus = c.s, minus = c.s;
            plus(j) += eps;
            minus(j) -= eps;
            const PoseState a = unicycleStep(plus, c.dt, c.v, c.w, c.imu).next;
            const PoseState b = unicycleStep(minus, c.dt, c.v, c.w, c.imu).next;
            for (int i = 0; i < 4; ++i) {
                const double diff = i == kPoseTheta ? wrapAngle(a(i) - b(i)) : a(i) - b(i);
                DOUBLES_EQUAL(diff / (2.0 * eps), step.F(i, j), 1e-7);
            }
        }
        for (int j = 0; j < 2; ++j) {
            const double dv = j == 0 ? eps : 0.0, dw = j == 1 ? eps : 0.0;
            const PoseState a = unicycleStep(c.s, c.dt, c.v + dv, c.w + dw, c.imu).next;
            const PoseState b = unicycleStep(c.s, c.dt, c.v - dv, c.w - dw, c.imu).next;
            for (int i = 0; i < 4; ++i) {
                const double diff = i == kPoseTheta ? wrapAngle(a(i) - b(i)) : a(i) - b(i);
                DOUBLES_EQUAL(diff / (2.0 * eps), step.G(i, j), 1e-7);
            }
        }
    }
}

TEST(PoseEkfPropagation, CovarianceGrowsAsTheNoiseModelSaysWhenDrivingStraight) {
    const PoseProcessNoise n = tableNoise();
    const double v = 0.3, t = 20.0, dt = 0.01;
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(0.0, 0.0, 0.0, 0.0, 0.0, 0.0));
    for (int i = 0; i < 2000; ++i) {
        CHECK_TRUE(Status::kOk == ekf.predict(dt, v, 0.0, false, n));
        checkSymmetricPsd(ekf.covariance());
    }
    const double qv = n.speedNoiseDensity * n.speedNoiseDensity +
                      (n.speedNoiseFracDensity * v) * (n.speedNoiseFracDensity * v);
    const double qw = n.wheelYawRateNoiseDensity * n.wheelYawRateNoiseDensity;
    const PoseCovariance& p = ekf.covariance();
    DOUBLES_EQUAL(qv * t, p(kPoseX, kPoseX), 1e-12 * qv * t);  // along track: exactly q_v t
    DOUBLES_EQUAL(qw * t, p(kPoseTheta, kPoseTheta), 1e-12 * qw * t);
    // Cross track integrates the heading random walk: v^2 q_w t^3 / 3 (to O(dt/t)).
    DOUBLES_EQUAL(v * v * qw * t * t * t / 3.0, p(kPoseY, kPoseY), 0.01 * v * v * qw * t * t * t / 3.0);
    DOUBLES_EQUAL(v * qw * t * t / 2.0, p(kPoseY, kPoseTheta), 0.01 * v * qw * t * t / 2.0);
    const double biasGrowth = n.gyroBiasWalk * n.gyroBiasWalk * t;
    DOUBLES_EQUAL(biasGrowth, p(kPoseBias, kPoseBias), 1e-9 * biasGrowth);
    DOUBLES_EQUAL(std::sqrt(p(kPoseY, kPoseY)), ekf.positionSigma(), 1e-12);  // cross track dominates
}

TEST(PoseEkfPropagation, StaysSymmetricPsdThroughTurnsAndFixes) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(0.0, 0.0, 0.0, 0.05, 0.005, 0.01));
    for (int i = 1; i <= 3000; ++i) {
        CHECK_TRUE(Status::kOk == ekf.predict(0.01, 0.3, 0.4 * std::sin(0.01 * i), i % 700 < 350, tableNoise()));
        if (i % 100 == 0) {
            FixUpdateResult r;
            CHECK_TRUE(Status::kOk == ekf.updateFix(ekf.x(), ekf.y(), ekf.heading(), 0.05, 0.005, 16.27, &r));
            CHECK_TRUE(r.accepted);
        }
        checkSymmetricPsd(ekf.covariance());
    }
}

TEST_GROUP(PoseEkfFix){};

TEST(PoseEkfFix, AFixAsUncertainAsThePriorHalvesTheVarianceAndMeetsHalfWay) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(0.0, 0.0, 0.0, 0.2, 0.01, 0.01));
    FixUpdateResult r;
    CHECK_TRUE(Status::kOk == ekf.updateFix(0.1, -0.1, 0.005, 0.2, 0.01, 16.27, &r));
    CHECK_TRUE(r.accepted);
    DOUBLES_EQUAL(0.375, r.mahalanobis2, 1e-12);  // 0.1^2 / 0.08 twice plus 0.005^2 / 2e-4
    const PoseCovariance& p = ekf.covariance();
    DOUBLES_EQUAL(0.5 * 0.04, p(kPoseX, kPoseX), 1e-15);
    DOUBLES_EQUAL(0.5 * 0.04, p(kPoseY, kPoseY), 1e-15);
    DOUBLES_EQUAL(0.5 * 1e-4, p(kPoseTheta, kPoseTheta), 1e-18);
    DOUBLES_EQUAL(1e-4, p(kPoseBias, kPoseBias), 1e-18);  // uncorrelated: untouched
    DOUBLES_EQUAL(0.05, ekf.x(), 1e-15);
    DOUBLES_EQUAL(-0.05, ekf.y(), 1e-15);
    DOUBLES_EQUAL(0.0025, ekf.heading(), 1e-15);
    DOUBLES_EQUAL(std::sqrt(0.02), ekf.positionSigma(), 1e-15);
    DOUBLES_EQUAL(std::sqrt(0.5e-4), ekf.headingSigma(), 1e-15);
}

TEST(PoseEkfFix, AnOutlierBeyondTheGateChangesNothing) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(0.0, 0.0, 0.0, 0.2, 0.01, 0.01));
    CHECK_TRUE(Status::kOk == ekf.predict(0.5, 0.3, 0.1, true, tableNoise()));
    const PoseState s = ekf.state();
    const PoseCovariance p = ekf.covariance();
    FixUpdateResult r;
    CHECK_TRUE(Status::kOk == ekf.updateFix(s(0) + 5.0, s(1), s(2), 0.2, 0.01, 16.27, &r));
    CHECK_FALSE(r.accepted);
    Eigen::Matrix3d innovationCov = p.topLeftCorner<3, 3>();
    innovationCov.diagonal() += Eigen::Vector3d(0.04, 0.04, 1e-4);
    const Eigen::Vector3d nu(5.0, 0.0, 0.0);
    const double expected = nu.dot(innovationCov.inverse() * nu);
    DOUBLES_EQUAL(expected, r.mahalanobis2, 1e-9 * expected);
    CHECK_TRUE(r.mahalanobis2 > 16.27);
    CHECK_TRUE(s == ekf.state());
    CHECK_TRUE(p == ekf.covariance());
}

TEST(PoseEkfFix, HeadingInnovationAcrossPlusMinusPiWraps) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(0.0, 0.0, 3.1, 0.05, 0.05, 0.01));
    FixUpdateResult r;
    // -3.0 is 0.183 rad counter-clockwise of 3.1, not 6.1 rad clockwise.
    CHECK_TRUE(Status::kOk == ekf.updateFix(0.0, 0.0, -3.0, 0.05, 0.05, 16.27, &r));
    CHECK_TRUE(r.accepted);
    const double innovation = 2.0 * M_PI - 6.1;
    DOUBLES_EQUAL(innovation * innovation / (2.0 * 0.0025), r.mahalanobis2, 1e-9);
    DOUBLES_EQUAL(3.1 + 0.5 * innovation - 2.0 * M_PI, ekf.heading(), 1e-12);  // past +pi: wrapped
    CHECK_TRUE(ekf.heading() > -M_PI && ekf.heading() <= M_PI);
}

TEST(PoseEkfFix, WrapAngleKeepsPlusPiAndMapsMinusPiToIt) {
    DOUBLES_EQUAL(M_PI, wrapAngle(M_PI), 0.0);
    DOUBLES_EQUAL(M_PI, wrapAngle(-M_PI), 1e-15);
    DOUBLES_EQUAL(0.5, wrapAngle(0.5 + 6.0 * M_PI), 1e-12);
    DOUBLES_EQUAL(-0.5, wrapAngle(-0.5 - 4.0 * M_PI), 1e-12);
}

TEST(PoseEkfFix, PositionSigmaIsTheLargestAxisOfTheXyBlock) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(0.0, 0.0, 0.0, 1.0, 0.01, 0.01));
    // A straight drive along 45 degrees correlates x and y; the closed form must
    // match the numerical eigenvalue.
    PoseEkf tilted;
    CHECK_TRUE(Status::kOk == tilted.init(0.0, 0.0, M_PI / 4.0, 0.01, 0.2, 0.01));
    CHECK_TRUE(Status::kOk == tilted.predict(10.0, 0.3, 0.0, false, tableNoise()));
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(tilted.covariance().topLeftCorner<2, 2>());
    CHECK_TRUE(std::fabs(tilted.covariance()(0, 1)) > 1e-3);
    DOUBLES_EQUAL(std::sqrt(eig.eigenvalues().maxCoeff()), tilted.positionSigma(), 1e-12);
    DOUBLES_EQUAL(1.0, ekf.positionSigma(), 1e-15);
}

TEST(PoseEkfFix, TheGyroBiasBecomesObservableAndConverges) {
    const double trueBias = 0.003;
    Gaussian g(42);
    PoseEkf ekf;
    PoseState truth = stateOf(0.0, 0.0, 0.0, 0.0);
    CHECK_TRUE(Status::kOk == ekf.init(truth(0), truth(1), truth(2), 0.05, 0.005, 0.01));
    const double dt = 0.01;
    for (int i = 1; i <= 30000; ++i) {  // 300 s
        const double v = 0.2, w = 0.15 * std::sin(0.02 * i * dt * 2.0 * M_PI);
        truth = unicycleStep(truth, dt, v, w, false).next;
        const double imu = w + trueBias + 0.002 * g();
        CHECK_TRUE(Status::kOk == ekf.predict(dt, v, imu, true, tableNoise()));
        if (i % 100 == 0) {
            FixUpdateResult r;
            CHECK_TRUE(Status::kOk == ekf.updateFix(truth(0) + 0.05 * g(), truth(1) + 0.05 * g(),
                                                    truth(2) + 0.005 * g(), 0.05, 0.005, 16.27, &r));
        }
    }
    const double sigma = std::sqrt(ekf.covariance()(kPoseBias, kPoseBias));
    CHECK_TRUE(sigma < 0.001);  // from 0.01 at the start
    CHECK_TRUE(std::fabs(ekf.gyroBias() - trueBias) < 3.0 * sigma);
    DOUBLES_EQUAL(trueBias, ekf.gyroBias(), 0.0005);
}

TEST_GROUP(PoseEkfRefusals){};

TEST(PoseEkfRefusals, NothingBeforeInit) {
    PoseEkf ekf;
    FixUpdateResult r;
    CHECK_TRUE(Status::kNotInitialized == ekf.predict(0.01, 0.1, 0.0, true, tableNoise()));
    CHECK_TRUE(Status::kNotInitialized == ekf.updateFix(0.0, 0.0, 0.0, 0.1, 0.01, 16.0, &r));
    CHECK_FALSE(ekf.initialised());
    CHECK_TRUE(Status::kInvalidArgument == ekf.init(0.0, NAN, 0.0, 0.1, 0.01, 0.01));
    CHECK_TRUE(Status::kInvalidArgument == ekf.init(0.0, 0.0, 0.0, -0.1, 0.01, 0.01));
    CHECK_FALSE(ekf.initialised());
}

TEST(PoseEkfRefusals, BadPredictionInputsLeaveTheFilterUnchanged) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(1.0, 2.0, 0.5, 0.1, 0.01, 0.01));
    CHECK_TRUE(Status::kOk == ekf.predict(0.1, 0.2, 0.1, true, tableNoise()));
    const PoseState s = ekf.state();
    const PoseCovariance p = ekf.covariance();
    PoseProcessNoise negative = tableNoise();
    negative.speedNoiseDensity = -1.0;
    CHECK_TRUE(Status::kInvalidArgument == ekf.predict(0.0, 0.2, 0.1, true, tableNoise()));
    CHECK_TRUE(Status::kInvalidArgument == ekf.predict(-0.01, 0.2, 0.1, true, tableNoise()));
    CHECK_TRUE(Status::kInvalidArgument == ekf.predict(NAN, 0.2, 0.1, true, tableNoise()));
    CHECK_TRUE(Status::kInvalidArgument == ekf.predict(0.01, INFINITY, 0.1, true, tableNoise()));
    CHECK_TRUE(Status::kInvalidArgument == ekf.predict(0.01, 0.2, NAN, false, tableNoise()));
    CHECK_TRUE(Status::kInvalidArgument == ekf.predict(0.01, 0.2, 0.1, true, negative));
    CHECK_TRUE(s == ekf.state());
    CHECK_TRUE(p == ekf.covariance());
}

TEST(PoseEkfRefusals, BadFixesLeaveTheFilterUnchanged) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kOk == ekf.init(1.0, 2.0, 0.5, 0.1, 0.01, 0.01));
    const PoseState s = ekf.state();
    const PoseCovariance p = ekf.covariance();
    FixUpdateResult r;
    CHECK_TRUE(Status::kInvalidArgument == ekf.updateFix(NAN, 2.0, 0.5, 0.1, 0.01, 16.0, &r));
    CHECK_TRUE(Status::kInvalidArgument == ekf.updateFix(1.0, 2.0, INFINITY, 0.1, 0.01, 16.0, &r));
    CHECK_TRUE(Status::kInvalidArgument == ekf.updateFix(1.0, 2.0, 0.5, 0.0, 0.01, 16.0, &r));
    CHECK_TRUE(Status::kInvalidArgument == ekf.updateFix(1.0, 2.0, 0.5, 0.1, -0.01, 16.0, &r));
    CHECK_TRUE(Status::kInvalidArgument == ekf.updateFix(1.0, 2.0, 0.5, 0.1, 0.01, 0.0, &r));
    CHECK_TRUE(Status::kInvalidArgument == ekf.updateFix(1.0, 2.0, 0.5, 0.1, 0.01, 16.0, nullptr));
    CHECK_FALSE(r.accepted);
    CHECK_TRUE(s == ekf.state());
    CHECK_TRUE(p == ekf.covariance());
}

TEST_GROUP(PoseEkfReanchor){};

// Re-anchoring: the pose from the fix as at initialisation, the bias estimate
// kept with the given sigma, every correlation gone.
TEST(PoseEkfReanchor, TakesThePoseFromTheFixKeepsTheBiasAndResetsTheCovariance) {
    PoseEkf ekf;
    CHECK_TRUE(Status::kNotInitialized == ekf.reanchor(1.0, 2.0, 0.3, 0.05, 0.005, 0.01));
    CHECK_TRUE(Status::kOk == ekf.init(0.0, 0.0, 0.0, 0.05, 0.005, 0.01));
    const PoseProcessNoise noise = rse::test::defaultTableNoise();
    for (int i = 0; i < 500; ++i) {  // turning on a biased IMU: correlations build up
        CHECK_TRUE(Status::kOk == ekf.predict(0.01, 0.2, 0.05, true, noise));
    }
    FixUpdateResult r;
    CHECK_TRUE(Status::kOk == ekf.updateFix(ekf.x(), ekf.y(), ekf.heading() + 0.01, 0.05, 0.005, 16.27, &r));
    CHECK_TRUE(r.accepted);
    const double bias = ekf.gyroBias();
    CHECK(std::fabs(bias) > 1e-4);
    CHECK(std::fabs(ekf.covariance()(kPoseTheta, kPoseBias)) > 0.0);

    const PoseState before = ekf.state();
    CHECK_TRUE(Status::kInvalidArgument == ekf.reanchor(1.0, 2.0, 0.3, -1.0, 0.005, 0.02));
    CHECK_TRUE(before == ekf.state());

    CHECK_TRUE(Status::kOk == ekf.reanchor(1.0, 2.0, 0.3, 0.05, 0.005, 0.02));
    DOUBLES_EQUAL(1.0, ekf.x(), 0.0);
    DOUBLES_EQUAL(2.0, ekf.y(), 0.0);
    DOUBLES_EQUAL(0.3, ekf.heading(), 1e-15);
    DOUBLES_EQUAL(bias, ekf.gyroBias(), 0.0);
    PoseCovariance expected = PoseCovariance::Zero();
    expected(kPoseX, kPoseX) = 0.05 * 0.05;
    expected(kPoseY, kPoseY) = 0.05 * 0.05;
    expected(kPoseTheta, kPoseTheta) = 0.005 * 0.005;
    expected(kPoseBias, kPoseBias) = 0.02 * 0.02;
    CHECK_TRUE(expected == ekf.covariance());
}

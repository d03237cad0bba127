#include "fsw/estimator/pose_ekf.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace rse::estimator {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
// Below this |h| the closed forms of sinc and its derivative lose digits to
// cancellation; the series terms kept are exact to well below double rounding.
constexpr double kSeriesBelow = 1e-3;

bool finite(double v) { return std::isfinite(v); }

double sinc(double h) {
    if (std::fabs(h) < kSeriesBelow) {
        const double h2 = h * h;
        return 1.0 - h2 / 6.0 + h2 * h2 / 120.0;
    }
    return std::sin(h) / h;
}

double sincDerivative(double h) {
    if (std::fabs(h) < kSeriesBelow) {
        const double h2 = h * h;
        return h * (-1.0 / 3.0 + h2 / 30.0);
    }
    return (h * std::cos(h) - std::sin(h)) / (h * h);
}

}  // namespace

double wrapAngle(double angleRad) {
    double wrapped = std::remainder(angleRad, kTwoPi);  // [-pi, pi]
    if (wrapped <= -kPi) {
        wrapped += kTwoPi;
    }
    return wrapped;
}

UnicycleStep unicycleStep(const PoseState& state, double dtS, double speedMS, double omegaMeasuredRadS,
                          bool yawFromImu) {
    UnicycleStep step{};
    const double omega = yawFromImu ? omegaMeasuredRadS - state(kPoseBias) : omegaMeasuredRadS;
    const double h = 0.5 * omega * dtS;
    const double c = sinc(h);
    const double dc = sincDerivative(h);
    const double a = state(kPoseTheta) + h;
    const double cosA = std::cos(a);
    const double sinA = std::sin(a);
    const double chord = speedMS * dtS * c;

    step.yawRateRadS = omega;
    step.next = state;
    step.next(kPoseX) += chord * cosA;
    step.next(kPoseY) += chord * sinA;
    step.next(kPoseTheta) = wrapAngle(state(kPoseTheta) + 2.0 * h);

    step.G.setZero();
    step.G(kPoseX, 0) = dtS * c * cosA;
    step.G(kPoseY, 0) = dtS * c * sinA;
    step.G(kPoseX, 1) = 0.5 * dtS * (speedMS * dtS * dc * cosA - chord * sinA);
    step.G(kPoseY, 1) = 0.5 * dtS * (speedMS * dtS * dc * sinA + chord * cosA);
    step.G(kPoseTheta, 1) = dtS;

    step.F.setIdentity();
    step.F(kPoseX, kPoseTheta) = -chord * sinA;
    step.F(kPoseY, kPoseTheta) = chord * cosA;
    if (yawFromImu) {
        // omega = omegaMeasured - b: the bias enters exactly as -omega does.
        step.F.col(kPoseBias) -= step.G.col(1);
        step.F(kPoseBias, kPoseBias) = 1.0;
    }
    return step;
}

core::Status PoseEkf::init(double xM, double yM, double thetaRad, double sigmaXyM, double sigmaThetaRad,
                           double sigmaBiasRadS) {
    if (!finite(xM) || !finite(yM) || !finite(thetaRad) || !finite(sigmaXyM) || !finite(sigmaThetaRad) ||
        !finite(sigmaBiasRadS) || sigmaXyM < 0.0 || sigmaThetaRad < 0.0 || sigmaBiasRadS < 0.0) {
        return core::Status::kInvalidArgument;
    }
    state_ << xM, yM, wrapAngle(thetaRad), 0.0;
    covariance_.setZero();
    covariance_(kPoseX, kPoseX) = sigmaXyM * sigmaXyM;
    covariance_(kPoseY, kPoseY) = sigmaXyM * sigmaXyM;
    covariance_(kPoseTheta, kPoseTheta) = sigmaThetaRad * sigmaThetaRad;
    covariance_(kPoseBias, kPoseBias) = sigmaBiasRadS * sigmaBiasRadS;
    initialised_ = true;
    return core::Status::kOk;
}

core::Status PoseEkf::reanchor(double xM, double yM, double thetaRad, double sigmaXyM, double sigmaThetaRad,
                               double sigmaBiasRadS) {
    if (!initialised_) {
        return core::Status::kNotInitialized;
    }
    const double bias = state_(kPoseBias);
    const core::Status status = init(xM, yM, thetaRad, sigmaXyM, sigmaThetaRad, sigmaBiasRadS);
    state_(kPoseBias) = bias;
    return status;
}

core::Status PoseEkf::predict(double dtS, double speedMS, double omegaMeasuredRadS, bool yawFromImu,
                              const PoseProcessNoise& noise) {
    if (!initialised_) {
        return core::Status::kNotInitialized;
    }
    const double densities[] = {noise.speedNoiseDensity, noise.speedNoiseFracDensity, noise.imuYawRateNoiseDensity,
                                noise.wheelYawRateNoiseDensity, noise.gyroBiasWalk};
    for (double d : densities) {
        if (!finite(d) || d < 0.0) {
            return core::Status::kInvalidArgument;
        }
    }
    if (!finite(dtS) || dtS <= 0.0 || !finite(speedMS) || !finite(omegaMeasuredRadS)) {
        return core::Status::kInvalidArgument;
    }
    const UnicycleStep step = unicycleStep(state_, dtS, speedMS, omegaMeasuredRadS, yawFromImu);

    const double speedFrac = noise.speedNoiseFracDensity * std::fabs(speedMS);
    const double qv = noise.speedNoiseDensity * noise.speedNoiseDensity + speedFrac * speedFrac;
    const double yawDensity = yawFromImu ? noise.imuYawRateNoiseDensity : noise.wheelYawRateNoiseDensity;
    const double qw = yawDensity * yawDensity;
    Eigen::Matrix2d inputNoise = Eigen::Matrix2d::Zero();
    inputNoise(0, 0) = qv / dtS;
    inputNoise(1, 1) = qw / dtS;
    PoseCovariance processNoise = step.G * inputNoise * step.G.transpose();
    processNoise(kPoseBias, kPoseBias) += noise.gyroBiasWalk * noise.gyroBiasWalk * dtS;

    const PoseCovariance predicted = step.F * covariance_ * step.F.transpose() + processNoise;
    if (!step.next.allFinite() || !predicted.allFinite()) {
        return core::Status::kInvalidArgument;  // dt so long the numbers overflow
    }
    state_ = step.next;
    covariance_ = predicted;
    symmetrise();
    return core::Status::kOk;
}

core::Status PoseEkf::updateFix(double xM, double yM, double thetaRad, double sigmaXyM, double sigmaThetaRad,
                                double gateChi2, FixUpdateResult* result) {
    if (result == nullptr) {
        return core::Status::kInvalidArgument;
    }
    *result = FixUpdateResult{};
    if (!initialised_) {
        return core::Status::kNotInitialized;
    }
    if (!finite(xM) || !finite(yM) || !finite(thetaRad) || !finite(sigmaXyM) || !finite(sigmaThetaRad) ||
        !finite(gateChi2) || sigmaXyM <= 0.0 || sigmaThetaRad <= 0.0 || gateChi2 <= 0.0) {
        return core::Status::kInvalidArgument;
    }
    Eigen::Vector3d innovation;
    innovation << xM - state_(kPoseX), yM - state_(kPoseY), wrapAngle(thetaRad - state_(kPoseTheta));

    Eigen::Matrix3d measurementNoise = Eigen::Matrix3d::Zero();
    measurementNoise(0, 0) = sigmaXyM * sigmaXyM;
    measurementNoise(1, 1) = sigmaXyM * sigmaXyM;
    measurementNoise(2, 2) = sigmaThetaRad * sigmaThetaRad;
    const Eigen::Matrix3d innovationCov = covariance_.topLeftCorner<3, 3>() + measurementNoise;
    const Eigen::LLT<Eigen::Matrix3d> llt(innovationCov);
    if (llt.info() != Eigen::Success) {
        return core::Status::kInvalidArgument;
    }
    const Eigen::Vector3d whitened = llt.solve(innovation);
    result->mahalanobis2 = innovation.dot(whitened);
    if (!finite(result->mahalanobis2) || result->mahalanobis2 > gateChi2) {
        return core::Status::kOk;  // gated: an outlier must not move the estimate
    }

    // K = P H^T S^-1; with H = [I3 | 0], H P is the top three rows of P.
    const Eigen::Matrix<double, 4, 3> gain = llt.solve(covariance_.topRows<3>()).transpose();
    PoseJacobian iMinusKh = PoseJacobian::Identity();
    iMinusKh.leftCols<3>() -= gain;
    state_ += gain * innovation;
    state_(kPoseTheta) = wrapAngle(state_(kPoseTheta));
    covariance_ = iMinusKh * covariance_ * iMinusKh.transpose() + gain * measurementNoise * gain.transpose();
    symmetrise();
    result->accepted = true;
    return core::Status::kOk;
}

double PoseEkf::positionSigma() const {
    const double a = covariance_(kPoseX, kPoseX);
    const double c = covariance_(kPoseY, kPoseY);
    const double b = covariance_(kPoseX, kPoseY);
    const double halfDiff = 0.5 * (a - c);
    const double largest = 0.5 * (a + c) + std::sqrt(halfDiff * halfDiff + b * b);
    return std::sqrt(largest > 0.0 ? largest : 0.0);
}

double PoseEkf::headingSigma() const {
    const double v = covariance_(kPoseTheta, kPoseTheta);
    return std::sqrt(v > 0.0 ? v : 0.0);
}

void PoseEkf::symmetrise() {
    const PoseCovariance transposed = covariance_.transpose();
    covariance_ = 0.5 * (covariance_ + transposed);
}

}  // namespace rse::estimator

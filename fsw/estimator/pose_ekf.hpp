// The rover's pose filter: an extended Kalman filter over
//   s = [x, y, theta, b]
// x, y site frame (m), theta heading (rad, wrapped to (-pi, pi]), b the IMU
// yaw-rate bias (rad/s). Pure math: no bus, no tables, no events; the pose
// estimator task (pose_estimator_task.hpp) feeds it and reports what it refuses.
//
// Every layer decides from this estimate and the planner starts its chance
// constraints from its covariance, so the covariance has to be honest
// (consistent with the real error), not merely small.
//
// Process model (one prediction over dt with v and omega held constant):
//   omega = omegaMeasured - b   when the yaw rate comes from the IMU,
//   omega = omegaMeasured       when it comes from the wheels (b not involved).
// The exact unicycle solution, written so it has no 0/0 at omega = 0:
//   h = omega dt / 2,  L = v dt sinc(h)  (chord length),  a = theta + h
//   x' = x + L cos(a),  y' = y + L sin(a),  theta' = theta + 2h,  b' = b
// sinc and its derivative switch to their Taylor series for |h| < 1e-3, so
// straight driving (h = 0) is the exact straight line, not a limit taken
// numerically. F = df/ds and G = df/d(v, omega) are the analytic Jacobians.
//
// Process noise: v and omega carry continuous white noise of densities
//   q_v = speed_noise_density^2 + (speed_noise_frac_density |v|)^2   [m^2/s]
//   q_w = imu (or wheel) yaw_rate_noise_density^2                    [rad^2/s]
// and the bias walks with density q_b = gyro_bias_walk^2 [rad^2/s^3]. Held
// over dt, white noise of density q averages to variance q / dt, and G (the
// discrete step's Jacobian) already carries one factor dt, so
//   Q = G diag(q_v, q_w) G^T / dt + diag(0, 0, 0, q_b dt)
// which is the continuous-time G_c diag(q) G_c^T dt with G_c = G / dt: straight
// along-track variance grows by exactly q_v t.
//
// Position fix: z = [x, y, theta], H = [I3 | 0], R = diag(sxy^2, sxy^2, sth^2),
// heading innovation wrapped to (-pi, pi]. Mahalanobis d2 = nu^T S^-1 nu
// (chi-square, 3 dof) beyond the gate: the fix is rejected and nothing changes.
// Otherwise the Joseph form P = (I-KH) P (I-KH)^T + K R K^T, which stays
// symmetric positive semi-definite whatever the rounding. P is symmetrised
// after every step.
//
// Fixed-size Eigen only: nothing here allocates.
#pragma once

#include <Eigen/Core>

#include "fsw/core/status.hpp"

namespace rse::estimator {

using PoseState = Eigen::Matrix<double, 4, 1>;
using PoseCovariance = Eigen::Matrix<double, 4, 4>;
using PoseJacobian = Eigen::Matrix<double, 4, 4>;
using PoseNoiseJacobian = Eigen::Matrix<double, 4, 2>;

// State indices.
constexpr int kPoseX = 0;
constexpr int kPoseY = 1;
constexpr int kPoseTheta = 2;
constexpr int kPoseBias = 3;

// Wraps an angle to (-pi, pi]; a finite input is required.
double wrapAngle(double angleRad);

// One exact unicycle step with its Jacobians (exposed for tests and for any
// layer that needs to predict a pose the same way the filter does).
struct UnicycleStep {
    PoseState next;          // theta wrapped
    PoseJacobian F;          // d next / d state
    PoseNoiseJacobian G;     // d next / d (v, omega)
    double yawRateRadS;      // the omega used (bias-corrected when from the IMU)
};
UnicycleStep unicycleStep(const PoseState& state, double dtS, double speedMS, double omegaMeasuredRadS,
                          bool yawFromImu);

// Densities of the continuous white noises (see the header comment).
struct PoseProcessNoise {
    double speedNoiseDensity = 0.0;        // m/sqrt(s)
    double speedNoiseFracDensity = 0.0;    // sqrt(s)
    double imuYawRateNoiseDensity = 0.0;   // rad/sqrt(s)
    double wheelYawRateNoiseDensity = 0.0; // rad/sqrt(s)
    double gyroBiasWalk = 0.0;             // rad/s/sqrt(s)
};

struct FixUpdateResult {
    bool accepted = false;
    double mahalanobis2 = 0.0;  // d2 of the innovation (reported whether accepted or not)
};

class PoseEkf {
public:
    // Any sigma must be finite and >= 0 (kInvalidArgument otherwise, the filter unchanged).
    core::Status init(double xM, double yM, double thetaRad, double sigmaXyM, double sigmaThetaRad,
                      double sigmaBiasRadS);

    // Puts position and heading at a fix with the fix's sigmas, drops every
    // correlation and gives the bias (estimate kept) the variance sigmaBias^2,
    // so the fixes that follow re-estimate it. For a filter whose estimate the
    // fixes have refuted (a bias step it could not follow): kNotInitialized
    // before init(), kInvalidArgument as init(), the filter unchanged.
    core::Status reanchor(double xM, double yM, double thetaRad, double sigmaXyM, double sigmaThetaRad,
                          double sigmaBiasRadS);

    // kNotInitialized before init(); kInvalidArgument for dt <= 0, a non-finite
    // input or a negative / non-finite noise density, the filter unchanged.
    core::Status predict(double dtS, double speedMS, double omegaMeasuredRadS, bool yawFromImu,
                         const PoseProcessNoise& noise);

    // kOk when the fix was judged (result says accepted or gated, and d2);
    // kNotInitialized before init(); kInvalidArgument for non-finite values, a
    // sigma <= 0, a gate <= 0 or an innovation covariance that is not positive
    // definite. Only an accepted fix changes the filter.
    core::Status updateFix(double xM, double yM, double thetaRad, double sigmaXyM, double sigmaThetaRad,
                           double gateChi2, FixUpdateResult* result);

    bool initialised() const { return initialised_; }
    const PoseState& state() const { return state_; }
    const PoseCovariance& covariance() const { return covariance_; }
    double x() const { return state_(kPoseX); }
    double y() const { return state_(kPoseY); }
    double heading() const { return state_(kPoseTheta); }
    double gyroBias() const { return state_(kPoseBias); }
    // sqrt of the largest eigenvalue of the (x, y) block (closed form for 2x2).
    double positionSigma() const;
    double headingSigma() const;

private:
    void symmetrise();

    PoseState state_ = PoseState::Zero();
    PoseCovariance covariance_ = PoseCovariance::Zero();
    bool initialised_ = false;
};

}  // namespace rse::estimator

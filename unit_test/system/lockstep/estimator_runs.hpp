// Seeded lockstep drives for judging the estimator against simulator truth:
// shared by the estimator benchmark (unit_test/bench/bench_estimator.cpp, 100
// five-minute runs) and the lockstep tests (a few short runs).
//
// The harness plays the part of a higher layer: it commands body speed and yaw
// rate from a seeded random profile, kept on the flight software's site (the
// COARSE_MAP bounds) by steering on the flight software's own pose estimate, as
// a higher layer would. It alone reads the simulator's truth, to score the
// flight software's estimate; nothing of it reaches the flight code.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/geometry/site_bounds.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"

namespace rse::test {

// Segments of 5-20 s: mostly arcs at 0.1-0.3 m/s and up to 0.1 rad/s, sometimes
// a stop or a turn on the spot, so the estimator sees straight lines, curves,
// rotations and standstill. Commands ramp at the rover's acceleration limits
// (as a trajectory follower's would): a step from rest to full speed would ask
// the drives for a current spike that is not a fault. Turn rates stay gentle
// because skid-steer scrubbing loads the motors: a nominal drive then draws at
// most ~1.8 A, below the 2.5 A over-current threshold, while a drive degraded
// by 1.6 still stays under the drives' own 3 A trip.
//
// Kept on a site (the second constructor and the at() that takes the pose
// estimate): the simulated world may be larger than the flight software's
// site, and a rover the estimate puts off the site raises fault 46 (off the
// map) — rightly, so the drive must not leave it. Within kSiteMarginM of an
// edge, heading out through it, the profile drops its segment and arcs back
// (kReturnSpeedMS, kReturnYawRateRadS: a 1 m radius, inside the profile's own
// range of commands) towards the site's centre until it heads in through
// every edge it is near, then draws a new segment. The rover goes on outwards
// for a while (slowing from up to 0.3 m/s, reversing the yaw rate, the arc's
// radius): in bench_estimator's 100 runs it came within 1.06 m of an edge,
// its footprint (radius 0.6 m) still on the site.
class DriveProfile {
public:
    static constexpr double kMaxAccelMS2 = 0.2;   // rover geometry table max_accel_m_s2
    static constexpr double kMaxYawAccelRadS2 = 0.2;
    static constexpr double kSiteMarginM = 3.0;
    static constexpr double kReturnSpeedMS = 0.1;
    static constexpr double kReturnYawRateRadS = 0.1;

    explicit DriveProfile(std::uint64_t seed) : rng_(seed ^ 0x5EEDD12E5ULL) {}
    DriveProfile(std::uint64_t seed, const geometry::SiteBox& site) : DriveProfile(seed) {
        site_ = site;
        keepOnSite_ = true;
    }

    // Steers on the estimate (when initialised) to keep on the site, if one was given.
    void at(core::TimeNs now, const msg::PoseEstimateMsg& estimate, double* speedMS, double* yawRateRadS) {
        if (keepOnSite_ && estimate.initialised != 0) {
            steer(now, estimate);
        }
        at(now, speedMS, yawRateRadS);
    }

    void at(core::TimeNs now, double* speedMS, double* yawRateRadS) {
        while (!returning_ && now >= segmentEnd_) {
            next();
        }
        const double dt = static_cast<double>(now - last_) * 1e-9;
        last_ = now;
        speed_ += clamp(targetSpeed_ - speed_, kMaxAccelMS2 * dt);
        yawRate_ += clamp(targetYawRate_ - yawRate_, kMaxYawAccelRadS2 * dt);
        *speedMS = speed_;
        *yawRateRadS = yawRate_;
    }

    // Times the profile turned back from a site edge.
    unsigned siteReturns() const { return siteReturns_; }

private:
    static double clamp(double delta, double limit) { return std::max(-limit, std::min(limit, delta)); }

    // Whether a rover at (x, y) heading `heading` is within kSiteMarginM of an
    // edge (or beyond it) and moves out through it (outward > 0), or moves in
    // through every edge it is that near (outward < 0 for all: returns false
    // with *inward true).
    bool headingOut(double x, double y, double heading, bool* inward) const {
        const double c = std::cos(heading);
        const double sn = std::sin(heading);
        // Each edge: distance inside it, and the heading's component along its outward normal.
        const double inside[4] = {x - site_.minX, site_.maxX - x, y - site_.minY, site_.maxY - y};
        const double outward[4] = {-c, c, -sn, sn};
        bool out = false;
        *inward = true;
        for (std::size_t e = 0; e < 4; ++e) {
            if (inside[e] < kSiteMarginM) {
                out = out || outward[e] > 0.0;
                *inward = *inward && outward[e] < 0.0;
            }
        }
        return out;
    }

    void steer(core::TimeNs now, const msg::PoseEstimateMsg& est) {
        bool inward = false;
        const bool out = headingOut(est.xM, est.yM, est.headingRad, &inward);
        if (!returning_ && out) {
            // Turn the shorter way towards the centre, and keep that way round.
            const double toCentre = std::atan2(0.5 * (site_.minY + site_.maxY) - est.yM,
                                               0.5 * (site_.minX + site_.maxX) - est.xM);
            const double error = geometry::wrapAngleRad(toCentre - est.headingRad);
            returning_ = true;
            ++siteReturns_;
            targetSpeed_ = kReturnSpeedMS;
            targetYawRate_ = error >= 0.0 ? kReturnYawRateRadS : -kReturnYawRateRadS;
        } else if (returning_ && inward) {
            returning_ = false;
            segmentEnd_ = now;  // a new segment from here
        }
    }

    void next() {
        std::uniform_real_distribution<double> u(0.0, 1.0);
        const double kind = u(rng_);
        double seconds = 5.0 + 15.0 * u(rng_);
        if (kind < 0.1) {
            targetSpeed_ = 0.0;
            targetYawRate_ = 0.0;
            seconds = 2.0 + 3.0 * u(rng_);
        } else if (kind < 0.2) {
            targetSpeed_ = 0.0;
            targetYawRate_ = u(rng_) < 0.5 ? -0.1 : 0.1;
            seconds = 3.0 + 7.0 * u(rng_);
        } else {
            targetSpeed_ = 0.1 + 0.2 * u(rng_);
            targetYawRate_ = -0.1 + 0.2 * u(rng_);
        }
        segmentEnd_ += static_cast<core::TimeNs>(seconds * 1e9);
    }

    std::mt19937_64 rng_;
    core::TimeNs segmentEnd_ = 0;
    core::TimeNs last_ = 0;
    double targetSpeed_ = 0.0;
    double targetYawRate_ = 0.0;
    double speed_ = 0.0;
    double yawRate_ = 0.0;
    geometry::SiteBox site_;
    bool keepOnSite_ = false;
    bool returning_ = false;
    unsigned siteReturns_ = 0;
};

inline double wrapPi(double a) {
    while (a > M_PI) {
        a -= 2.0 * M_PI;
    }
    while (a <= -M_PI) {
        a += 2.0 * M_PI;
    }
    return a;
}

// NEES of the (x, y, heading) error against the published 3x3 covariance.
inline double poseNees(const msg::PoseEstimateMsg& est, const sim::Pose2& truth, double* posErr2,
                       double* headingErr2) {
    const double e[3] = {truth.x - est.xM, truth.y - est.yM, wrapPi(truth.theta - est.headingRad)};
    *posErr2 = e[0] * e[0] + e[1] * e[1];
    *headingErr2 = e[2] * e[2];
    // Solve P z = e by Cholesky (P is symmetric positive definite when honest).
    double L[3][3] = {};
    const double* P = est.covariance;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j <= i; ++j) {
            double sum = P[i * 3 + j];
            for (int k = 0; k < j; ++k) {
                sum -= L[i][k] * L[j][k];
            }
            if (i == j) {
                if (sum <= 0.0) {
                    return INFINITY;
                }
                L[i][i] = std::sqrt(sum);
            } else {
                L[i][j] = sum / L[j][j];
            }
        }
    }
    double y[3];
    for (int i = 0; i < 3; ++i) {
        double sum = e[i];
        for (int k = 0; k < i; ++k) {
            sum -= L[i][k] * y[k];
        }
        y[i] = sum / L[i][i];
    }
    return y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
}

// Chi-square quantile (Wilson-Hilferty; within 0.1 % for the hundreds of
// degrees of freedom used here). z: standard normal quantile of the probability.
inline double chiSquareQuantile(double dof, double z) {
    const double a = 2.0 / (9.0 * dof);
    const double c = 1.0 - a + z * std::sqrt(a);
    return dof * c * c * c;
}
constexpr double kZ975 = 1.959963985;

struct NominalRun {
    std::vector<double> nees;  // one per NEES sample time (1 Hz, half-way between fixes)
    double sumPosErr2 = 0.0;   // over every frame after initialisation
    double sumHeadingErr2 = 0.0;
    std::uint64_t frames = 0;
    double maxPosErr = 0.0;
    bool initialised = false;
    unsigned driveModeAlarms = 0;  // frames x wheels declared other than nominal
    std::uint32_t faultsRaised = 0;
    std::uint32_t raisedById[msg::fault::kCount] = {};  // faultsRaised by fault id
    double closestToEdgeM = INFINITY;  // the rover (truth) to the nearest site edge; negative: off the site
    unsigned siteReturns = 0;          // times the profile turned back from the site's edge
    std::uint32_t fixesRejected = 0;
    double distanceM = 0.0;
    // Host CPU per run of the estimator, drive_modes and health tasks (ns).
    core::TimeNs cpuMean[3] = {};
    core::TimeNs cpuMax[3] = {};
};

constexpr const char* kEstimatorTaskNames[3] = {"estimator", "drive_modes", "health"};

// keepOnSite false: the profile alone, wherever it leads (to see fault 46 raised).
inline NominalRun runNominal(const sim::Scenario& base, std::uint64_t seed, double durationS,
                             bool keepOnSite = true) {
    sim::Scenario scenario = base;
    scenario.seed = seed;
    auto rig = std::make_unique<sim::LockstepRig>(scenario);
    NominalRun out;
    if (!core::isOk(rig->init())) {
        return out;
    }
    const geometry::SiteBox site = geometry::siteBox(rig->fsw().tables().coarseMap(), 0.0);
    DriveProfile profile = keepOnSite ? DriveProfile(seed, site) : DriveProfile(seed);
    const core::TimeNs end = static_cast<core::TimeNs>(durationS * 1e9);
    const core::TimeNs firstSample = 1500 * core::kNsPerMs;  // then every second, half-way between fixes
    core::TimeNs nextSample = firstSample;
    while (rig->clock().now() < end) {
        double v = 0.0;
        double w = 0.0;
        profile.at(rig->clock().now(), rig->fsw().poseEstimator().latest(), &v, &w);
        rig->commandBody(v, w);
        rig->runFor(app::kMinorFramePeriod);
        const msg::PoseEstimateMsg& est = rig->fsw().poseEstimator().latest();
        const sim::TruthRecord& truth = rig->rover().truth();
        out.closestToEdgeM = std::min(out.closestToEdgeM, -geometry::outsideBy(site, truth.pose.x, truth.pose.y));
        for (std::size_t wheel = 0; wheel < msg::kWheelCount; ++wheel) {
            if (rig->fsw().driveModes().declared(wheel) != msg::DriveMode::kNominal) {
                ++out.driveModeAlarms;
            }
        }
        if (est.initialised == 0) {
            continue;
        }
        out.initialised = true;
        double posErr2 = 0.0;
        double headingErr2 = 0.0;
        const double nees = poseNees(est, truth.pose, &posErr2, &headingErr2);
        out.sumPosErr2 += posErr2;
        out.sumHeadingErr2 += headingErr2;
        out.maxPosErr = std::max(out.maxPosErr, std::sqrt(posErr2));
        ++out.frames;
        if (est.timeNs >= nextSample) {
            out.nees.push_back(nees);
            nextSample += core::kNsPerSec;
        }
    }
    out.faultsRaised = rig->fsw().health().status().raisedTotal;
    for (std::uint8_t id = 0; id < msg::fault::kCount; ++id) {
        out.raisedById[id] = rig->fsw().health().raisedCount(id);
    }
    out.siteReturns = profile.siteReturns();
    out.fixesRejected = rig->fsw().poseEstimator().latest().fixesRejected;
    out.distanceM = rig->rover().truth().distanceM;
    const core::Executive& exec = rig->fsw().executive();
    for (std::size_t i = 0; i < exec.taskCount(); ++i) {
        for (std::size_t k = 0; k < 3; ++k) {
            if (std::string(exec.entry(i)->name) == kEstimatorTaskNames[k]) {
                out.cpuMean[k] = exec.taskStats(i)->hostMean();
                out.cpuMax[k] = exec.taskStats(i)->hostMax;
            }
        }
    }
    return out;
}

struct FaultRun {
    std::size_t wheel = 0;
    double factor = 1.0;
    double degradeAtS = 0.0;
    double failAtS = 0.0;
    double degradeLatencyS = -1.0;  // injection -> declared degraded (-1: never)
    double failLatencyS = -1.0;     // injection -> declared failed (-1: never)
    bool degradedBeforeFail = false;
    unsigned otherWheelAlarms = 0;  // frames x other wheels declared other than nominal
};

// A motor degrades at a random time in [60, 120] s by a random factor in
// [1.3, 1.6], then fails 30-60 s later; the run ends 3 s after the failure.
// (Beyond ~1.6 the degraded drive trips its own 3 A over-current protection on
// the profile's turns: a CiA 402 fault, which is a different story.)
inline FaultRun runFaulted(const sim::Scenario& base, std::uint64_t seed) {
    sim::Scenario scenario = base;
    scenario.seed = seed;
    std::mt19937_64 pick(seed ^ 0xFA17ULL);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    FaultRun out;
    out.wheel = static_cast<std::size_t>(pick() % msg::kWheelCount);
    out.factor = 1.3 + 0.3 * u(pick);
    out.degradeAtS = 60.0 + 60.0 * u(pick);
    out.failAtS = out.degradeAtS + 30.0 + 30.0 * u(pick);
    auto rig = std::make_unique<sim::LockstepRig>(scenario);
    if (!core::isOk(rig->init())) {
        return out;
    }
    DriveProfile profile(seed, geometry::siteBox(rig->fsw().tables().coarseMap(), 0.0));
    const auto degradeAt = static_cast<core::TimeNs>(out.degradeAtS * 1e9);
    const auto failAt = static_cast<core::TimeNs>(out.failAtS * 1e9);
    const core::TimeNs end = failAt + 3 * core::kNsPerSec;
    bool degraded = false;
    bool failed = false;
    while (rig->clock().now() < end) {
        const core::TimeNs now = rig->clock().now();
        if (!degraded && now >= degradeAt) {
            rig->rover().degradeMotor(out.wheel, out.factor);
            degraded = true;
        }
        if (!failed && now >= failAt) {
            rig->rover().failMotor(out.wheel);
            failed = true;
        }
        double v = 0.0;
        double w = 0.0;
        profile.at(now, rig->fsw().poseEstimator().latest(), &v, &w);
        rig->commandBody(v, w);
        rig->runFor(app::kMinorFramePeriod);
        const double t = static_cast<double>(rig->clock().now()) * 1e-9;
        const msg::DriveMode mode = rig->fsw().driveModes().declared(out.wheel);
        if (degraded && out.degradeLatencyS < 0.0 && mode == msg::DriveMode::kDegraded) {
            out.degradeLatencyS = t - out.degradeAtS;
            out.degradedBeforeFail = !failed;
        }
        if (failed && out.failLatencyS < 0.0 && mode == msg::DriveMode::kFailed) {
            out.failLatencyS = t - out.failAtS;
        }
        for (std::size_t wheel = 0; wheel < msg::kWheelCount; ++wheel) {
            if (wheel != out.wheel && rig->fsw().driveModes().declared(wheel) != msg::DriveMode::kNominal) {
                ++out.otherWheelAlarms;
            }
        }
    }
    return out;
}

}  // namespace rse::test

// A plan's certified risk one segment a unit (cc_risk_certifier.hpp): each
// segment's share is the smaller of its deltas' sum and the bound from the
// means, riskUsed their sum, and each unit's tails and orthants are charged.
// The expected figures are worked out by hand from the Gaussian tail of known
// margins (values from mpmath at 40 digits), not from plan_risk.hpp.
#include <cmath>
#include <cstdint>

#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_risk_certifier.hpp"
#include "fsw/deliberative/cc_work_units.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::boxAboveTheWay;

namespace {

CcRiskCertifier certifier;

// |expected - actual| within `relative` of expected (for risks of 1e-72 ..
// 1e-36, where an absolute tolerance says nothing).
void checkRelative(double expected, double actual, double relative) {
    DOUBLES_EQUAL(expected, actual, std::fabs(expected) * relative);
}

}  // namespace

TEST_GROUP(CcRiskCertifier){};

// The box (x 3..5, y 2..4) 2 m above a straight path along y = 0 from (0, 0)
// to (8, 0) in 6 steps: mu_tau = (4 tau / 3, 0). The end variances on any
// face are Sigma_0 + tau sigma^2 = 0.01 + 0.0025 tau = 0.0025 (4 + tau), so
// the bottom face (y >= 2: slack 2 m at every end) is missed by an end with
// probability Q(2 / (0.05 sqrt(4 + tau))) = Q(40 / sqrt(4 + tau)):
//   tau  z = 40/sqrt(4+tau)   Q(z)
//   0    20                   2.7536241186062337e-89
//   1    17.888543819998318   7.2422121863684707e-72
//   2    16.329931618554521   3.0226034100424410e-60
//   3    15.118578920369089   6.1075119883380502e-52
//   4    14.142135623730950   1.0442437918812724e-45
//   5    13.333333333333333   7.4064127719071423e-41
//   6    12.649110640673517   5.6574189512164918e-37
// Every segment's bottom-face union Q(z_t) + Q(z_{t+1}) is below 1e-30
// (kNegligibleRisk), so the bound is that sum, nothing refined; the other
// faces' unions are larger (the top face's is 1, the left face's at least
// 1.48e-50 at segment 0 against 7.24e-72). Segments 0..4 have deltas of
// 5e-4 + 5e-4 = 1e-3, far above; segment 5's are 1e-40 + 1e-40 = 2e-40,
// below its 5.66e-37: the deltas win.
//
// Work a unit: 4 faces x 2 ends = 8 tails (20 each); an orthant (320) for
// each face whose union passes 1e-30 (the top face always; the right face,
// x <= 5, at every segment: at segment 5 its ends are 1.667 m / 0.15 m =
// 11.1 sigma and 3 m / 0.158 m away, Q = 5.54e-29; the left face, x >= 3,
// from segment 1 on: at segment 0 its ends are 30 and 14.9 sigma away, 1.48e-50),
// none for the bottom face. Segment 0: 160 + 2 x 320 = 800; the others
// 160 + 3 x 320 = 1120.
TEST(CcRiskCertifier, EachSegmentIsChargedTheGaussianTailsOfItsEndsOrItsDeltas) {
    const CcProblem p = boxAboveTheWay(6);
    CcPlan plan{};
    plan.steps = p.steps;
    for (std::size_t tau = 0; tau <= p.steps; ++tau) {
        plan.meanX[tau] = 8.0 * static_cast<double>(tau) / 6.0;
        plan.meanY[tau] = 0.0;
    }
    for (std::size_t t = 0; t < p.steps; ++t) {
        plan.delta[t][0][0] = plan.delta[t][0][1] = t == 5 ? 1e-40 : 5e-4;
    }
    claimBooleRisk(p, &plan);  // what the certifier replaces: the deltas' sums
    DOUBLES_EQUAL(1e-3, plan.segmentRisk[0], 1e-18);

    const double expectedRisk[6] = {
        7.2422121863684707e-72,  // Q(z0) + Q(z1)
        3.0226034100496833e-60,  // Q(z1) + Q(z2)
        6.1075120185640843e-52,  // Q(z2) + Q(z3)
        1.0442444026324712e-45,  // Q(z3) + Q(z4)
        7.4065171962863304e-41,  // Q(z4) + Q(z5)
        2e-40,                   // the deltas: below Q(z5) + Q(z6) = 5.6581595924936825e-37
    };
    const std::uint64_t expectedWork[6] = {800, 1920, 3040, 4160, 5280, 6400};  // cumulative
    CHECK_FALSE(certifier.running());
    certifier.start();
    CHECK(certifier.running());
    std::uint64_t work = 0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        const bool last = certifier.unit(p, &plan, &work);
        CHECK_EQUAL(t + 1 == p.steps, last);
        checkRelative(expectedRisk[t], plan.segmentRisk[t], 1e-9);
        LONGS_EQUAL(expectedWork[t], work);
    }
    CHECK_FALSE(certifier.running());
    // 7.4065171962863304e-41 + 2e-40 + the (negligible) rest.
    checkRelative(2.7406621620787669e-40, plan.riskUsed, 1e-9);
}

// A mean path through the box: the middle mean (4, 3) is 1 m inside every
// face, where an end is missed with probability Q(-1 / 0.112) ~ 1, so any
// bound from the means is near 1 and each segment is charged exactly its
// deltas' sum.
TEST(CcRiskCertifier, ASegmentThroughTheBoxIsChargedItsDeltas) {
    const CcProblem p = boxAboveTheWay(2);
    CcPlan plan{};
    plan.steps = p.steps;
    const double x[3] = {0.0, 4.0, 8.0};
    for (std::size_t tau = 0; tau <= p.steps; ++tau) {
        plan.meanX[tau] = x[tau];
        plan.meanY[tau] = 3.0;
    }
    plan.delta[0][0][0] = 2e-3;
    plan.delta[0][0][1] = 3e-3;
    plan.delta[1][0][0] = 1e-3;
    plan.delta[1][0][1] = 4e-4;
    certifier.start();
    std::uint64_t work = 0;
    CHECK_FALSE(certifier.unit(p, &plan, &work));
    CHECK_TRUE(certifier.unit(p, &plan, &work));
    DOUBLES_EQUAL(5e-3, plan.segmentRisk[0], 1e-17);
    DOUBLES_EQUAL(1.4e-3, plan.segmentRisk[1], 1e-17);
    DOUBLES_EQUAL(6.4e-3, plan.riskUsed, 1e-17);
    // Near its obstacle a pair is refined (the segment's own line, face
    // pairs' orthants): more than the 8 tails of a far pair, each segment.
    CHECK(work > 2 * 8 * kTailWork);
}

// A plan's certified risk one segment a unit (cc_risk_certifier.hpp): each
// segment's share is certifiedSegmentRisk's, riskUsed their sum, and each
// unit's tails and orthants are charged.
#include <cmath>

#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_risk_certifier.hpp"
#include "fsw/deliberative/cc_work_units.hpp"
#include "fsw/deliberative/plan_risk.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::boxAboveTheWay;
using rse::test::kBoxBottom;

namespace {

CcRiskCertifier certifier;

}  // namespace

TEST_GROUP(CcRiskCertifier){};

TEST(CcRiskCertifier, OneSegmentAUnitSummedIntoRiskUsed) {
    const CcProblem p = boxAboveTheWay(6);
    CcPlan plan{};
    plan.steps = p.steps;
    for (std::size_t tau = 0; tau <= p.steps; ++tau) {
        plan.meanX[tau] = 8.0 * static_cast<double>(tau) / 6.0;
        plan.meanY[tau] = 0.0;
    }
    for (std::size_t t = 0; t < p.steps; ++t) {
        plan.face[t][0] = kBoxBottom;
        plan.delta[t][0][0] = plan.delta[t][0][1] = 5e-4;
    }
    claimBooleRisk(p, &plan);
    CHECK_FALSE(certifier.running());
    certifier.start();
    CHECK(certifier.running());
    std::uint64_t work = 0;
    std::uint64_t expectedWork = 0;
    double sum = 0.0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        RiskWork w;
        const double segment = certifiedSegmentRisk(p, plan, t, &w);
        expectedWork += kTailWork * w.tails + kOrthantWork * w.orthants + kScoreWork * w.lineSolves;
        sum += segment;
        const bool last = certifier.unit(p, &plan, &work);
        CHECK_EQUAL(t + 1 == p.steps, last);
        DOUBLES_EQUAL(segment, plan.segmentRisk[t], 0.0);
        LONGS_EQUAL(expectedWork, work);
    }
    CHECK_FALSE(certifier.running());
    DOUBLES_EQUAL(sum, plan.riskUsed, 0.0);
    CHECK(plan.riskUsed < 6e-3);  // tighter than the deltas' sum: the box is 2 m away
    DOUBLES_EQUAL(certifiedPlanRisk(p, plan, nullptr, nullptr), plan.riskUsed, 1e-15);
}

// The planner's work budget is hard (issue 15 item 2): every unit of step()
// does at most CcPlanner::kMaxUnitWork work units, so a plan's work() never
// exceeds workBudget x 1000 + kMaxUnitWork, at the table's largest sizes
// (N = kMaxPlanSteps, M = kMaxPlanObstacles, octagons) and with both
// allocations, with the default budget and with budgets that end in every
// phase (seeds, search, allocation).
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "fsw/deliberative/cc_planner.hpp"
#include "unit_test/fsw/deliberative/cc_test_maps.hpp"

#include "CppUTest/TestHarness.h"

using rse::deliberative::CcPlan;
using rse::deliberative::CcPlanner;
using rse::deliberative::CcPlannerParams;
using rse::deliberative::CcProblem;
using rse::deliberative::kMaxObstacleFaces;
using rse::deliberative::kMaxPlanObstacles;
using rse::deliberative::kMaxPlanSteps;
using rse::deliberative::RiskAllocation;
using rse::test::makePolygon;
using rse::test::randomInstance;

namespace {

CcPlanner budgetPlanner;  // static storage, as in flight

// The worst size: N = 24, M = 8 obstacles of 8 faces each (randomInstance's
// scene with every obstacle made an octagon of the same place and size), a
// large sigma so that the margins differ a lot from step to step.
CcProblem worstSize(std::uint64_t seed, double riskBound) {
    CcProblem p = randomInstance(seed, kMaxPlanSteps, kMaxPlanObstacles, riskBound);
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        const auto& o = p.obstacles[i];
        double cx = 0.0, cy = 0.0, r = 0.0;
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            r += o.offset[j];
        }
        // The box's or polygon's centre and mean offset: good enough to place an octagon.
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            cx += o.normalX[j] * o.offset[j];
            cy += o.normalY[j] * o.offset[j];
        }
        cx *= 2.0 / o.faceCount;
        cy *= 2.0 / o.faceCount;
        r = 0.75 + 0.1 * static_cast<double>(i);
        p.obstacles[i] = makePolygon(static_cast<std::uint8_t>(i), cx, cy, r, kMaxObstacleFaces, 0.3 * static_cast<double>(i));
    }
    p.processSigmaM = 0.15;
    return p;
}

// Runs a plan one unit at a time; the largest work of one unit.
std::uint64_t runByUnits(const CcProblem& p, const CcPlannerParams& params) {
    CHECK(budgetPlanner.start(p, params) == rse::core::Status::kOk);
    std::uint64_t worst = 0;
    for (std::uint32_t k = 0; k < 200000 && !budgetPlanner.finished(); ++k) {
        const std::uint64_t before = budgetPlanner.work();
        (void)budgetPlanner.step(1);
        const std::uint64_t used = budgetPlanner.work() - before;
        worst = used > worst ? used : worst;
    }
    CHECK(budgetPlanner.finished());
    return worst;
}

}  // namespace

TEST_GROUP(CcPlannerBudget){};

TEST(CcPlannerBudget, NoUnitExceedsTheUnitBoundAndNoPlanTheBudget) {
    std::uint64_t worstUnit = 0;
    double worstRatio = 0.0;
    std::uint64_t worstOver = 0;  // work beyond the budget
    for (std::uint64_t seed = 0; seed < 4; ++seed) {
        for (int a = 0; a < 2; ++a) {
            CcProblem p = worstSize(4200 + seed, seed % 2 == 0 ? 0.05 : 1e-4);
            p.allocation = a == 0 ? RiskAllocation::kEvenSplit : RiskAllocation::kOptimised;
            for (std::uint32_t budget : {20000U, 3000U, 500U}) {
                CcPlannerParams params;
                params.workBudget = budget;
                const std::uint64_t unit = runByUnits(p, params);
                worstUnit = unit > worstUnit ? unit : worstUnit;
                const double ratio = static_cast<double>(budgetPlanner.work()) / (1000.0 * budget);
                worstRatio = ratio > worstRatio ? ratio : worstRatio;
                std::uint64_t over = budgetPlanner.work() > 1000ULL * budget ? budgetPlanner.work() - 1000ULL * budget : 0U;
                // Whole-plan calls (step(1000)) keep the same bound.
                CcPlan plan;
                (void)budgetPlanner.solve(p, params, &plan);
                const std::uint64_t overSolve =
                    budgetPlanner.work() > 1000ULL * budget ? budgetPlanner.work() - 1000ULL * budget : 0U;
                over = overSolve > over ? overSolve : over;
                worstOver = over > worstOver ? over : worstOver;
            }
        }
    }
    std::printf("\n  CcPlannerBudget: largest unit %llu work units (kMaxUnitWork %llu), worst work / budget %.3f, "
                "largest excess %llu\n",
                static_cast<unsigned long long>(worstUnit), static_cast<unsigned long long>(CcPlanner::kMaxUnitWork),
                worstRatio, static_cast<unsigned long long>(worstOver));
    CHECK(worstUnit <= CcPlanner::kMaxUnitWork);
    CHECK(worstOver <= CcPlanner::kMaxUnitWork);
}

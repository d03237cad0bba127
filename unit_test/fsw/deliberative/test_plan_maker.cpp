// Making the plan of the goal in hand (plan_maker.hpp) with the default
// tables: the problem from the start, the planner sliced within a run's work,
// PLAN_PATH numbered by the plans made, refusals, the re-entry start, the
// failed-drive model and the seed from the last plan.
#include <cmath>

#include "fsw/core/clock.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/plan_maker.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "unit_test/fsw/deliberative/event_record.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::PlanMaker;
using deliberative::PlanStart;
namespace ev = rse::deliberative::events;

namespace {

constexpr int kMaxRuns = 300;

}  // namespace

TEST_GROUP(PlanMaker) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    tables::TableService tables{events};
    test::EventRecord seen{events};
    deliberative::Publisher out{bus, events};
    PlanMaker* maker = nullptr;  // 460 KB: not on the stack
    msg::KnownHazardsMsg hazards{};
    core::PipeId probe = 0;

    void setup() override {
        CHECK(core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount)));
        CHECK(core::isOk(bus.createPipe("probe", 8, &probe)));
        CHECK(core::isOk(bus.subscribe(probe, msg::ids::kPlanPath)));
        maker = new PlanMaker(events, tables, out);
        seen.clear();
    }
    void teardown() override { delete maker; }

    PlanStart request(double x, double y, double gx, double gy, double risk = 1e-3) {
        PlanStart s;
        s.xM = x;
        s.yM = y;
        s.cov[0] = 0.0025;
        s.cov[3] = 0.0025;
        s.goalX = gx;
        s.goalY = gy;
        s.goalNumber = 1;
        s.riskBound = risk;
        s.hazards = &hazards;
        return s;
    }
    // Steps to the end; the runs it took.
    int stepToEnd() {
        int runs = 1;
        while (!maker->step() && runs < kMaxRuns) {
            ++runs;
        }
        CHECK(runs < kMaxRuns);
        return runs;
    }
};

TEST(PlanMaker, APlanIsMadeOverRunsEachWithinTheSliceAndPublishedNumbered) {
    const char* refusal = nullptr;
    CHECK_TRUE(maker->start(request(0.1, 0.0, 20.0, 0.0), &refusal));
    LONGS_EQUAL(1, maker->counters().plansStarted);
    CHECK_TRUE(seen.textHas(ev::kPlanStarted, "plan goal 1 (20.00, 0.00) from (0.10, 0.00), risk 0.001"));
    const int runs = stepToEnd();
    LONGS_EQUAL(runs, static_cast<int>(maker->slices()));
    LONGS_EQUAL(runs, static_cast<int>(maker->counters().planningRuns));
    CHECK(maker->counters().maxRunWork <= deliberative::kSliceWork + deliberative::CcPlanner::kMaxUnitWork);
    CHECK(maker->counters().maxRunUnits <= deliberative::kMaxUnitsPerRun);
    CHECK_TRUE(maker->finish());
    CHECK(maker->plan().riskUsed <= 1e-3 * (1.0 + 1e-9));
    maker->countPlanFound(5 * core::kNsPerSec);
    maker->reportPlanFound(4);
    LONGS_EQUAL(1, maker->counters().plansFound);
    CHECK(maker->planGap() >= 0.0 && maker->planGap() <= 1.0);
    CHECK_TRUE(seen.textHas(ev::kPlanFound, "4 legs"));
    core::Message m;
    msg::PlanPathMsg path{};
    CHECK(core::isOk(bus.receive(probe, &m)));
    CHECK(core::isOk(m.decode(&path)));
    LONGS_EQUAL(1, path.planNumber);
    LONGS_EQUAL(maker->plan().steps, path.steps);
    DOUBLES_EQUAL(20.0, path.goalX, 0.0);
    DOUBLES_EQUAL(0.0025, path.startCov[0], 0.0);
    DOUBLES_EQUAL(maker->plan().meanX[path.steps], path.meanX[path.steps], 0.0);
    // A new goal list: "no plan" until the next.
    maker->forgetPlan();
    CHECK(deliberative::CcStatus::kNoPlan == maker->plan().status);
    DOUBLES_EQUAL(1.0, maker->planGap(), 0.0);
}

TEST(PlanMaker, AGoalInsideAnObstacleIsRefusedWithTheReason) {
    const char* refusal = nullptr;
    CHECK_FALSE(maker->start(request(0.1, 0.0, 5.7, 2.5), &refusal));
    CHECK(refusal != nullptr);
    STRCMP_EQUAL(toString(deliberative::MapProblemError::kGoalInObstacle), refusal);
    LONGS_EQUAL(1, maker->counters().problemsRefused);
    LONGS_EQUAL(0, maker->counters().plansStarted);
    CHECK_TRUE(seen.textHas(ev::kProblemRefused, "goal 1 (5.70, 2.50) from (0.10, 0.00)"));
}

TEST(PlanMaker, AStartOffTheSiteIsPlannedFromTheNearestPointInsideIt) {
    const char* refusal = nullptr;
    CHECK_TRUE(maker->start(request(-6.0, 0.0, 3.0, 0.0), &refusal));
    CHECK_TRUE(maker->fromReentry());
    LONGS_EQUAL(1, maker->counters().reentryPlans);
    LONGS_EQUAL(1, seen.count(ev::kPlannedFromReentry));
    CHECK(maker->problem().startX > -5.0);
    CHECK_TRUE(maker->start(request(0.0, 0.0, 3.0, 0.0), &refusal));
    CHECK_FALSE(maker->fromReentry());
}

TEST(PlanMaker, ConfirmedFailedDrivesArePlannedWithMoreNoiseAndTheChangeIsEvented) {
    const char* refusal = nullptr;
    CHECK_TRUE(maker->start(request(0.1, 0.0, 20.0, 0.0), &refusal));
    const double nominal = maker->problem().processSigmaM;
    LONGS_EQUAL(0, seen.count(ev::kFailedDriveModel));
    PlanStart failed = request(0.1, 0.0, 20.0, 0.0);
    failed.failedDrives = 0x04;
    failed.meanPowerFactor = 1.33;
    CHECK_TRUE(maker->start(failed, &refusal));
    const double factor = static_cast<double>(tables.planner().failed_drive_noise_factor);
    DOUBLES_EQUAL(nominal * factor, maker->problem().processSigmaM, 1e-9);
    LONGS_EQUAL(1, maker->counters().failedDriveModels);
    CHECK_TRUE(seen.textHas(ev::kFailedDriveModel, "drive estimate: RL failed: plans at power factor 1.33"));
    CHECK_TRUE(maker->start(failed, &refusal));  // the same set: no event
    LONGS_EQUAL(1, seen.count(ev::kFailedDriveModel));
    CHECK_TRUE(maker->start(request(0.1, 0.0, 20.0, 0.0), &refusal));
    LONGS_EQUAL(2, seen.count(ev::kFailedDriveModel));
    CHECK_TRUE(seen.textHas(ev::kFailedDriveModel, "every drive back"));
}

TEST(PlanMaker, ThePlanToTheSameGoalAmongTheSameObstaclesIsSeededWithTheLastPlan) {
    const char* refusal = nullptr;
    CHECK_TRUE(maker->start(request(0.1, 0.0, 20.0, 0.0), &refusal));
    (void)stepToEnd();
    CHECK_TRUE(maker->finish());
    LONGS_EQUAL(0, maker->counters().seededPlans);
    CHECK_TRUE(maker->start(request(0.1, 0.0, 20.0, 0.0, 1e-4), &refusal));
    LONGS_EQUAL(1, maker->counters().seededPlans);
    // Another goal: no seed.
    CHECK_TRUE(maker->start(request(0.1, 0.0, 12.0, 0.0), &refusal));
    LONGS_EQUAL(1, maker->counters().seededPlans);
}

TEST(PlanMaker, TheWideSearchRunsOnceAPlanAndOnlyAmongObstacles) {
    const char* refusal = nullptr;
    CHECK_TRUE(maker->start(request(0.1, 0.0, 20.0, 0.0), &refusal));
    (void)stepToEnd();
    (void)maker->finish();
    CHECK_TRUE(maker->startWideSearch());
    LONGS_EQUAL(1, maker->counters().wideSearches);
    CHECK_TRUE(seen.textHas(ev::kWideSearch, "search x8, certify at 0.001"));
    CHECK_FALSE(maker->startWideSearch());
    maker->reportNoPlan(3);
    LONGS_EQUAL(1, maker->counters().noPlans);
    CHECK_TRUE(seen.textHas(ev::kNoPlan, "no plan for goal 3 within risk 0.001"));
    // A new plan may search wide again.
    CHECK_TRUE(maker->start(request(0.1, 0.0, 20.0, 0.0), &refusal));
    CHECK_TRUE(maker->startWideSearch());
}

// What the habitual task says on the bus (fsw/habitual/habitual_outputs.hpp):
// stops, plans and back-outs each with a new trajectory id, the leg report
// (the fail-up's reason and excess only in kFailedUp), the one-off answer to a
// refused leg, and the known hazards when they changed.
#include "fsw/core/clock.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/habitual/habitual_outputs.hpp"
#include "unit_test/fsw/habitual/habitual_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using habitual::HabitualOutputs;
using msg::HabitualState;
using msg::LegConstraint;

TEST_GROUP(HabitualOutputs) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    tables::HabitualTable table = test::defaultTable<tables::HabitualTable>();
    HabitualOutputs outputs{bus, table};
    core::PipeId probe = 0;
    core::Message inbox{};

    void setup() override {
        CHECK(core::Status::kOk == bus.createPipe("probe", 8, &probe));
        CHECK(core::Status::kOk == bus.subscribe(probe, msg::ids::kTrajectory));
        CHECK(core::Status::kOk == bus.subscribe(probe, msg::ids::kLegReport));
        CHECK(core::Status::kOk == bus.subscribe(probe, msg::ids::kKnownHazards));
    }
    template <typename M>
    M received() {
        M m{};
        CHECK(core::isOk(bus.receive(probe, &inbox)));
        CHECK(core::isOk(inbox.decode(&m)));
        return m;
    }
    bool nothingMore() { return !core::isOk(bus.receive(probe, &inbox)); }
};

TEST(HabitualOutputs, EveryTrajectoryHasANewIdTheLegAndForAPlanTheCruiseSpeed) {
    outputs.sendStop(3, 100);
    msg::TrajectoryMsg t = received<msg::TrajectoryMsg>();
    LONGS_EQUAL(1, t.trajectoryId);
    LONGS_EQUAL(3, t.legId);
    LONGS_EQUAL(0, t.count);
    LONGS_EQUAL(100, t.timeNs);
    DOUBLES_EQUAL(0.0, t.speedMS, 0.0);
    const Point2 path[] = {{0.0, 0.0}, {4.0, 1.0}, {8.0, 0.0}};
    outputs.sendPath(3, path, 3, 200);
    t = received<msg::TrajectoryMsg>();
    LONGS_EQUAL(2, t.trajectoryId);
    LONGS_EQUAL(3, t.count);
    DOUBLES_EQUAL(4.0, t.points[1].xM, 0.0);
    DOUBLES_EQUAL(static_cast<double>(table.cruise_speed_m_s), t.speedMS, 0.0);
    CHECK_FALSE(outputs.escaping());
    LONGS_EQUAL(2, outputs.trajectory().trajectoryId);
    LONGS_EQUAL(1, outputs.counters().stopsSent);
    LONGS_EQUAL(1, outputs.counters().plansSent);
    CHECK_TRUE(nothingMore());
}

TEST(HabitualOutputs, ABackOutIsAnEscapeUntilTheNextTrajectory) {
    outputs.sendEscape(5, Point2{19.0, -6.0}, Point2{18.2, -6.0}, 300);
    const msg::TrajectoryMsg t = received<msg::TrajectoryMsg>();
    LONGS_EQUAL(2, t.count);
    DOUBLES_EQUAL(19.0, t.points[0].xM, 0.0);
    DOUBLES_EQUAL(18.2, t.points[1].xM, 0.0);
    DOUBLES_EQUAL(static_cast<double>(table.cruise_speed_m_s), t.speedMS, 0.0);
    CHECK_TRUE(outputs.escaping());
    LONGS_EQUAL(0, outputs.counters().plansSent);  // not a plan
    outputs.escapeEnded();
    CHECK_FALSE(outputs.escaping());
    outputs.sendEscape(5, Point2{19.0, -6.0}, Point2{18.2, -6.0}, 300);
    outputs.sendStop(5, 400);
    CHECK_FALSE(outputs.escaping());
}

TEST(HabitualOutputs, TheReportCarriesTheFiguresAndTheFailUpOnlyWhenFailedUp) {
    const habitual::Evaluation figures{12.0, 700.0, 18.0, 800.0, LegConstraint::kNone, 0.0, -0.2, 15.0, 40.0};
    const habitual::ReportCounts counts{2, 1, 4, 3};
    outputs.setFailUp(LegConstraint::kEnergy, 25.0);
    outputs.publishReport(500, 6, HabitualState::kDriving, figures, counts);
    msg::LegReportMsg r = received<msg::LegReportMsg>();
    LONGS_EQUAL(6, r.legId);
    CHECK(HabitualState::kDriving == r.state);
    CHECK(LegConstraint::kNone == r.violated);
    DOUBLES_EQUAL(0.0, r.excess, 0.0);
    DOUBLES_EQUAL(12.0, r.predictedLengthM, 0.0);
    DOUBLES_EQUAL(18.0, r.allowedLengthM, 0.0);
    DOUBLES_EQUAL(700.0, r.predictedEnergyJ, 0.0);
    DOUBLES_EQUAL(800.0, r.allowedEnergyJ, 0.0);
    DOUBLES_EQUAL(15.0, r.predictedPowerW, 0.0);
    DOUBLES_EQUAL(40.0, r.allowedPowerW, 0.0);
    LONGS_EQUAL(2, r.legsAchieved);
    LONGS_EQUAL(1, r.failUps);
    LONGS_EQUAL(4, r.replans);
    LONGS_EQUAL(3, r.minorAnomalies);
    outputs.publishReport(600, 6, HabitualState::kFailedUp, figures, counts);
    r = received<msg::LegReportMsg>();
    CHECK(LegConstraint::kEnergy == r.violated);
    DOUBLES_EQUAL(25.0, r.excess, 0.0);
    outputs.clearFailUp();
    outputs.publishReport(700, 6, HabitualState::kFailedUp, figures, counts);
    r = received<msg::LegReportMsg>();
    CHECK(LegConstraint::kNone == r.violated);
    LONGS_EQUAL(700, outputs.latestReport().timeNs);
}

TEST(HabitualOutputs, ARefusedLegIsAnsweredOnceAsIdleAndBadLeg) {
    outputs.publishRefusal(800, 9, habitual::ReportCounts{1, 0, 0, 0});
    const msg::LegReportMsg r = received<msg::LegReportMsg>();
    LONGS_EQUAL(9, r.legId);
    CHECK(HabitualState::kIdle == r.state);
    CHECK(LegConstraint::kBadLeg == r.violated);
    LONGS_EQUAL(1, r.legsAchieved);
    DOUBLES_EQUAL(0.0, r.allowedLengthM, 0.0);
    LONGS_EQUAL(9, outputs.latestReport().legId);
}

TEST(HabitualOutputs, KnownHazardsArePublishedAndTheRevisionKept) {
    const tables::CoarseMapTable coarse = test::defaultTable<tables::CoarseMapTable>();
    habitual::HazardMemory memory{events, coarse};
    CHECK_FALSE(outputs.hazardsChanged(memory));
    msg::HazardMsg h{};
    h.count = 1;
    h.sightings[0] = test::sighting(7, 1.6, 0.0, 0.4);
    memory.remember(h, Point2{18.0, -6.0}, 0.0);
    CHECK_TRUE(outputs.hazardsChanged(memory));
    outputs.publishHazards(900, memory);
    const msg::KnownHazardsMsg k = received<msg::KnownHazardsMsg>();
    LONGS_EQUAL(1, k.count);
    LONGS_EQUAL(memory.revision(), k.revision);
    CHECK_FALSE(outputs.hazardsChanged(memory));
    LONGS_EQUAL(1, outputs.counters().hazardMapsSent);
}

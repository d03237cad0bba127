// The events the habitual task's state machine raises about its legs
// (fsw/habitual/leg_events.hpp): ids, severities, the texts people read, the
// numbers the ground decides on (event data, by name), and the throttled ones.
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/habitual/leg_events.hpp"
#include "unit_test/fsw/habitual/habitual_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using habitual::Evaluation;
using habitual::LegEvents;
using msg::LegConstraint;
namespace ev = habitual::events;
namespace evd = cmdtlm::event_data;

// Each RSE_EVENT_DATA of the habitual layer's events names that event's flight constant.
template <typename Layout>
constexpr bool isTheEvent(core::EventId id) {
    return Layout::kFirstId == id && Layout::kLastId == id;
}
static_assert(isTheEvent<evd::PATH_BLOCKED>(ev::kPathBlocked), "804");
static_assert(isTheEvent<evd::MINOR_ANOMALY>(ev::kMinorAnomaly), "805");
static_assert(isTheEvent<evd::HABITUAL_FAIL_UP>(ev::kFailUp), "807");
static_assert(isTheEvent<evd::LEG_ACHIEVED>(ev::kLegAchieved), "808");
static_assert(isTheEvent<evd::HAZARD_REMEMBERED>(ev::kHazardRemembered), "816");

namespace {

msg::LegCommandMsg leg() {
    msg::LegCommandMsg l{};
    l.legId = 3;
    l.goalXM = 12.5;
    l.goalYM = -1.25;
    l.maxPathLengthM = 14.2;
    l.maxEnergyJ = 16123.0;
    return l;
}

// lengthM, energyJ, allowedLengthM, allowedEnergyJ, violated, excess, score, powerW, allowedPowerW
const Evaluation kFigures{10.04, 9400.4, 12.78, 12898.4, LegConstraint::kNone, 0.0, -0.2, 18.0, 16.0};

}  // namespace

TEST_GROUP(LegEvents) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    test::EventReader seen{events};
    LegEvents say{events};

    const char* only(core::EventId id) {
        seen.take();
        LONGS_EQUAL(1, seen.count(id));
        return seen.text(id);
    }
};

TEST(LegEvents, ALegTakenSaysWhereAndItsBounds) {
    say.accepted(leg(), 0.0);
    STRCMP_EQUAL("habitual: leg 3 to (12.50, -1.25): max 14.2 m, 16123 J", only(ev::kLegAccepted));
    say.accepted(leg(), 3.0);
    STRCMP_EQUAL("habitual: leg 3 to (12.50, -1.25) within 3.00 m: max 14.2 m, 16123 J", only(ev::kLegAccepted));
    CHECK(core::Severity::kInfo == seen.severity(ev::kLegAccepted));
}

TEST(LegEvents, RefusalsAndPoseWaitsAreThrottled) {
    for (std::uint32_t n = 1; n <= 5; ++n) {
        say.refused(9, "leg id not new", n);
        say.poseNotReady(3, n);
    }
    seen.take();
    LONGS_EQUAL(3, seen.count(ev::kLegRefused));  // 1st, 2nd, 4th
    STRCMP_EQUAL("habitual: leg 9 refused: leg id not new (4 so far)", seen.text(ev::kLegRefused));
    LONGS_EQUAL(3, seen.count(ev::kPoseNotReady));
    STRCMP_EQUAL("habitual: leg 3 waits: no fresh initialised pose (4 runs so far)", seen.text(ev::kPoseNotReady));
}

TEST(LegEvents, StopsOfTheLegSayWhetherTheRoverWasMoving) {
    say.cancelled(3, true);
    STRCMP_EQUAL("habitual: leg 3 cancelled: rover stopped", only(ev::kLegCancelled));
    say.cancelled(3, false);
    STRCMP_EQUAL("habitual: leg 3 cancelled: nothing under way", only(ev::kLegCancelled));
    say.leftAutonomous(1, 3, false);
    STRCMP_EQUAL("habitual: left AUTONOMOUS (mode 1): leg 3 dropped, rover already stopped",
                 only(ev::kLeftAutonomous));
    say.held(0x5, 3, true);
    STRCMP_EQUAL("habitual: mission held (reasons 0x5): rover stopped, leg 3 kept", only(ev::kMissionHeld));
    CHECK(core::Severity::kWarning == seen.severity(ev::kMissionHeld));
    say.released(2, 3, true);
    STRCMP_EQUAL("habitual: hold released (resume 2): leg 3 waits for the re-sent leg", only(ev::kMissionReleased));
    say.released(2, 3, false);
    STRCMP_EQUAL("habitual: hold released (resume 2): leg 3 goes on", only(ev::kMissionReleased));
}

TEST(LegEvents, AchievementSaysWhereAndWhatWasDriven) {
    say.achieved(leg(), Point2{12.4, -1.3}, 13.04, 15012.4);
    STRCMP_EQUAL("habitual: leg 3 achieved at (12.40, -1.30): 13.0 m, 15012 J driven", only(ev::kLegAchieved));
    evd::LEG_ACHIEVED achieved;
    CHECK_TRUE(seen.data(ev::kLegAchieved, &achieved));
    DOUBLES_EQUAL(3.0, achieved.leg_id, 0.0);
    DOUBLES_EQUAL(12.4, achieved.x, 0.0);
    DOUBLES_EQUAL(-1.3, achieved.y, 0.0);
    DOUBLES_EQUAL(13.04, achieved.driven_length, 0.0);
    DOUBLES_EQUAL(15012.4, achieved.driven_energy, 0.0);
    say.achievedInside(leg(), Point2{11.0, -1.0}, 2.5);
    STRCMP_EQUAL("habitual: leg 3 achieved at (11.00, -1.00): already within 2.50 m of (12.50, -1.25)",
                 only(ev::kLegAchieved));
    CHECK_TRUE(seen.data(ev::kLegAchieved, &achieved));
    DOUBLES_EQUAL(11.0, achieved.x, 0.0);
    DOUBLES_EQUAL(0.0, achieved.driven_length, 0.0);  // nothing driven

}

TEST(LegEvents, PlansRepairsAndBackOuts) {
    say.planSent(3, 12, 4, kFigures, false);
    STRCMP_EQUAL("habitual: leg 3 trajectory 12: 4 pts, 10.0/12.8 m, 9400/12898 J", only(ev::kPlanSent));
    say.planSent(3, 12, 4, kFigures, true);
    STRCMP_EQUAL("habitual: leg 3 trajectory 12: 4 pts, 10.0/12.8 m, 9400/12898 J, margin cut", only(ev::kPlanSent));
    say.minorAnomaly(3, habitual::PlanTrigger::kPathBlocked, 0);
    STRCMP_EQUAL("habitual: leg 3 replanned (path blocked, run 0): constraints hold: minor anomaly",
                 only(ev::kMinorAnomaly));
    evd::MINOR_ANOMALY replanned;
    CHECK_TRUE(seen.data(ev::kMinorAnomaly, &replanned));
    DOUBLES_EQUAL(3.0, replanned.leg_id, 0.0);
    DOUBLES_EQUAL(static_cast<double>(habitual::PlanTrigger::kPathBlocked), replanned.trigger, 0.0);
    DOUBLES_EQUAL(0.0, replanned.run, 0.0);
    Evaluation over = kFigures;
    over.violated = LegConstraint::kPathLength;
    over.excess = 0.56;
    say.repair(3, 5, over, 1, 2);
    STRCMP_EQUAL("habitual: leg 3: plan 10.0 m 9400 J violates path length by 0.6: repair 1 of 2",
                 only(ev::kRepairAttempt));
    say.repair(3, 0, Evaluation{}, 2, 2);
    STRCMP_EQUAL("habitual: leg 3: no path found: repair 2 of 2", only(ev::kRepairAttempt));
    say.energyRepair(3, kFigures, 242.4, 2);
    STRCMP_EQUAL("habitual: leg 3: remaining path 10.0 m 9400 J violates energy by 242: repair 1 of 2",
                 only(ev::kRepairAttempt));
    say.escape(3, false, Point2{19.0, -6.0}, Point2{18.0, -6.0}, 1);
    STRCMP_EQUAL("habitual: leg 3: in a hazard disc at (19.00, -6.00): out 1.00 m to (18.00, -6.00) (1 of 3)",
                 only(ev::kEscape));
    say.escape(3, true, Point2{-6.0, 0.0}, Point2{-4.1, 0.0}, 2);
    STRCMP_EQUAL("habitual: leg 3: off the site at (-6.00, 0.00): out 1.90 m to (-4.10, 0.00) (2 of 3)",
                 only(ev::kEscape));
}

TEST(LegEvents, AFailUpGivesTheFiguresOfItsReason) {
    Evaluation e = kFigures;
    e.lengthM = 14.0;
    e.excess = 1.22;
    say.failUp(leg(), LegConstraint::kPathLength, e, 3, 1.0);
    STRCMP_EQUAL("habitual: leg 3 fail-up: path length 14.0 m > allowed 12.8 m by 1.2 m", only(ev::kFailUp));
    CHECK(core::Severity::kError == seen.severity(ev::kFailUp));
    e = kFigures;
    e.energyJ = 13140.6;
    e.excess = 242.2;
    say.failUp(leg(), LegConstraint::kEnergy, e, 3, 1.0);
    STRCMP_EQUAL("habitual: leg 3 fail-up: energy 13141 J > allowed 12898 J by 242 J", only(ev::kFailUp));
    say.failUp(leg(), LegConstraint::kNoPath, kFigures, 3, 1.0);
    STRCMP_EQUAL("habitual: leg 3 fail-up: no path to (12.50, -1.25) in 3 planning runs", only(ev::kFailUp));
    e = kFigures;
    e.excess = 2.0;
    say.failUp(leg(), LegConstraint::kPower, e, 1, 1.2);
    STRCMP_EQUAL("habitual: leg 3 fail-up: power 18.0 W > allowed 16.0 W by 2.0 W (power factor 1.200)",
                 only(ev::kFailUp));
    evd::HABITUAL_FAIL_UP failUp;
    CHECK_TRUE(seen.data(ev::kFailUp, &failUp));
    DOUBLES_EQUAL(3.0, failUp.leg_id, 0.0);
    DOUBLES_EQUAL(static_cast<double>(LegConstraint::kPower), failUp.constraint, 0.0);
    DOUBLES_EQUAL(18.0, failUp.predicted, 0.0);
    DOUBLES_EQUAL(16.0, failUp.allowed, 0.0);
    DOUBLES_EQUAL(2.0, failUp.excess, 0.0);
    DOUBLES_EQUAL(1.2, failUp.power_factor, 0.0);
    say.failUp(leg(), LegConstraint::kNoPath, kFigures, 3, 1.0);
    (void)only(ev::kFailUp);
    CHECK_TRUE(seen.data(ev::kFailUp, &failUp));
    DOUBLES_EQUAL(static_cast<double>(LegConstraint::kNoPath), failUp.constraint, 0.0);
    DOUBLES_EQUAL(3.0, failUp.planning_runs, 0.0);  // a count, apart from the bound figures
    DOUBLES_EQUAL(0.0, failUp.predicted, 0.0);
    say.failUp(leg(), LegConstraint::kCannotFollow, kFigures, 1, 1.0);
    STRCMP_EQUAL("habitual: leg 3 fail-up: cannot follow", only(ev::kFailUp));
    CHECK_TRUE(seen.data(ev::kFailUp, &failUp));
    DOUBLES_EQUAL(static_cast<double>(LegConstraint::kCannotFollow), failUp.constraint, 0.0);
    DOUBLES_EQUAL(0.0, failUp.predicted, 0.0);
}

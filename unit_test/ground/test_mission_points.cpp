// The ten-point tracker (ground/mission_points.hpp) on hand-made event
// streams in the flight software's own wording with the events' numbers (event
// data), and the report and map writers (ground/mission_report.hpp) on a
// hand-made record: each point's evidence, the order judged from the times, a
// hidden obstacle told from a known rock by the coarse map, a fail-up that
// spoils point 5, the call-home reason taken from the plan status, every point
// in the files; and that the points come from the numbers, not the words: a
// reworded stream gives the same points, a stream without its numbers none.
#include <cmath>
#include <string>
#include <vector>

#include "fsw/msg/deliberative_msgs.hpp"
#include "ground/mission_points.hpp"
#include "ground/mission_report.hpp"
#include "unit_test/ground/mission_stream_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using ground::FlightEvent;
using ground::TenPointTracker;
using test::kDemo;
using test::oneRock;
using test::Step;
namespace data = test::data;

namespace {

void feed(TenPointTracker* t, const std::vector<Step>& steps) {
    for (const Step& s : steps) {
        if (s.id == 912) {
            t->onCallHomeReason(static_cast<std::uint8_t>(msg::CallHomeReason::kNoPlanWithinRisk));
        }
        t->onPose(s.t, s.t / 5.0, 0.0);
        t->onEvent(FlightEvent{s.t, s.id, 1, s.text, s.data});
    }
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_GROUP(TenPointTracker) {
    TenPointTracker* t = nullptr;
    void setup() override { t = new TenPointTracker(oneRock()); }
    void teardown() override { delete t; }
};

TEST(TenPointTracker, TheDemoStreamShowsEveryPointOnceInOrderWithItsFigures) {
    feed(t, kDemo);
    CHECK_TRUE(t->allInOrder());
    STRCMP_EQUAL("ten points: all in order", t->verdict().c_str());
    const double expected[10] = {0.39, 1.47, 1.55, 17.27, 69.55, 80.45, 81.75, 103.45, 103.47, 104.68};
    const std::vector<ground::MissionPoint> fresh = t->takeNew();
    LONGS_EQUAL(10, fresh.size());
    for (int n = 1; n <= 10; ++n) {
        const ground::MissionPoint& p = t->points()[static_cast<std::size_t>(n - 1)];
        CHECK_TRUE(p.seen);
        DOUBLES_EQUAL(expected[n - 1], p.timeS, 1e-9);
        LONGS_EQUAL(n, fresh[static_cast<std::size_t>(n - 1)].number);
        CHECK_TRUE(p.hasPlace);
    }
    LONGS_EQUAL(0, t->takeNew().size());  // each point once
    DOUBLES_EQUAL(1e-3, t->fact(1, "risk bound"), 0.0);
    DOUBLES_EQUAL(308.0, t->fact(2, "power bound W"), 0.0);
    DOUBLES_EQUAL(3.0, t->fact(5, "hazard"), 0.0);
    DOUBLES_EQUAL(0.0, t->fact(5, "fail-ups"), 0.0);
    DOUBLES_EQUAL(308.0, t->fact(7, "power bound before W"), 0.0);
    DOUBLES_EQUAL(324.0, t->fact(7, "power bound after W"), 0.0);
    DOUBLES_EQUAL(1.0, t->fact(10, "call home reason"), 0.0);
    // Placed where they happened: 5 where the rover replanned.
    DOUBLES_EQUAL(45.75 / 5.0, t->points()[4].xM, 1e-9);
    CHECK_TRUE(contains(t->points()[5].what, "ML nominal -> degraded"));
    CHECK_TRUE(contains(t->points()[9].what, "no plan within the risk limit"));
    CHECK_FALSE(contains(t->points()[9].what, "goa"));  // the cut-off goal counts are left out
    STRCMP_EQUAL("[    17.270] POINT 4 habitual + deliberative: leg 1 reached (1 of 6); next issued: leg 2 to (14.33, -0.38)",
                 TenPointTracker::formatPoint(t->points()[3]).c_str());
}

// Seen while the leg was being planned (before its first trajectory): no
// "path blocked", the leg's plan goes round it; on the leg's way it counts,
// beside it not.
TEST(TenPointTracker, AHiddenObstacleSeenWhileItsLegIsPlannedOnItsWayCounts) {
    std::vector<Step> steps(kDemo.begin(), kDemo.begin() + 5);  // leg 1 achieved
    steps.push_back({17.27, 906, "deliberative: leg 1 reached (1 of 6)", data::legReached(1, 1, 6)});
    steps.push_back({17.27, 905, "deliberative: leg 2 (2 of 6) to (14.33, -0.38): <= 12.83 m, <= 15856 J, <= 308 W, risk 4.59e-06",
                     data::legSent(2, 2, 6, 14.33, -0.38, 12.83, 15856, 308)});
    steps.push_back({18.0, 816, "habitual: hazard 3 seen at (6.0, -0.10), radius 0.38 m: on the map",
                     data::hazardSeen(3, 6.0, -0.10, 0.38)});
    steps.push_back({18.5, 803, "habitual: leg 2 trajectory 4: 7 pts, 5.8/9.2 m, 7781/10739 J", {}});
    steps.push_back({40.0, 808, "habitual: leg 2 achieved at (14.2, -0.3): 10.9 m, 10000 J driven",
                     data::legAchieved(2, 14.2, -0.3, 10.9, 10000)});
    for (const Step& st : steps) {
        t->onPose(st.t, st.t < 17.3 ? st.t / 5.0 : 3.73, st.t < 17.3 ? 0.0 : -0.28);
        t->onEvent(FlightEvent{st.t, st.id, 1, st.text, st.data});
    }
    CHECK_TRUE(t->points()[4].seen);
    DOUBLES_EQUAL(40.0, t->points()[4].timeS, 0.0);
    DOUBLES_EQUAL(1.0, t->fact(5, "while planning"), 0.0);
    CHECK_TRUE(contains(t->points()[4].what, "while leg 2 was being planned; planned round it"));

    // The same leg with the rock 3 m off its way: not point 5.
    TenPointTracker beside(oneRock());
    steps[7] = {18.0, 816, "habitual: hazard 3 seen at (6.0, -3.40), radius 0.38 m: on the map",
                data::hazardSeen(3, 6.0, -3.40, 0.38)};
    for (const Step& st : steps) {
        beside.onPose(st.t, st.t < 17.3 ? st.t / 5.0 : 3.73, st.t < 17.3 ? 0.0 : -0.28);
        beside.onEvent(FlightEvent{st.t, st.id, 1, st.text, st.data});
    }
    CHECK_FALSE(beside.points()[4].seen);
}

// The vcan mission's form: the hidden rock seen while the leg before was
// driven, lying on the next leg's way; that leg's plan goes round it.
TEST(TenPointTracker, AHiddenObstacleSeenBeforeItsLegWasSentOnItsWayCounts) {
    std::vector<Step> steps(kDemo.begin(), kDemo.begin() + 5);  // leg 1 achieved at (3.73, -0.28)
    steps.push_back({17.27, 906, "deliberative: leg 1 reached (1 of 6)", data::legReached(1, 1, 6)});
    steps.push_back({17.27, 905, "deliberative: leg 2 (2 of 6) to (8.0, -0.28): <= 6.0 m, <= 8000 J, <= 308 W, risk 1e-06",
                     data::legSent(2, 2, 6, 8.0, -0.28, 6.0, 8000, 308)});
    steps.push_back({17.5, 803, "habitual: leg 2 trajectory 4: 2 pts, 4.3/6.0 m, 4000/8000 J", {}});
    steps.push_back({30.0, 816, "habitual: hazard 3 seen at (10.0, -0.20), radius 0.38 m: on the map",
                     data::hazardSeen(3, 10.0, -0.20, 0.38)});
    steps.push_back({35.0, 808, "habitual: leg 2 achieved at (7.9, -0.28): 4.2 m, 3900 J driven",
                     data::legAchieved(2, 7.9, -0.28, 4.2, 3900)});
    steps.push_back({35.02, 906, "deliberative: leg 2 reached (2 of 6)", data::legReached(2, 2, 6)});
    steps.push_back({35.02, 905, "deliberative: leg 3 (3 of 6) to (13.0, -0.28): <= 6.0 m, <= 8000 J, <= 308 W, risk 1e-06",
                     data::legSent(3, 3, 6, 13.0, -0.28, 6.0, 8000, 308)});
    steps.push_back({35.5, 803, "habitual: leg 3 trajectory 6: 8 pts, 5.7/6.0 m, 7000/8000 J", {}});
    steps.push_back({60.0, 808, "habitual: leg 3 achieved at (12.9, -0.2): 5.7 m, 7000 J driven",
                     data::legAchieved(3, 12.9, -0.2, 5.7, 7000)});
    auto run = [&](TenPointTracker* tracker) {
        for (const Step& st : steps) {
            tracker->onPose(st.t, st.t < 17.3 ? st.t / 5.0 : (st.t < 35.1 ? 7.9 : 12.9), -0.28);
            tracker->onEvent(FlightEvent{st.t, st.id, 1, st.text, st.data});
        }
    };
    run(t);
    CHECK_TRUE(t->points()[4].seen);
    DOUBLES_EQUAL(60.0, t->points()[4].timeS, 0.0);
    DOUBLES_EQUAL(3.0, t->fact(5, "leg"), 0.0);
    CHECK_TRUE(contains(t->points()[4].what, "before leg 3 was sent; planned round it"));

    // A fail-up on that leg spoils it.
    TenPointTracker failed(oneRock());
    steps.insert(steps.end() - 1, Step{40.0, 807, "habitual: leg 3 fail-up: cannot follow",
                                       data::failUp(3, msg::LegConstraint::kCannotFollow)});
    run(&failed);
    CHECK_FALSE(failed.points()[4].seen);
}

// A long leg replanned round the hidden rock may end in the worn motor's
// power fail-up (point 6) before it is achieved: the detour held, point 5
// ends there. Any other fail-up of the leg still spoils it.
TEST(TenPointTracker, APowerFailUpOfTheWornMotorEndsTheDetourLegAsPointFive) {
    std::vector<Step> steps(kDemo.begin(), kDemo.begin() + 11);  // leg 2 replanned round hazard 3 (805)
    steps.push_back({79.39, 761, "drive_modes: ML nominal -> degraded (p=0.997, power x1.13)",
                     data::driveMode(1, 0, 1, 0.997, 1.13)});
    steps.push_back({80.45, 807, "habitual: leg 2 fail-up: power 247.0 W > allowed 246.8 W by 0.3 W (power factor 1.051)",
                     data::failUp(2, msg::LegConstraint::kPower, 247.0, 246.8, 1.051)});
    feed(t, steps);
    CHECK_TRUE(t->points()[4].seen);
    DOUBLES_EQUAL(80.45, t->points()[4].timeS, 0.0);
    CHECK_TRUE(contains(t->points()[4].what, "driven on round it with no fail-up until a worn motor broke"));
    CHECK_TRUE(t->points()[5].seen);  // the same fail-up is point 6's

    TenPointTracker energy(oneRock());
    steps.back() = {80.45, 807, "habitual: leg 2 fail-up: energy 9167 J > allowed 8000 J by 1167 J",
                    data::failUp(2, msg::LegConstraint::kEnergy, 9167, 8000)};
    feed(&energy, steps);
    CHECK_FALSE(energy.points()[4].seen);
}

// The rock grows round the leg's end: the deliberative layer merges the leg
// into the next (919); the merged leg's plan goes round it and is achieved.
TEST(TenPointTracker, AHiddenObstacleLegMergedIntoTheNextCarriesItsDetourOn) {
    std::vector<Step> steps(kDemo.begin(), kDemo.begin() + 11);
    steps.push_back({50.0, 919, "deliberative: leg end (14.33, -0.38) too near a rock: merged into leg 3 of 6 (to (17.62, -0.47))", {}});
    steps.push_back({50.0, 905, "deliberative: leg 3 (3 of 6) to (17.62, -0.47): <= 19.78 m, <= 25208 J, <= 308 W, risk 4.86e-06",
                     data::legSent(3, 3, 6, 17.62, -0.47, 19.78, 25208, 308)});
    steps.push_back({50.3, 803, "habitual: leg 3 trajectory 13: 7 pts, 9.9/22.4 m, 10962/24074 J", {}});
    steps.push_back({75.0, 808, "habitual: leg 3 achieved at (17.5, -0.45): 9.9 m, 10962 J driven",
                     data::legAchieved(3, 17.5, -0.45, 9.9, 10962)});
    feed(t, steps);
    CHECK_TRUE(t->points()[4].seen);
    DOUBLES_EQUAL(75.0, t->points()[4].timeS, 0.0);
    DOUBLES_EQUAL(3.0, t->fact(5, "leg"), 0.0);
    CHECK_TRUE(contains(t->points()[4].what, "leg 2 replanned locally within its bounds at 45.75 s"));
    CHECK_TRUE(contains(t->points()[4].what, "merged into leg 3, planned round it at 50.30 s"));

    // Without the merge event the new leg is the deliberative layer stepping in: not point 5.
    TenPointTracker stepped(oneRock());
    steps.erase(steps.begin() + 11);
    feed(&stepped, steps);
    CHECK_FALSE(stepped.points()[4].seen);
}

TEST(TenPointTracker, AKnownRockSeenByTheDetectorIsNoHiddenObstacle) {
    std::vector<Step> steps(kDemo.begin(), kDemo.begin() + 7);
    // A disc that reaches rock 0 of the coarse map: the map's rock, seen.
    steps.push_back({30.0, 804, "habitual: leg 2: hazard 1 at (5.75, 1.20) r 0.80 m on the path: stop, replan",
                     data::pathBlocked(2, 1, 5.75, 1.20, 0.80)});
    steps.push_back({31.0, 803, "habitual: leg 2 trajectory 5: 4 pts, 7.0/11.4 m, 7638/12593 J", {}});
    steps.push_back({31.0, 805, "habitual: leg 2 replanned (path blocked, run 0): constraints hold: minor anomaly",
                     data::minorAnomaly(2, 1, 0)});
    steps.push_back({60.0, 808, "habitual: leg 2 achieved at (14.35, -0.25): 7.9 m, 10781 J driven",
                     data::legAchieved(2, 14.35, -0.25, 7.9, 10781)});
    feed(t, steps);
    CHECK_FALSE(t->points()[4].seen);
}

TEST(TenPointTracker, AFailUpAfterTheHiddenObstacleSpoilsPointFive) {
    std::vector<Step> steps(kDemo.begin(), kDemo.begin() + 9);  // up to the hidden rock on the path
    steps.push_back({46.0, 807, "habitual: leg 2 fail-up: energy 9167 J > allowed 3897 J by 5270 J",
                     data::failUp(2, msg::LegConstraint::kEnergy, 9167, 3897)});
    steps.push_back({46.1, 905, "deliberative: leg 3 (2 of 6) to (14.33, -0.38): <= 12.83 m, <= 20000 J, <= 308 W, risk 4.59e-06",
                     data::legSent(3, 2, 6, 14.33, -0.38, 12.83, 20000, 308)});
    steps.push_back({47.0, 803, "habitual: leg 3 trajectory 12: 7 pts, 5.8/9.7 m, 8056/10994 J", {}});
    steps.push_back({70.0, 808, "habitual: leg 3 achieved at (14.35, -0.25): 7.9 m, 10781 J driven",
                     data::legAchieved(3, 14.35, -0.25, 7.9, 10781)});
    feed(t, steps);
    CHECK_FALSE(t->points()[4].seen);
    CHECK_FALSE(t->allInOrder());
    CHECK_TRUE(contains(t->verdict(), "missing 5, 6, 7, 8, 9, 10"));
    ground::MissionRecord r;
    t->fill(&r);
    bool told = false;
    for (const ground::MissionDecision& d : r.decisions) {
        told = told || (d.kind == "hidden obstacle" && contains(d.text, "failed up"));
    }
    CHECK_TRUE(told);
}

TEST(TenPointTracker, PointsThatComeOutOfOrderAreSaidToBe) {
    // The call home first (risk), then the rest: 10 comes before 1.
    std::vector<Step> steps;
    steps.push_back({0.2, 912, "deliberative: CALL HOME: no plan within the risk limit (no plan at the relaxed risk limit), goa",
                     data::callHome(msg::CallHomeReason::kNoPlanWithinRisk, 0, 0.001)});
    steps.push_back({0.21, 215, "app: onboard call home (reason 1): mode AUTONOMOUS -> SAFE",
                     data::safed(msg::CallHomeReason::kNoPlanWithinRisk, 2)});
    steps.insert(steps.end(), kDemo.begin(), kDemo.end() - 2);
    feed(t, steps);
    CHECK_FALSE(t->allInOrder());
    const std::string v = t->verdict();
    CHECK_TRUE(contains(v, "ten points: NOT all in order"));
    CHECK_TRUE(contains(v, "out of order"));
    CHECK_FALSE(contains(v, "missing"));
}

TEST(TenPointTracker, ACallHomeForAnotherReasonIsNotPointTen) {
    std::vector<Step> steps(kDemo.begin(), kDemo.end() - 2);
    t->onCallHomeReason(static_cast<std::uint8_t>(msg::CallHomeReason::kMobilityLost));
    for (const Step& s : steps) {
        t->onEvent(FlightEvent{s.t, s.id, 1, s.text, s.data});
    }
    t->onCallHomeReason(static_cast<std::uint8_t>(msg::CallHomeReason::kMobilityLost));
    t->onEvent(FlightEvent{104.67, 912, 4, "deliberative: CALL HOME: mobility lost (the drive interlock holds every drive), goal 0",
                           data::callHome(msg::CallHomeReason::kMobilityLost, 0, 0.001)});
    t->onEvent(FlightEvent{104.68, 215, 2, "app: onboard call home (reason 5): mode AUTONOMOUS -> SAFE",
                           data::safed(msg::CallHomeReason::kMobilityLost, 2)});
    CHECK_FALSE(t->points()[9].seen);
    DOUBLES_EQUAL(5.0, t->fact(10, "call home reason"), 0.0);
    CHECK_TRUE(contains(t->verdict(), "missing 10"));
}

// On a downlink PLAN is routine telemetry: its call-home reason can come down
// after both the call home's and the safing's events. Point 10 then comes
// with the reason, at the time the rover was safed.
TEST(TenPointTracker, PointTenWaitsForTheReasonWhenItComesAfterTheEvents) {
    t->onCallHomeReason(0);
    for (const Step& s : kDemo) {
        t->onPose(s.t, s.t / 5.0, 0.0);
        t->onEvent(FlightEvent{s.t, s.id, 1, s.text, s.data});
    }
    CHECK_FALSE(t->points()[9].seen);
    (void)t->takeNew();
    t->onCallHomeReason(static_cast<std::uint8_t>(msg::CallHomeReason::kNoPlanWithinRisk));
    CHECK_TRUE(t->points()[9].seen);
    DOUBLES_EQUAL(104.68, t->points()[9].timeS, 1e-9);
    CHECK_TRUE(contains(t->points()[9].what, "CALL HOME, operator called: no plan within the risk limit"));
    LONGS_EQUAL(1, t->takeNew().size());
    CHECK_TRUE(t->allInOrder());
}

TEST(TenPointTracker, TheCallHomeWordsDropTheGoalCountsWholeOrCut) {
    STRCMP_EQUAL("mobility lost (x)",
                 ground::callHomeWords("deliberative: CALL HOME: mobility lost (x), goal 0, risk bound 0.001: rover").c_str());
    STRCMP_EQUAL("no plan within the risk limit (no plan at the relaxed risk limit)",
                 ground::callHomeWords("deliberative: CALL HOME: no plan within the risk limit (no plan at the relaxed "
                                       "risk limit), goa")
                     .c_str());
    STRCMP_EQUAL("fault unrecovered", ground::callHomeWords("fault protection: CALL HOME: fault unrecovered").c_str());
}

// The points are read from the events' numbers, never their words: the demo
// stream reworded (every text other words, the same numbers) shows the same
// points at the same times and places with the same figures, the same legs
// and hazards; only the quoted words differ.
TEST(TenPointTracker, ARewordedStreamGivesTheSamePointsLegsAndHazards) {
    std::vector<Step> reworded = kDemo;
    std::vector<std::string> words;
    words.reserve(reworded.size());
    for (std::size_t i = 0; i < reworded.size(); ++i) {
        words.push_back("layer: said otherwise, #" + std::to_string(i));
    }
    for (std::size_t i = 0; i < reworded.size(); ++i) {
        reworded[i].text = words[i].c_str();
    }
    TenPointTracker other(oneRock());
    feed(t, kDemo);
    feed(&other, reworded);
    STRCMP_EQUAL(t->verdict().c_str(), other.verdict().c_str());
    for (std::size_t i = 0; i < ground::kMissionPointCount; ++i) {
        const ground::MissionPoint& a = t->points()[i];
        const ground::MissionPoint& b = other.points()[i];
        CHECK_EQUAL(a.seen, b.seen);
        DOUBLES_EQUAL(a.timeS, b.timeS, 0.0);
        DOUBLES_EQUAL(a.xM, b.xM, 0.0);
        DOUBLES_EQUAL(a.yM, b.yM, 0.0);
        CHECK_TRUE(a.facts == b.facts);
        CHECK_TRUE(a.what != b.what);  // the words are quoted, so they differ
    }
    ground::MissionRecord ra, rb;
    t->fill(&ra);
    other.fill(&rb);
    LONGS_EQUAL(ra.legs.size(), rb.legs.size());
    for (std::size_t i = 0; i < ra.legs.size(); ++i) {
        LONGS_EQUAL(ra.legs[i].legId, rb.legs[i].legId);
        DOUBLES_EQUAL(ra.legs[i].powerBoundW, rb.legs[i].powerBoundW, 0.0);
        DOUBLES_EQUAL(ra.legs[i].drivenM, rb.legs[i].drivenM, 0.0);
        STRCMP_EQUAL(ra.legs[i].outcome.c_str(), rb.legs[i].outcome.c_str());
    }
    LONGS_EQUAL(ra.hazards.size(), rb.hazards.size());
    for (std::size_t i = 0; i < ra.hazards.size(); ++i) {
        LONGS_EQUAL(ra.hazards[i].id, rb.hazards[i].id);
        CHECK_EQUAL(ra.hazards[i].hidden, rb.hazards[i].hidden);
    }
    LONGS_EQUAL(ra.decisions.size(), rb.decisions.size());
}

// Numbers lost on the way (an EVENT whose EVENT_DATA never came) are not
// guessed from the words: the points that need them are missing; the ones
// that need only the events' ids and order (3: a plan sent; 10: the call home,
// the safing and PLAN's reason) are still seen.
TEST(TenPointTracker, WithoutTheirNumbersTheEventsShowOnlyThePointsThatNeedNone) {
    std::vector<Step> bare = kDemo;
    for (Step& s : bare) {
        s.data = core::EventData{};
    }
    feed(t, bare);
    for (int n : {1, 2, 4, 5, 6, 7, 8, 9}) {
        CHECK_FALSE_TEXT(t->points()[static_cast<std::size_t>(n - 1)].seen, ("point " + std::to_string(n)).c_str());
    }
    CHECK_TRUE(t->points()[2].seen);
    CHECK_TRUE(t->points()[9].seen);
    ground::MissionRecord r;
    t->fill(&r);
    CHECK_TRUE(r.legs.empty());     // a leg is known by its numbers
    CHECK_TRUE(r.hazards.empty());
    CHECK_FALSE(r.decisions.empty());  // the words are still quoted in the decisions list
}

// An event's numbers are read by its own id's layout only, and only when all
// of them came; values beyond the layout's (a newer flight appends) are left.
TEST_GROUP(FlightEventNumbers){};

TEST(FlightEventNumbers, AreReadByTheEventsOwnLayoutOnlyAndOnlyWhole) {
    const FlightEvent sentEvent{1.0, 905, 1, "x", data::legSent(7, 2, 6, 14.33, -0.38, 12.83, 15856, 308)};
    cmdtlm::event_data::LEG_SENT sent;
    CHECK_TRUE(sentEvent.read(&sent));
    DOUBLES_EQUAL(7.0, sent.leg_id, 0.0);
    DOUBLES_EQUAL(14.33, sent.x, 0.0);
    DOUBLES_EQUAL(308.0, sent.power_bound, 0.0);
    cmdtlm::event_data::GOALS_COMMANDED goals;
    CHECK_FALSE(sentEvent.read(&goals));  // 905 is not GOALS_COMMANDED's event
    FlightEvent cut = sentEvent;
    cut.data.count = 5;
    CHECK_FALSE(cut.read(&sent));
    FlightEvent longer{1.0, 208, 1, "x", data::goals(1, 0.001)};
    longer.data.count = 3;  // a value more than the layout has
    CHECK_TRUE(longer.read(&goals));
    DOUBLES_EQUAL(0.001, goals.risk_bound, 0.0);
    const FlightEvent bare{1.0, 208, 1, "app: 1 goal(s), risk bound 0.001", {}};
    CHECK_FALSE(bare.read(&goals));
}

TEST_GROUP(MissionReport){};

TEST(MissionReport, TheReportAndTheMapCarryEveryPointTheLegsThePlansAndTheTracks) {
    TenPointTracker t(oneRock());
    feed(&t, kDemo);
    ground::MissionRecord r;
    t.fill(&r);
    r.scenario = "demo";
    r.goalX = 20.0;
    r.riskBound = 1e-3;
    r.map = oneRock();
    r.outcome = "called home at 104.7 s";
    r.hiddenRocks.push_back({{12.5, -0.5}, {13.0, -0.5}, {13.0, 0.0}, {12.5, 0.0}});
    r.truthTrack = {{0.0, 0.0, 0.0}, {50.0, 10.0, 0.1}, {100.0, 18.5, -0.3}};
    r.estimatedTrack = {{1.0, 0.1, 0.0}, {50.0, 10.05, 0.12}};
    ground::PlanDrawing plan;
    plan.timeS = 1.47;
    plan.problem.steps = 2;
    plan.problem.processSigmaM = 0.05;
    plan.problem.riskBound = 1e-3;
    plan.plan.status = deliberative::CcStatus::kOptimal;
    plan.plan.steps = 2;
    const double xs[3] = {0.0, 10.0, 20.0};
    for (int k = 0; k < 3; ++k) {
        plan.plan.meanX[k] = xs[k];
        plan.plan.meanY[k] = 0.0;
    }
    r.plans.push_back(plan);
    r.timing.push_back(ground::TaskTimingRow{"deliberative", 1067, 0, 5000.0, 0.0, 0.0, 5.2, 2544.4});
    const std::string report = ground::renderMissionReport(r, "map.svg");
    const std::string map = ground::renderMissionMap(r);
    CHECK_TRUE(contains(report, "**ten points: all in order**"));
    for (int n = 1; n <= 10; ++n) {
        CHECK_TRUE(contains(report, "| " + std::to_string(n) + " | "));
        CHECK_TRUE(contains(map, "id=\"point-" + std::to_string(n) + "\""));
    }
    CHECK_TRUE(contains(report, "| 3 | 69.57 | (17.62, -0.47) | 6.20 | 7670 | 308 | failed up: power"));
    CHECK_TRUE(contains(report, "| deliberative | 1067 | 5000 |"));
    CHECK_TRUE(contains(report, "power bound relaxed"));
    CHECK_TRUE(contains(map, "class=\"hidden-rock\""));
    CHECK_TRUE(contains(map, "class=\"hazard-hidden\""));
    CHECK_TRUE(contains(map, "class=\"track-truth\""));
    CHECK_TRUE(contains(map, "class=\"track-estimate\""));
    CHECK_TRUE(contains(map, "class=\"mean-path\""));
    CHECK_TRUE(contains(map, "class=\"rock\""));
    // An ellipse per step of the plan, and no number that is not one.
    std::size_t ellipses = 0;
    for (std::size_t at = map.find("class=\"ellipse\""); at != std::string::npos;
         at = map.find("class=\"ellipse\"", at + 1)) {
        ++ellipses;
    }
    LONGS_EQUAL(3, ellipses);
    CHECK_FALSE(contains(map, "nan"));
    CHECK_FALSE(contains(map, "inf"));
}

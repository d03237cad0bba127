// The scenario suite (issue 17): every scenario file in sim_stub/scenarios/
// that is a mission of its own ([mission]: a goal, or a plan, at a risk
// bound) is flown as `rse-demo --scenario FILE` flies it (the runner loads
// the file, uplinks its COARSE_MAP, SET_MODE AUTONOMOUS, then its GOTO or its
// plan) and its expected outcome, written in the file's header comment, is
// asserted here: other maps, a narrow passage, a hidden rock whose detour does
// not fit, fault timings, risk bounds from 10^-1 to 10^-6, low batteries, a
// node crash with and without its restart, and the two-targets grinder failure
// through the plan executive. The figures asserted are the flight software's
// (its counters, events and plan status, read by the runner) and the
// simulator's truth (position, contact, the driven track); the ten points are
// read by the mission's tracker (ground/mission_points.hpp).
//
// The aarch64 build can plan an equally good but different route (the last
// bits of libm): the assertions are on what the scenario is about, not on a
// particular route or time. RSE_PRINT_CONSOLE=1 prints each mission's console.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "fsw/msg/health_msgs.hpp"
#include "sim_stub/lockstep/mission_runner.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::MissionOptions;
using sim::MissionOutcome;
using sim::MissionSummary;
using msg::CallHomeReason;

namespace {

constexpr const char* kDir = "sim_stub/scenarios/";
constexpr std::uint8_t kSafe = 0;  // cmdtlm::Mode::kSafe

bool printConsole() { return std::getenv("RSE_PRINT_CONSOLE") != nullptr; }

// `rse-demo --quiet --scenario sim_stub/scenarios/NAME.toml [extra...]`.
MissionSummary fly(const char* name, std::vector<const char*> extra = {}) {
    const std::string path = std::string(kDir) + name + ".toml";
    std::vector<const char*> argv = {"rse-demo", "--quiet", "--scenario", path.c_str()};
    argv.insert(argv.end(), extra.begin(), extra.end());
    MissionOptions o;
    std::string error;
    if (sim::parseMissionArgs(static_cast<int>(argv.size()), argv.data(), &o, &error) != sim::ParseOutcome::kRun) {
        std::printf("\n%s: bad options: %s\n", name, error.c_str());
        return MissionSummary{};
    }
    o.quiet = !printConsole();
    return sim::runMission(o, printConsole() ? stdout : nullptr);
}

// One line a mission, for the log and for a failing check.
std::string line(const char* name, const MissionSummary& s) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "%s: %s at %.1f s (%s), %.2f m from (%.2f, %.2f), driven %.1f m, %u collisions, least clearance "
                  "%.2f m; %u fail-ups, %u replans, %u bound / %u risk relaxations; fault protection %u/%u/%u "
                  "(started/recovered/gave up); %.2f s wall",
                  name, sim::toString(s.outcome), s.outcomeTimeS, s.callHomeText.c_str(), s.goalDistanceM, s.goalX,
                  s.goalY, s.distanceM, static_cast<unsigned>(s.collisions), s.leastClearanceM,
                  static_cast<unsigned>(s.failUps), static_cast<unsigned>(s.replans),
                  static_cast<unsigned>(s.boundRelaxations), static_cast<unsigned>(s.riskRelaxations),
                  static_cast<unsigned>(s.responsesStarted), static_cast<unsigned>(s.responsesRecovered),
                  static_cast<unsigned>(s.responsesGaveUp), s.wallTimeS);
    return text;
}

void report(const char* name, const MissionSummary& s) { std::printf("\n  %s", line(name, s).c_str()); }

// Reached, at the goal, without contact (the runner's goal: the scenario's).
void checkReached(const char* name, const MissionSummary& s) {
    CHECK_TEXT(s.outcome == MissionOutcome::kGoalReached, line(name, s).c_str());
    CHECK_TEXT(s.goalDistanceM < 0.6, line(name, s).c_str());
    LONGS_EQUAL(0, s.collisions);
    LONGS_EQUAL(0, s.callHomes);
    CHECK(s.distanceM >= std::hypot(s.finalX - s.record.truthTrack.front().xM,
                                    s.finalY - s.record.truthTrack.front().yM) - 1e-9);
}

// Called home for `reason`, safed, without contact.
void checkCalledHome(const char* name, const MissionSummary& s, CallHomeReason reason) {
    CHECK_TEXT(s.outcome == MissionOutcome::kCalledHome, line(name, s).c_str());
    LONGS_EQUAL(static_cast<int>(reason), static_cast<int>(s.callHome));
    LONGS_EQUAL(kSafe, s.finalMode);
    LONGS_EQUAL(0, s.collisions);
}

const ground::MissionPoint& point(const MissionSummary& s, int n) {
    return s.record.points[static_cast<std::size_t>(n - 1)];
}

bool contains(const std::string& text, const char* what) { return text.find(what) != std::string::npos; }

// Where a track crosses the vertical line x (interpolated between the points
// either side of it); empty when it does not.
std::vector<double> crossingsOf(const std::vector<ground::TrackPoint>& track, double x) {
    std::vector<double> ys;
    for (std::size_t i = 1; i < track.size(); ++i) {
        const ground::TrackPoint& a = track[i - 1];
        const ground::TrackPoint& b = track[i];
        if ((a.xM - x) * (b.xM - x) <= 0.0 && a.xM != b.xM) {
            ys.push_back(a.yM + (b.yM - a.yM) * (x - a.xM) / (b.xM - a.xM));
        }
    }
    return ys;
}

// A plan's mean path as a track.
std::vector<ground::TrackPoint> meanPath(const ground::PlanDrawing& p) {
    std::vector<ground::TrackPoint> path;
    for (std::size_t t = 0; t <= p.plan.steps; ++t) {
        path.push_back(ground::TrackPoint{0.0, p.plan.meanX[t], p.plan.meanY[t]});
    }
    return path;
}

// The least distance between a polyline and the scenario's known rocks (0
// where it crosses one): a segment's distance to a convex polygon is its
// ends' distance to the polygon or the polygon's vertices' distance to it.
double clearanceToKnownRocks(const std::vector<ground::TrackPoint>& path, const sim::Scenario& scenario) {
    double least = 1e9;
    for (const sim::Obstacle& o : scenario.obstacles) {
        if (!o.known) {
            continue;
        }
        for (std::size_t i = 1; i < path.size(); ++i) {
            const sim::Vec2 a{path[i - 1].xM, path[i - 1].yM};
            const sim::Vec2 b{path[i].xM, path[i].yM};
            if (sim::segmentIntersectsPolygon(a, b, o.shape)) {
                return 0.0;
            }
            least = std::min({least, sim::distanceToPolygon(a, o.shape), sim::distanceToPolygon(b, o.shape)});
            for (std::size_t k = 0; k < o.shape.n; ++k) {
                least = std::min(least, sim::norm(o.shape.v[k] - sim::closestOnSegment(o.shape.v[k], a, b)));
            }
        }
    }
    return least;
}

}  // namespace

TEST_GROUP(ScenarioSuite){};

// ---- Other maps ------------------------------------------------------------

// straight_10m.toml: open ground, GOTO (10, 0): the baseline.
TEST(ScenarioSuite, StraightTenMetresOnOpenGroundIsDrivenInOnePlan) {
    const MissionSummary s = fly("straight_10m");
    report("straight_10m", s);
    checkReached("straight_10m", s);
    DOUBLES_EQUAL(10.0, s.goalX, 0.0);  // the scenario's goal, not the demo's
    LONGS_EQUAL(0, s.record.map.obstacle_count);
    LONGS_EQUAL(1, s.plansMade);
    LONGS_EQUAL(0, s.failUps);
    LONGS_EQUAL(s.legsSent, s.legsAchieved);
    CHECK(s.distanceM < 10.6);
}

// offset_site.toml: a site far from the origin, its own rocks, a goal to the
// north-east of a start facing north.
TEST(ScenarioSuite, AnOffsetSiteIsUplinkedAndCrossedToItsGoal) {
    const MissionSummary s = fly("offset_site");
    report("offset_site", s);
    checkReached("offset_site", s);
    DOUBLES_EQUAL(135.0, s.goalX, 0.0);
    DOUBLES_EQUAL(-50.0, s.goalY, 0.0);
    // The flight software flew the scenario's site: its bounds and five known rocks.
    LONGS_EQUAL(5, s.record.map.obstacle_count);
    DOUBLES_EQUAL(100.0, s.record.map.x_min_m, 0.0);
    DOUBLES_EQUAL(-45.0, s.record.map.y_max_m, 0.0);
    const double straight = std::hypot(135.0 - 104.0, -50.0 + 66.0);
    CHECK(s.planLengthM > straight - 0.2 && s.planLengthM < 1.1 * straight);
    LONGS_EQUAL(0, s.failUps);
    LONGS_EQUAL(0, s.replans);
    LONGS_EQUAL(0, s.responsesStarted);
}

// boulder_field.toml: sixteen known rocks, the COARSE_MAP table full.
TEST(ScenarioSuite, ABoulderFieldOfSixteenRocksIsCrossedWithoutContact) {
    const MissionSummary s = fly("boulder_field");
    report("boulder_field", s);
    checkReached("boulder_field", s);
    LONGS_EQUAL(16, s.record.map.obstacle_count);
    CHECK(!s.record.plans.empty());
    CHECK(s.record.plans.front().problem.obstacleCount <= 8);  // the rocks that matter to the route
    const sim::Scenario scenario = sim::loadScenarioFile(std::string(kDir) + "boulder_field.toml");
    // Half the rocks are left out of the problem; none of them is where the plan goes.
    const double clearance = clearanceToKnownRocks(meanPath(s.record.plans.front()), scenario);
    std::printf("\n  boulder_field: the first plan's mean path %.2f m from the nearest known rock", clearance);
    CHECK(clearance > scenario.rover.radiusM);
    const double straight = std::hypot(30.0, 20.0);
    CHECK(s.planLengthM > straight - 0.2 && s.planLengthM < 1.1 * straight);
    LONGS_EQUAL(0, s.failUps);
    CHECK(s.leastClearanceM > 0.0);
}

// ---- A narrow passage ------------------------------------------------------

// narrow_passage.toml: the only way across is a 1.9 m passage at y 1.0..2.9.
TEST(ScenarioSuite, ANarrowPassageIsThreadedAtItsBoundAndRefusedAtTenToTheMinusSix) {
    const MissionSummary s = fly("narrow_passage");
    report("narrow_passage at 1e-2", s);
    checkReached("narrow_passage", s);
    DOUBLES_EQUAL(1e-2, s.riskBound, 1e-15);
    LONGS_EQUAL(0, s.failUps);
    // The rover crossed the wall line once, inside the passage.
    const std::vector<double> ys = crossingsOf(s.record.truthTrack, 10.0);
    LONGS_EQUAL(1, ys.size());
    CHECK_TEXT(ys[0] > 1.0 && ys[0] < 2.9, std::to_string(ys[0]).c_str());
    const std::vector<double> planned = crossingsOf(meanPath(s.record.plans.front()), 10.0);
    LONGS_EQUAL(1, planned.size());
    CHECK(planned[0] > 1.0 && planned[0] < 2.9);

    // At 10^-6 no plan fits the passage, nor at the bound relaxed tenfold:
    // the operator is called before the rover moves.
    const MissionSummary tight = fly("narrow_passage", {"--goto", "20,0,1e-6"});
    report("narrow_passage at 1e-6", tight);
    checkCalledHome("narrow_passage at 1e-6", tight, CallHomeReason::kNoPlanWithinRisk);
    LONGS_EQUAL(1, tight.riskRelaxations);
    DOUBLES_EQUAL(1e-5, tight.riskInForce, 1e-18);
    LONGS_EQUAL(0, tight.legsSent);
    CHECK(tight.distanceM < 0.1);
}

// ---- Risk bounds from 10^-1 to 10^-6 ---------------------------------------

// risk_gap.toml: a 1.9 m gap on the line, the way round 4 m longer. The first
// plan at each bound (a mission cut at 5 s has made it), the whole mission
// at the two ends.
TEST(ScenarioSuite, AsTheRiskBoundTightensThePlanLeavesTheGapForTheLongerWayRound) {
    const sim::Scenario scenario = sim::loadScenarioFile(std::string(kDir) + "risk_gap.toml");
    const char* const bounds[] = {"1e-1", "1e-2", "1e-3", "1e-4", "1e-5", "1e-6"};
    struct FirstPlan {
        double bound;
        bool through;
        double costM;
        double lengthM;
        double clearanceM;
        deliberative::CcStatus status;
    };
    std::vector<FirstPlan> plans;
    MissionSummary loosest;
    MissionSummary tightest;
    for (const char* bound : bounds) {
        const std::string gotoArg = std::string("20,0,") + bound;
        const bool whole = bound == bounds[0] || bound == bounds[5];
        std::vector<const char*> extra = {"--goto", gotoArg.c_str()};
        if (!whole) {
            extra.push_back("--duration");
            extra.push_back("5");
        }
        const MissionSummary s = fly("risk_gap", extra);
        CHECK_TEXT(!s.record.plans.empty(), line(bound, s).c_str());
        const ground::PlanDrawing& first = s.record.plans.front();
        const std::vector<double> ys = crossingsOf(meanPath(first), 10.0);
        CHECK_TEXT(ys.size() == 1, bound);
        FirstPlan p{std::atof(bound), std::fabs(ys.at(0)) < 0.95, first.plan.cost, first.plan.euclideanLengthM,
                    clearanceToKnownRocks(meanPath(first), scenario), first.plan.status};
        DOUBLES_EQUAL(p.bound, first.problem.riskBound, p.bound * 1e-12);
        CHECK(first.plan.riskUsed <= p.bound);
        std::printf("\n  risk_gap at %s: %s, %s plan, %.2f m (K-gon cost %.2f m), clearance of the mean path %.2f m",
                    bound, p.through ? "through the gap" : "round a wall's end",
                    p.status == deliberative::CcStatus::kOptimal ? "optimal" : "budget", p.lengthM, p.costM,
                    p.clearanceM);
        plans.push_back(p);
        if (bound == bounds[0]) {
            loosest = s;
        } else if (bound == bounds[5]) {
            tightest = s;
        }
    }
    // The loose end through the gap, the tight end round it; once round,
    // never back through.
    CHECK_TRUE(plans.front().through);
    CHECK_FALSE(plans.back().through);
    for (std::size_t i = 1; i < plans.size(); ++i) {
        if (!plans[i - 1].through) {
            CHECK_FALSE(plans[i].through);
        }
    }
    for (std::size_t i = 0; i < plans.size(); ++i) {
        for (std::size_t j = i + 1; j < plans.size(); ++j) {
            // A tighter bound's plan is a plan at the looser one: never
            // cheaper than a proven optimum there (beyond its 0.2 % gap).
            if (plans[i].status == deliberative::CcStatus::kOptimal) {
                CHECK(plans[j].costM >= plans[i].costM / 1.002);
            }
            // Going round is farther from every rock than any way through.
            if (plans[i].through && !plans[j].through) {
                CHECK(plans[j].clearanceM > plans[i].clearanceM);
                CHECK(plans[j].lengthM > plans[i].lengthM + 2.0);
            }
        }
    }
    // The mean path through the gap passes within its half-width of a wall.
    CHECK(plans.front().clearanceM < 0.95);

    // Both ends flown: through the gap at 10^-1, round at 10^-6; no contact.
    report("risk_gap at 1e-1", loosest);
    report("risk_gap at 1e-6", tightest);
    checkReached("risk_gap at 1e-1", loosest);
    checkReached("risk_gap at 1e-6", tightest);
    const std::vector<double> loose = crossingsOf(loosest.record.truthTrack, 10.0);
    const std::vector<double> tight = crossingsOf(tightest.record.truthTrack, 10.0);
    LONGS_EQUAL(1, loose.size());
    LONGS_EQUAL(1, tight.size());
    CHECK(std::fabs(loose[0]) < 0.95);  // between the walls
    CHECK(std::fabs(tight[0]) > 4.95);  // beyond a wall's end
    CHECK(tightest.distanceM > loosest.distanceM + 2.0);
}

// ---- A hidden obstacle whose detour does not fit ---------------------------

// hidden_rock_detour_fails.toml (point 5's other side): a hidden rock whose
// detour does not fit the leg's energy bound fails up to the deliberative
// layer, which relaxes the bound; point 5 is not shown (rse-demo would exit
// 3); the goal is reached without contact.
TEST(ScenarioSuite, AHiddenRockWhoseDetourDoesNotFitFailsUpAndTheBoundIsRelaxed) {
    const MissionSummary s = fly("hidden_rock_detour_fails");
    report("hidden_rock_detour_fails", s);
    const ground::MissionRecord& r = s.record;
    double hiddenSeen = -1.0;
    for (const ground::HazardSeen& h : r.hazards) {
        if (h.hidden && hiddenSeen < 0.0) {
            hiddenSeen = h.timeS;
        }
    }
    CHECK(hiddenSeen > 0.0);
    unsigned energyFailUpsAfter = 0;
    for (const ground::MissionDecision& d : r.decisions) {
        energyFailUpsAfter += d.kind == "fail-up" && d.timeS > hiddenSeen && contains(d.text, "energy") ? 1U : 0U;
    }
    CHECK(energyFailUpsAfter >= 1);
    CHECK(s.failUps >= 1);
    CHECK(s.boundRelaxations >= 1);
    CHECK_FALSE(point(s, 5).seen);
    CHECK_FALSE(s.tenPointsInOrder);
    CHECK_TRUE(contains(r.verdict, "missing 5"));
    checkReached("hidden_rock_detour_fails", s);
}

// ---- Fault timings ---------------------------------------------------------

// motor_fails_early.toml: the motor fails at 10 s on leg 1: points 8, 9, 10.
TEST(ScenarioSuite, AMotorFailingEarlyLeavesNoPlanWithinTheRiskBoundAndTheOperatorIsCalled) {
    const MissionSummary s = fly("motor_fails_early");
    report("motor_fails_early", s);
    checkCalledHome("motor_fails_early", s, CallHomeReason::kNoPlanWithinRisk);
    CHECK_TRUE(s.interlockTripped);
    for (int n = 8; n <= 10; ++n) {
        CHECK_TEXT(point(s, n).seen, std::to_string(n).c_str());
    }
    CHECK(point(s, 8).timeS > 10.0);  // after the failure
    CHECK(point(s, 9).timeS >= point(s, 8).timeS);
    CHECK(point(s, 10).timeS >= point(s, 9).timeS);
    CHECK(s.riskRelaxations >= 1);
    CHECK(s.outcomeTimeS < 40.0);
    CHECK(s.distanceM < 4.0);  // stopped on leg 1
    CHECK_FALSE(point(s, 6).seen);  // no wear first: no power fail-up
}

// motor_wears_early.toml: worn before the turns in place: power fail-up and
// relaxation, then the drive trips in a turn until fault protection gives it up.
TEST(ScenarioSuite, AMotorWornEarlyTripsInTheTurnsUntilItIsGivenUpAndMobilityIsLost) {
    const MissionSummary s = fly("motor_wears_early");
    report("motor_wears_early", s);
    checkCalledHome("motor_wears_early", s, CallHomeReason::kMobilityLost);
    CHECK_TRUE(s.interlockTripped);
    // The power bound broken by the worn motor and relaxed (points 6 and 7).
    CHECK_TRUE(point(s, 6).seen);
    CHECK_TRUE(point(s, 7).seen);
    CHECK(point(s, 6).timeS > 10.0);
    CHECK(s.boundRelaxations >= 1);
    // The worn drive's over-current trips: reset and recovered, then given up.
    const std::uint8_t overcurrent = msg::fault::kDriveOvercurrent + 1;  // the middle-left drive
    CHECK(s.countMarks(sim::MarkKind::kFaultRaised, overcurrent) >= 2);
    CHECK(s.responsesRecovered >= 1);
    LONGS_EQUAL(1, s.responsesGaveUp);
    CHECK_FALSE(point(s, 10).seen);  // not the risk bound: mobility
    CHECK(s.goalDistanceM > 2.0);
}

// motor_wears_late.toml: the same wear after the last turn in place: points
// 6 and 7 and the goal.
TEST(ScenarioSuite, AMotorWornLateFailsUpOnPowerIsRelaxedAndTheGoalReached) {
    const MissionSummary s = fly("motor_wears_late");
    report("motor_wears_late", s);
    checkReached("motor_wears_late", s);
    CHECK_TRUE(point(s, 6).seen);
    CHECK_TRUE(point(s, 7).seen);
    CHECK(point(s, 6).timeS > 79.0);
    CHECK(point(s, 7).timeS >= point(s, 6).timeS);
    const auto& facts = point(s, 7).facts;
    CHECK(facts.at("power bound after W") > facts.at("power bound before W"));
    CHECK(s.failUps >= 1);
    CHECK(s.boundRelaxations >= 1);
    LONGS_EQUAL(0, s.responsesStarted);  // the worn drive never tripped
    for (int n = 8; n <= 10; ++n) {
        CHECK_FALSE(point(s, n).seen);
    }
}

// drive_fault_recovered.toml: EMCY on the front-left drive at 25 s, reset.
TEST(ScenarioSuite, ADriveFaultIsResetWithinASecondAndTheGoalReached) {
    const MissionSummary s = fly("drive_fault_recovered");
    report("drive_fault_recovered", s);
    checkReached("drive_fault_recovered", s);
    LONGS_EQUAL(1, s.responsesStarted);
    LONGS_EQUAL(1, s.responsesRecovered);
    LONGS_EQUAL(0, s.responsesGaveUp);
    const sim::MissionMark* started = s.firstMark(sim::MarkKind::kResponseStarted, 25.0);
    CHECK(started != nullptr);
    LONGS_EQUAL(0, started->wheel);  // front-left
    CHECK(started->timeS < 25.05);
    CHECK(s.firstHoldTimeS >= 25.0 && s.firstHoldTimeS < 25.05);
    CHECK(s.lastResumeTimeS > s.firstHoldTimeS && s.lastResumeTimeS < 26.0);
    LONGS_EQUAL(0, s.marksUnattributed);
}

// ---- A node crash and restart ----------------------------------------------

// drive_crash_restart.toml: node 5 silent from 30 s, booting again at 33 s.
TEST(ScenarioSuite, ADriveNodeThatCrashesAndRebootsIsResetAndTheGoalReached) {
    const MissionSummary s = fly("drive_crash_restart");
    report("drive_crash_restart", s);
    checkReached("drive_crash_restart", s);
    const std::uint8_t lost = msg::fault::kDriveHeartbeatLost + 4;  // middle-right
    const sim::MissionMark* raised = s.firstMark(sim::MarkKind::kFaultRaised, 30.0, lost);
    const sim::MissionMark* reset = s.firstMark(sim::MarkKind::kRecoveryAction, 30.0, lost);
    CHECK(raised != nullptr && reset != nullptr);
    LONGS_EQUAL(720, raised->eventId);
    LONGS_EQUAL(4, raised->wheel);
    CHECK(raised->timeS < 30.5);
    LONGS_EQUAL(931, reset->eventId);  // NMT node reset
    LONGS_EQUAL(4, reset->wheel);
    LONGS_EQUAL(1, s.responsesStarted);
    LONGS_EQUAL(1, s.responsesRecovered);
    LONGS_EQUAL(0, s.responsesGaveUp);
    CHECK(s.lastResumeTimeS > 33.0);  // after the reboot, not before
    LONGS_EQUAL(0, s.marksUnattributed);
}

// drive_crash_no_restart.toml: the same crash for good.
TEST(ScenarioSuite, ADriveNodeThatNeverRebootsIsGivenUpAndMobilityIsLost) {
    const MissionSummary s = fly("drive_crash_no_restart");
    report("drive_crash_no_restart", s);
    checkCalledHome("drive_crash_no_restart", s, CallHomeReason::kMobilityLost);
    const std::uint8_t lost = msg::fault::kDriveHeartbeatLost + 4;
    CHECK(s.countMarks(sim::MarkKind::kRecoveryAction, lost) >= 2);  // node resets tried, all on that drive
    LONGS_EQUAL(s.countMarks(sim::MarkKind::kRecoveryAction, lost), s.recoveryActions);
    LONGS_EQUAL(1, s.responsesGaveUp);
    LONGS_EQUAL(0, s.responsesRecovered);
    CHECK_TRUE(s.interlockTripped);
    CHECK(s.goalDistanceM > 10.0);  // stopped where it was
}

// ---- Low batteries ---------------------------------------------------------

// low_battery_midway.toml: low in a turn mid-mission, held, recharged, on.
TEST(ScenarioSuite, ABatteryLowMidMissionHoldsTheRoverUntilRechargedThenTheGoalIsReached) {
    const MissionSummary s = fly("low_battery_midway");
    report("low_battery_midway", s);
    checkReached("low_battery_midway", s);
    const sim::MissionMark* low = s.firstMark(sim::MarkKind::kFaultRaised, 0.0, msg::fault::kBatteryLow);
    CHECK(low != nullptr);
    LONGS_EQUAL(726, low->eventId);
    CHECK(low->timeS > 20.0);  // mid-mission, not at the start
    LONGS_EQUAL(1, s.countMarks(sim::MarkKind::kFaultRaised, msg::fault::kBatteryLow));
    LONGS_EQUAL(1, s.responsesStarted);
    LONGS_EQUAL(1, s.responsesRecovered);
    LONGS_EQUAL(0, s.responsesGaveUp);
    CHECK(s.lastResumeTimeS - s.firstHoldTimeS > 30.0);  // it waited for the charge
    CHECK(s.outcomeTimeS > s.lastResumeTimeS);
}

// low_battery_too_small.toml: low again within a minute of the recharge.
TEST(ScenarioSuite, ABatteryTooSmallIsLowAgainTooSoonAndFaultProtectionCallsHome) {
    const MissionSummary s = fly("low_battery_too_small");
    report("low_battery_too_small", s);
    checkCalledHome("low_battery_too_small", s, CallHomeReason::kFaultUnrecovered);
    CHECK_TRUE(s.faultProtectionCalledHome);
    CHECK_TRUE(contains(s.callHomeText, "battery low"));
    CHECK_TRUE(contains(s.callHomeText, "back too soon"));
    LONGS_EQUAL(2, s.countMarks(sim::MarkKind::kFaultRaised, msg::fault::kBatteryLow));
    LONGS_EQUAL(1, s.responsesRecovered);
    LONGS_EQUAL(1, s.responsesGaveUp);
    const sim::MissionMark* again = s.firstMark(sim::MarkKind::kFaultRaised, s.lastResumeTimeS, msg::fault::kBatteryLow);
    CHECK(again != nullptr);
    CHECK(again->timeS - s.lastResumeTimeS < 60.0);  // FAULT_PROTECTION.attempt_memory_ms
    CHECK(s.goalDistanceM > 1.0);
}

// ---- The two-targets grinder failure, through the plan executive -----------

// two_targets.toml with its plan: target 1 sampled, the grinder fails, target
// 2 imaged instead; the plan complete, the rover at target 2.
TEST(ScenarioSuite, TwoTargetsThePlanExecutiveImagesTargetTwoWhenTheGrinderFails) {
    const MissionSummary s = fly("two_targets");
    report("two_targets", s);
    CHECK_TEXT(s.outcome == MissionOutcome::kPlanComplete, line("two_targets", s).c_str());
    CHECK_TRUE(s.planMission);
    const msg::PlanExecutiveStatusMsg& p = s.planExec;
    STRCMP_EQUAL("two_targets", p.planName);
    CHECK(p.state == msg::PlanExecutiveState::kComplete);
    DOUBLES_EQUAL(32.5, p.costBefore, 1e-9);
    DOUBLES_EQUAL(37.5, p.cost, 1e-9);
    LONGS_EQUAL(1, p.regenerations);
    CHECK(p.lastRegeneration == msg::PlanRegeneration::kComponentFailed);
    LONGS_EQUAL(1, p.deprecatedCount);
    LONGS_EQUAL(0, p.options[0]);  // science1: sample
    LONGS_EQUAL(1, p.options[1]);  // science2: image
    LONGS_EQUAL(4, p.activitiesCompleted);  // drive1, sample1, drive2, image2
    LONGS_EQUAL(0, p.activitiesFailed);
    LONGS_EQUAL(0, p.operatorCalls);
    // The last drive's goal is target 2, and the rover is there, untouched.
    DOUBLES_EQUAL(20.0, s.goalX, 1e-9);
    DOUBLES_EQUAL(5.0, s.goalY, 1e-9);
    CHECK(s.goalDistanceM < 0.6);
    LONGS_EQUAL(0, s.collisions);
    DOUBLES_EQUAL(1e-3, s.riskBound, 1e-15);  // the scenario's SET_RISK_BOUND
    CHECK(s.outcomeTimeS > 240.0);            // after the grinder failed
}

// ---- The suite covers every mission ------------------------------------------

// Every scenario file loads, and every one with a [mission] has its outcome
// asserted: here, or (named) in the suite that was written for it.
TEST(ScenarioSuite, EveryScenarioWithAMissionHasItsOutcomeAsserted) {
    const char* const here[] = {"straight_10m",      "offset_site",         "boulder_field",
                                "narrow_passage",    "risk_gap",            "hidden_rock_detour_fails",
                                "motor_fails_early", "motor_wears_early",   "motor_wears_late",
                                "drive_fault_recovered", "drive_crash_restart", "drive_crash_no_restart",
                                "low_battery_midway", "low_battery_too_small", "two_targets"};
    const char* const elsewhere[] = {"demo_mission",     // test_mission_demo.cpp: the ten points
                                     "contact_unseen_rock",  // test_lockstep_contact.cpp
                                     "habitual_stall",   // test_lockstep_fault_protection.cpp
                                     "low_battery",      // test_lockstep_fault_protection.cpp
                                     "rock_field_100m",  // test_lockstep_rock_field.cpp
                                     // test_site_file.cpp: rock_field_100m's map, start, mission
                                     // and rocks (to the bit on the host, within 0.1 mm where the
                                     // target's libm draws the field's last bits otherwise), so its flight
                                     "rock_field_100m_site",
                                     "snowdrift"};       // test_lockstep_snowdrift_host.cpp
    std::size_t files = 0;
    std::size_t missions = 0;
    for (const auto& entry : std::filesystem::directory_iterator(kDir)) {
        if (entry.path().extension() != ".toml") {
            continue;
        }
        ++files;
        sim::Scenario s;
        std::string error;
        CHECK_TEXT(sim::tryLoadScenarioFile(entry.path().string(), &s, &error), error.c_str());
        const std::string stem = entry.path().stem().string();
        if (!s.mission.present) {
            continue;
        }
        ++missions;
        bool covered = false;
        for (const char* n : here) {
            covered = covered || stem == n;
        }
        for (const char* n : elsewhere) {
            covered = covered || stem == n;
        }
        CHECK_TEXT(covered, (stem + ": a mission with no asserted outcome").c_str());
        STRCMP_EQUAL(stem.c_str(), s.name.c_str());  // the file is called what the scenario is
    }
    LONGS_EQUAL(sizeof here / sizeof here[0] + sizeof elsewhere / sizeof elsewhere[0], missions);
    CHECK(files > missions);  // the estimator's and the detector's drives are not missions
}

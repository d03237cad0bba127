// Lockstep: the habitual and reflexive layers drive the simulated rover. The
// test stands in for the deliberative layer: it commands AUTONOMOUS mode and the
// e-stop from a ground station (authenticated CCSDS commands, as an operator
// would) and publishes LegCommandMsg on the bus (as the deliberative layer
// will); it reads LegReportMsg and DriveStatusMsg as the flight software
// publishes them, and the simulator's truth only to judge the outcome.
//
// Scenario: sim_stub/scenarios/demo_mission.toml (known rocks 1, 2, 4, 5 are in
// the COARSE_MAP table; rock 3 is hidden on the straight line to the goal). Its
// own faults are replaced by each test's.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "fsw/rover_model/power_model.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/memory_ground.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;
using msg::HabitualState;
using msg::LegConstraint;

namespace {

constexpr double kCruiseSpeedTolerance = 0.05;  // m/s: "driving at cruise speed"
constexpr double kStoppedWheelRadS = 0.05;      // a wheel slower than this has stopped
// docs/habitual.md, "E-stop": every drive reports below kStoppedWheelRadS within
// this time of the frame the ESTOP_SET command is executed in (measured 0.25 s
// from cruise speed; the drives decelerate with a 50 ms lag).
constexpr core::TimeNs kEstopStopTime = 400 * kNsPerMs;

// What the test sees of the flight software each frame (the rig's frame callback).
struct Watch {
    sim::MemoryGround* ground = nullptr;
    core::PipeId pipe = 0;
    core::Message inbox{};
    msg::LegReportMsg report{};
    std::uint32_t reports = 0;
    msg::LegReportMsg firstDriving{};  // the first report of each leg in kDriving
    bool sawDriving = false;
    msg::DriveModesMsg modes{};
    msg::ModeMsg mode{};
    core::TimeNs estopAt = -1;          // frame the e-stop ModeMsg was published in
};
Watch g_watch;

void watchFrame(sim::LockstepRig& rig) {
    g_watch.ground->drainDownlink();
    while (core::isOk(rig.fsw().bus().receive(g_watch.pipe, &g_watch.inbox))) {
        msg::LegReportMsg r{};
        msg::DriveModesMsg m{};
        msg::ModeMsg mode{};
        if (core::isOk(g_watch.inbox.decode(&r))) {
            g_watch.report = r;
            ++g_watch.reports;
            if (r.state == HabitualState::kDriving && !g_watch.sawDriving) {
                g_watch.firstDriving = r;
                g_watch.sawDriving = true;
            }
        } else if (core::isOk(g_watch.inbox.decode(&m))) {
            g_watch.modes = m;
        } else if (core::isOk(g_watch.inbox.decode(&mode))) {
            if (mode.estop != 0 && g_watch.mode.estop == 0) {
                g_watch.estopAt = mode.timeNs;
            }
            g_watch.mode = mode;
        }
    }
}

sim::Scenario demoScenario() {
    sim::Scenario s = sim::loadScenarioFile("sim_stub/scenarios/demo_mission.toml");
    s.faults.clear();
    return s;
}

double distance(double ax, double ay, double bx, double by) { return std::hypot(ax - bx, ay - by); }

struct SecondLegOutcome {
    msg::LegReportMsg report;
    double meanFactor;
    double nominalEnergyJ;  // the second leg's straight path at power factor 1
    double movedM;          // truth displacement after the leg's outcome, over 5 s
    std::uint32_t repairs;
};

}  // namespace

TEST_GROUP(LockstepHabitual) {
    sim::LockstepRig* rig = nullptr;
    sim::MemoryGround* ground = nullptr;

    void start(const sim::Scenario& scenario) {
        rig = new sim::LockstepRig(scenario);
        ground = new sim::MemoryGround;
        CHECK(core::isOk(rig->fsw().addGroundLink(&ground->link())));
        CHECK(core::Status::kOk == rig->init());
        g_watch = Watch{};
        g_watch.ground = ground;
        core::SoftwareBus& bus = rig->fsw().bus();
        CHECK(core::isOk(bus.createPipe("habitual-test", 16, &g_watch.pipe)));
        CHECK(core::isOk(bus.subscribe(g_watch.pipe, msg::ids::kLegReport)));
        CHECK(core::isOk(bus.subscribe(g_watch.pipe, msg::ids::kDriveModes)));
        CHECK(core::isOk(bus.subscribe(g_watch.pipe, msg::ids::kMode)));
        rig->setOnFrame(watchFrame);
        CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 3 * kNsPerSec));
        CHECK_TRUE(ground->setMode(2));  // AUTONOMOUS
        CHECK_TRUE(rig->runUntil([&] { return g_watch.mode.mode == 2; }, kNsPerSec));
    }
    void teardown() override {
        delete rig;
        delete ground;
    }

    void sendLeg(std::uint32_t legId, double x, double y, double maxLengthM, double maxEnergyJ) {
        msg::LegCommandMsg leg{};
        leg.timeNs = rig->clock().now();
        leg.legId = legId;
        leg.finalLeg = 1;
        leg.goalXM = x;
        leg.goalYM = y;
        leg.maxPathLengthM = maxLengthM;
        leg.maxEnergyJ = maxEnergyJ;
        g_watch.sawDriving = false;
        CHECK(core::isOk(rig->fsw().bus().publish(leg)));
    }
    bool legEnded(std::uint32_t legId) const {
        return g_watch.report.legId == legId &&
               (g_watch.report.state == HabitualState::kAchieved || g_watch.report.state == HabitualState::kFailedUp);
    }
    bool allWheelsStopped() const {
        for (const msg::WheelStatus& w : rig->driveStatus().wheels) {
            if (std::fabs(w.velocityRadS) >= kStoppedWheelRadS) {
                return false;
            }
        }
        for (const auto& w : rig->rover().truth().wheels) {
            if (std::fabs(w.speedRadS) >= kStoppedWheelRadS) {
                return false;
            }
        }
        return true;
    }
    SecondLegOutcome secondLeg(double currentFactor) {
        sim::Scenario s = demoScenario();
        if (currentFactor != 1.0) {
            sim::FaultSpec f;
            f.type = sim::FaultType::kMotorDegradation;
            f.at = 0;
            f.wheel = 1;  // middle left
            f.value = currentFactor;
            s.faults.push_back(f);
        }
        start(s);
        // Leg 1: 4 m with loose bounds, for the drive-mode estimator to learn
        // each drive's power factor from its current while driving.
        sendLeg(1, 4.0, 0.0, 10.0, 40000.0);
        CHECK_TRUE(rig->runUntil([&] { return legEnded(1); }, 60 * kNsPerSec));
        CHECK(HabitualState::kAchieved == g_watch.report.state);
        rig->runFor(kNsPerSec);

        // Leg 2: 6 m straight on; the energy bound leaves 4 % over what six
        // nominal drives need after the table's power margin.
        const tables::HabitualTable& table = rig->fsw().tables().habitual();
        const rover_model::PowerModel model = rover_model::powerModelFrom(table);
        const msg::PoseEstimateMsg pose = rig->fsw().poseEstimator().latest();
        const geometry::Point2 path[2] = {{pose.xM, pose.yM}, {10.0, 0.0}};
        SecondLegOutcome out{};
        out.nominalEnergyJ = rover_model::pathEnergyJ(model, path, 2, pose.headingRad, 1.0);
        out.meanFactor =
            rover_model::meanPowerFactor(g_watch.modes, static_cast<double>(table.failed_drive_power_factor));
        const double maxEnergyJ = 1.04 * out.nominalEnergyJ / (1.0 - static_cast<double>(table.power_margin_frac));
        const std::uint32_t repairsBefore = rig->fsw().habitual().counters().repairAttempts;
        sendLeg(2, 10.0, 0.0, 20.0, maxEnergyJ);
        CHECK_TRUE(rig->runUntil(
            [&] {
                return g_watch.report.legId == 2 && (g_watch.report.state == HabitualState::kDriving ||
                                                     g_watch.report.state == HabitualState::kFailedUp);
            },
            10 * kNsPerSec));
        out.report = g_watch.report;
        out.repairs = rig->fsw().habitual().counters().repairAttempts - repairsBefore;
        const double x0 = rig->rover().truth().pose.x;
        const double y0 = rig->rover().truth().pose.y;
        rig->runFor(5 * kNsPerSec);
        out.movedM = distance(rig->rover().truth().pose.x, rig->rover().truth().pose.y, x0, y0);
        std::printf("\n  motor current x%.2f: mean power factor %.3f, leg 2 state %d violated %d, "
                    "predicted %.0f J allowed %.0f J excess %.0f J (nominal %.0f J), repairs %u, moved %.2f m\n",
                    currentFactor, out.meanFactor, static_cast<int>(out.report.state),
                    static_cast<int>(out.report.violated), out.report.predictedEnergyJ, out.report.allowedEnergyJ,
                    out.report.excess, out.nominalEnergyJ, out.repairs, out.movedM);
        return out;
    }

    void printConsoleOnFailure() {
        if (rig != nullptr && !legEnded(g_watch.report.legId)) {
            std::printf("%s\n", rig->consoleText());
        }
    }
};

// Must-show 1a and 3: the hidden rock is only seen by the hazard detector once
// the rover is driving the straight plan; the habitual layer stops, replans
// round it on the local map within the leg's constraints, logs a minor anomaly,
// does not fail up, and arrives. No heap allocation across the whole leg (every
// planning query included).
TEST(LockstepHabitual, AHiddenRockOnThePathIsAvoidedByALocalReplanWithoutFailingUp) {
    start(demoScenario());
    const habitual::HabitualCounters& counters = rig->fsw().habitual().counters();
    const std::uint32_t planningRunsBefore = counters.planningRuns;
    {
        test::AllocationWatch watch;
        sendLeg(1, 15.0, 0.0, 25.0, 40000.0);
        CHECK_TRUE(rig->runUntil([&] { return legEnded(1); }, 150 * kNsPerSec));
        LONGS_EQUAL(0, watch.count());
    }
    const msg::LegReportMsg& r = g_watch.report;
    const sim::TruthRecord& truth = rig->rover().truth();
    std::printf("\n  hidden rock: %.1f s, replans %u, minor anomalies %u, %u planning runs, end (%.2f, %.2f), "
                "driven %.2f m\n",
                static_cast<double>(rig->clock().now()) * 1e-9, r.replans, r.minorAnomalies,
                counters.planningRuns - planningRunsBefore, truth.pose.x, truth.pose.y, truth.distanceM);
    const core::Executive& exec = rig->fsw().executive();
    for (std::size_t i = 0; i < exec.taskCount(); ++i) {
        const char* name = exec.entry(i)->name;
        if (std::strcmp(name, "habitual") == 0 || std::strcmp(name, "follower") == 0) {
            std::printf("  %s: host CPU per run mean %lld us, max %lld us (timing goals: make bench)\n", name,
                        static_cast<long long>(exec.taskStats(i)->hostMean() / 1000),
                        static_cast<long long>(exec.taskStats(i)->hostMax / 1000));
        }
    }
    if (r.state != HabitualState::kAchieved) {
        printConsoleOnFailure();
    }
    CHECK(HabitualState::kAchieved == r.state);
    CHECK(LegConstraint::kNone == r.violated);
    // The first plan was the straight line (the rock was not on the map) ...
    CHECK(g_watch.firstDriving.predictedLengthM < 15.1);
    // ... the rock was seen and planned round, as minor anomalies, never a fail-up.
    CHECK(counters.pathBlocked >= 1);
    CHECK(r.replans >= 1);
    CHECK(r.minorAnomalies >= 1);
    LONGS_EQUAL(0, r.failUps);
    LONGS_EQUAL(0, counters.failUps);
    LONGS_EQUAL(1, r.legsAchieved);
    CHECK(rig->consoleCount("EVT 816 INFO  habitual: hazard 3 seen") >= 1);
    // Truth: no contact with any rock, arrived within the follower's tolerance
    // (plus the estimate's error), and the path stayed within the length bound.
    LONGS_EQUAL(0, truth.collisions);
    CHECK(distance(truth.pose.x, truth.pose.y, 15.0, 0.0) < 0.5);
    CHECK(truth.distanceM < 25.0);
    CHECK(truth.distanceM > 15.0);  // it went round, not through
}


// Must-show 1b: a wheel motor that draws 1.5x the current makes the drives'
// estimated power factors rise; the next leg's energy, predicted with them,
// exceeds its bound, plan repair cannot help (the straight line is already the
// shortest path), so the habitual layer keeps the rover stopped and fails up
// with the constraint and by how much. The same leg without the degraded motor
// is accepted (the control run).
TEST(LockstepHabitual, ADegradedMotorMakesTheEnergyBoundFailUpWithTheReasonAndTheRoverStaysStopped) {
    const SecondLegOutcome out = secondLeg(1.5);
    CHECK(out.meanFactor > 1.05);  // the estimator saw the degraded drive
    CHECK(HabitualState::kFailedUp == out.report.state);
    CHECK(LegConstraint::kEnergy == out.report.violated);
    CHECK(out.report.predictedEnergyJ > out.report.allowedEnergyJ);
    DOUBLES_EQUAL(out.report.predictedEnergyJ - out.report.allowedEnergyJ, out.report.excess, 1.0);
    CHECK(out.report.excess > 0.0);
    LONGS_EQUAL(rig->fsw().tables().habitual().repair_attempts, out.repairs);
    LONGS_EQUAL(1, out.report.failUps);
    CHECK(out.movedM < 0.05);  // stopped, waiting for the deliberative layer
    CHECK(allWheelsStopped());
}

TEST(LockstepHabitual, TheSameLegWithNominalDrivesIsAccepted) {
    const SecondLegOutcome out = secondLeg(1.0);
    CHECK(out.meanFactor < 1.02);
    CHECK(HabitualState::kDriving == out.report.state);
    CHECK(out.report.predictedEnergyJ <= out.report.allowedEnergyJ);
    LONGS_EQUAL(0, out.report.failUps);
    CHECK(out.movedM > 0.5);
}

// Must-show 1c: ESTOP_SET from the ground while the rover drives at cruise
// speed: every drive reports (and truly is) below 0.05 rad/s within the
// documented time, stays there while the follower and habitual layer are told
// the drives are held, and only a new leg after ESTOP_CLEAR moves the rover.
TEST(LockstepHabitual, EStopStopsEveryDriveWithinTheDocumentedTimeAndHoldsThemUntilCleared) {
    start(demoScenario());
    sendLeg(1, 10.0, 0.0, 20.0, 40000.0);
    const double cruise = static_cast<double>(rig->fsw().tables().habitual().cruise_speed_m_s);
    CHECK_TRUE(rig->runUntil([&] { return std::fabs(rig->rover().truth().speedMS - cruise) < kCruiseSpeedTolerance; },
                             10 * kNsPerSec));
    rig->runFor(2 * kNsPerSec);

    CHECK_TRUE(ground->send("ESTOP_SET"));
    CHECK_TRUE(rig->runUntil([&] { return g_watch.estopAt >= 0; }, kNsPerSec));
    CHECK_TRUE(rig->runUntil([&] { return allWheelsStopped(); }, 2 * kNsPerSec));
    const core::TimeNs stopTime = rig->clock().now() - g_watch.estopAt;
    std::printf("\n  e-stop: every drive below %.2f rad/s %.0f ms after the command (bound %.0f ms)\n",
                kStoppedWheelRadS, static_cast<double>(stopTime) * 1e-6, static_cast<double>(kEstopStopTime) * 1e-6);
    CHECK(stopTime <= kEstopStopTime);
    // The flight software times the stop itself (CAN I/O's e-stop watch).
    rig->runFor(100 * kNsPerMs);
    CHECK(rig->fsw().canIo().lastEstopStopTime() > 0);
    CHECK(rig->fsw().canIo().lastEstopStopTime() <= stopTime);
    LONGS_EQUAL(1, rig->consoleCount("EVT 213 INFO  app: e-stop: every wheel below 0.05 rad/s"));
    LONGS_EQUAL(0, rig->fsw().canIo().estopOverruns());

    // Held: nothing moves while the e-stop is set, whatever the layers do.
    const double x0 = rig->rover().truth().pose.x;
    for (int i = 0; i < 300; ++i) {
        rig->runFor(10 * kNsPerMs);
        CHECK_TRUE(allWheelsStopped());
    }
    DOUBLES_EQUAL(x0, rig->rover().truth().pose.x, 0.01);
    CHECK(rig->fsw().follower().counters().gaveUpDrivesHeld >= 1);
    CHECK(HabitualState::kFailedUp == g_watch.report.state);
    CHECK(LegConstraint::kCannotFollow == g_watch.report.violated);

    // Cleared: still at rest until the deliberative layer sends a leg; then it drives.
    CHECK_TRUE(ground->send("ESTOP_CLEAR"));
    CHECK_TRUE(rig->runUntil([&] { return g_watch.mode.estop == 0; }, kNsPerSec));
    rig->runFor(kNsPerSec);
    DOUBLES_EQUAL(x0, rig->rover().truth().pose.x, 0.01);
    sendLeg(2, 10.0, 0.0, 20.0, 40000.0);
    CHECK_TRUE(rig->runUntil([&] { return legEnded(2); }, 60 * kNsPerSec));
    CHECK(HabitualState::kAchieved == g_watch.report.state);
    CHECK(distance(rig->rover().truth().pose.x, rig->rover().truth().pose.y, 10.0, 0.0) < 0.5);
}

// The e-stop watch's other side: a drive that stops answering while the rover
// drives keeps its last reported speed, so the stop cannot be confirmed; once
// FAULT_RESPONSE.estop_stop_time_ms has passed that is reported, once.
TEST(LockstepHabitual, AnEStopWhoseStopCannotBeConfirmedInTheTableTimeIsReportedAsAnOverrun) {
    start(demoScenario());
    sendLeg(1, 10.0, 0.0, 20.0, 40000.0);
    const double cruise = static_cast<double>(rig->fsw().tables().habitual().cruise_speed_m_s);
    CHECK_TRUE(rig->runUntil([&] { return std::fabs(rig->rover().truth().speedMS - cruise) < kCruiseSpeedTolerance; },
                             10 * kNsPerSec));
    rig->rover().crashDrive(4);  // MR: silent from now on, its last speed stays in the drive status
    CHECK_TRUE(ground->send("ESTOP_SET"));
    CHECK_TRUE(rig->runUntil([&] { return g_watch.estopAt >= 0; }, kNsPerSec));
    const core::TimeNs limit =
        static_cast<core::TimeNs>(rig->fsw().tables().faultResponse().estop_stop_time_ms) * kNsPerMs;
    rig->runFor(limit - 50 * kNsPerMs);
    LONGS_EQUAL(0, rig->fsw().canIo().estopOverruns());
    rig->runFor(2 * limit);
    LONGS_EQUAL(1, rig->fsw().canIo().estopOverruns());
    LONGS_EQUAL(1, rig->consoleCount("EVT 214 CRIT  app: e-stop overrun: a wheel still turns"));
    LONGS_EQUAL(0, rig->consoleCount("EVT 213 "));
}

// Lockstep: the plan executive end to end (issue 16, must-show 1 and 2). The
// test is the operator: the two-targets plan (unit_test/fuzz/corpus/plan/
// two_targets.plan) goes up as the ground would send it, PLAN_LOAD chunks then
// PLAN_START with its length and CRC-32, through the authenticated in-memory
// ground link; the executive drives the rover through the deliberative layer
// and works the simulated grinder and camera over CAN. The judgement is on
// what the ground sees: the console's events and the PLAN_EXEC packet.
//
// Scenario: sim_stub/scenarios/two_targets.toml: the demo site, targets 1 at
// (10, 0) and 2 at (20, 5), the grinder failing for good at 240 s, after it
// sampled target 1 and while the rover drives to target 2.
//
// A drive `within 3` of (10, 0): completed inside the region, short of the
// point, sooner than the drive to the point.
//
// Opportunistic science (group LockstepExtension, the grinder healthy):
// PLAN_EXTEND sent while a sample runs, taken (a follow-on to the simulated
// grinder over CAN, the sample completing 60 s later than in the same run
// without it, within its ub) or refused (beyond its ub; past a later
// deadline, the plan then running as if nothing was asked).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "fsw/msg/mode_msgs.hpp"
#include "unit_test/support/alloc_guard.hpp"
#include "unit_test/support/plan_lockstep.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;
using test::readTextFile;

TEST_GROUP(LockstepPlanExecutive) {
    std::unique_ptr<test::PlanLockstep> session;
    sim::LockstepRig* rig = nullptr;
    sim::MemoryGround* ground = nullptr;

    void start(const sim::Scenario& scenario) {
        session = std::make_unique<test::PlanLockstep>(scenario);
        rig = &session->rig();
        ground = &session->ground();
        const char* failed = session->start();
        CHECK_TEXT(failed == nullptr, failed);
    }
    void teardown() override { session.reset(); }
    // PLAN_LOAD in 200-byte chunks (one every 20 ms), then PLAN_START.
    void uplink(const std::string& text, std::uint32_t crcXor = 0) { CHECK_TRUE(session->uplink(text, crcXor)); }
    bool complete() { return session->complete(); }
    ground::DecodedPacket planExec() { return session->planExec(); }
    double field(const char* name, std::size_t i = 0) {
        const auto v = planExec().value(name, i);
        CHECK_TEXT(v.has_value(), name);
        return v.value_or(-1.0);
    }
    void dumpOnFailure(bool ok) {
        if (!ok || std::getenv("PLAN_EXEC_CONSOLE") != nullptr) {
            std::printf("%s\n", rig->consoleText());
        }
    }
};

// Must-show 1: target 1 sampled; the grinder fails; sample(target 2)
// deprecated, the plan regenerated with image(target 2), driven there and
// imaged; the cost before and after in the events and in PLAN_EXEC.
TEST(LockstepPlanExecutive, TwoTargetsTheGrinderFailsAndTarget2IsImagedInstead) {
    start(sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml"));
    const std::string plan = readTextFile("unit_test/fuzz/corpus/plan/two_targets.plan");
    CHECK(plan.size() > 200);
    bool done = false;
    {
        test::AllocationWatch watch;  // uplink, selection, dispatch, regeneration: no heap
        uplink(plan);
        done = rig->runUntil([&] { return complete(); }, 470 * kNsPerSec);
        LONGS_EQUAL(0, watch.count());
    }
    rig->runFor(1100 * kNsPerMs);  // the last PLAN_EXEC downlinked
    dumpOnFailure(done);
    CHECK_TRUE(done);
    LONGS_EQUAL(1, rig->consoleCount("EVT 950 INFO  plan_exec: plan two_targets accepted"));
    LONGS_EQUAL(1, rig->consoleCount("plan_exec: drive drive1 started"));
    LONGS_EQUAL(1, rig->consoleCount("plan_exec: sample sample1 started"));
    LONGS_EQUAL(1, rig->consoleCount("plan_exec: sample sample1 completed"));
    LONGS_EQUAL(1, rig->consoleCount("plan_exec: drive drive2 started"));
    // The drives take under their 60 s lb: early, each end held to its earliest.
    LONGS_EQUAL(1, rig->consoleCount("EVT 958 WARN  plan_exec: drive1 completed early"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 958 WARN  plan_exec: drive2 completed early"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 972 WARN  plan_exec: grinder now failed"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 973 WARN  plan_exec: 1 activity ask a component no longer so (first sample2)"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 962 WARN  plan_exec: two_targets regenerating"));
    LONGS_EQUAL(1, rig->consoleCount(": component failed (sample2), cost before 32.50"));
    LONGS_EQUAL(1, rig->consoleCount("cost 32.50 -> 37.50"));
    LONGS_EQUAL(0, rig->consoleCount("plan_exec: sample sample2 started"));
    LONGS_EQUAL(1, rig->consoleCount("plan_exec: image image2 started"));
    LONGS_EQUAL(1, rig->consoleCount("plan_exec: image image2 completed"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 964 INFO  plan_exec: plan two_targets complete"));
    LONGS_EQUAL(0, rig->consoleCount("EVT 966"));
    // The ground's view.
    CHECK(ground->keptCount() > 0);
    STRCMP_EQUAL("PLAN_EXEC", planExec().name());
    DOUBLES_EQUAL(4.0, field("state"), 0.0);
    DOUBLES_EQUAL(32.5, field("cost_before"), 1e-9);
    DOUBLES_EQUAL(37.5, field("cost"), 1e-9);
    DOUBLES_EQUAL(5.0, field("last_regeneration"), 0.0);  // component failed
    DOUBLES_EQUAL(0.0, field("options", 0), 0.0);          // science1: sample
    DOUBLES_EQUAL(1.0, field("options", 1), 0.0);          // science2: image
    DOUBLES_EQUAL(1.0, field("deprecated"), 0.0);
    DOUBLES_EQUAL(1.0, field("regenerations"), 0.0);
    DOUBLES_EQUAL(4.0, field("completed"), 0.0);
    DOUBLES_EQUAL(2.0, field("early"), 0.0);
    DOUBLES_EQUAL(1.0, field("plans_accepted"), 0.0);
    // The truth: the rover at target 2.
    const sim::Pose2 p = rig->rover().truth().pose;
    std::printf("\n  two targets: complete at %.1f s, rover at (%.2f, %.2f)\n",
                static_cast<double>(rig->clock().now()) / 1e9, p.x, p.y);
}

// The failure of a running activity replaced at once: the grinder fails 5 s
// into sample(target 2), reported by the simulated grinder on CAN (its
// instrument_failure hook, code 0x42: the command aborted, every later one
// refused). The sequence: the grinder's failure report on the flight bus;
// the executive sees the grinder failed (972) and the sample failed (960);
// regeneration begun (962, activity failed) and done (963, cost 32.50 ->
// 37.50); then image(target 2), the replacement, started (956) and sent to
// the camera (InstrumentCommandMsg on the bus, target 2), imaged within its
// window from the rover's arrival, and the plan complete. No timing is
// asserted here: bench_plan_executive measures the frames.
TEST(LockstepPlanExecutive, ARunningSampleWhoseGrinderFailsIsReplacedByTheImage) {
    sim::Scenario s = sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml");
    s.faults.clear();
    start(s);
    CHECK_TRUE(session->uplink(readTextFile("unit_test/fuzz/corpus/plan/two_targets.plan")));
    const msg::Instrument grinder = msg::Instrument::kGrinder;
    const msg::Instrument camera = msg::Instrument::kCamera;
    // sample2 on the grinder: the executive's command for target 2.
    const bool sampling = rig->runUntil(
        [&] {
            const msg::InstrumentCommandMsg& c = rig->instrumentCommand(grinder);
            return c.action == msg::InstrumentAction::kSample && c.targetId == 2;
        },
        400 * kNsPerSec);
    dumpOnFailure(sampling);
    CHECK_TRUE(sampling);
    rig->runFor(5 * kNsPerSec);
    CHECK(rig->instrumentStatus(grinder).state == msg::InstrumentState::kBusy);  // still grinding
    const std::uint32_t cameraCommands = rig->instrumentCommandCount(camera);
    LONGS_EQUAL(0, cameraCommands);
    rig->rover().failInstrument(sim::SimDevice::kGrinder, 0x42, false, true);  // the scenario's fault hook
    const bool reported = rig->runUntil([&] { return rig->instrumentStatus(grinder).faultCode != 0; }, kNsPerSec);
    CHECK_TRUE(reported);
    const bool imaging = rig->runUntil([&] { return rig->instrumentCommandCount(camera) > cameraCommands; },
                                       5 * kNsPerSec);
    dumpOnFailure(imaging);
    CHECK_TRUE(imaging);
    const msg::InstrumentCommandMsg& image = rig->instrumentCommand(camera);
    CHECK(image.action == msg::InstrumentAction::kImage);
    LONGS_EQUAL(2, image.targetId);
    const bool done = rig->runUntil([&] { return complete(); }, 120 * kNsPerSec);
    rig->runFor(1100 * kNsPerMs);  // the last PLAN_EXEC downlinked
    dumpOnFailure(done);
    CHECK_TRUE(done);
    // The sequence, in the console's order.
    const std::string console = rig->consoleText();
    const char* const sequence[] = {
        "plan_exec: sample sample2 started",
        "EVT 972 WARN  plan_exec: grinder now failed (instrument state 4, fault 66)",
        "EVT 960 WARN  plan_exec: sample sample2 failed",
        "EVT 962 WARN  plan_exec: two_targets regenerating",
        "EVT 963 WARN  plan_exec: plan two_targets regenerated (selected): cost 32.50 -> 37.50",
        "EVT 956 INFO  plan_exec: image image2 started",
        "plan_exec: image image2 completed",
        "EVT 964 INFO  plan_exec: plan two_targets complete",
    };
    std::size_t at = 0;
    for (const char* text : sequence) {
        const std::size_t found = console.find(text, at);
        CHECK_TEXT(found != std::string::npos, text);
        at = found == std::string::npos ? at : found;
    }
    LONGS_EQUAL(1, rig->consoleCount("EVT 962 "));
    LONGS_EQUAL(1, rig->consoleCount(": activity failed (sample2), cost before 32.50"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 956 INFO  plan_exec: image "));  // the one image, the replacement
    LONGS_EQUAL(0, rig->consoleCount("EVT 959 "));                          // in its window, not late
    LONGS_EQUAL(0, rig->consoleCount("EVT 966"));
    LONGS_EQUAL(1, rig->instrumentCommandCount(camera));
    DOUBLES_EQUAL(4.0, field("state"), 0.0);
    DOUBLES_EQUAL(32.5, field("cost_before"), 1e-9);
    DOUBLES_EQUAL(37.5, field("cost"), 1e-9);
    DOUBLES_EQUAL(4.0, field("last_regeneration"), 0.0);  // activity failed
    DOUBLES_EQUAL(1.0, field("options", 1), 0.0);          // science2: image
    DOUBLES_EQUAL(1.0, field("failed"), 0.0);
    DOUBLES_EQUAL(1.0, field("regenerations"), 0.0);
}

namespace {
sim::FaultSpec instrumentFails(sim::SimDevice device, double atS) {
    sim::FaultSpec f;
    f.type = sim::FaultType::kInstrumentFailure;
    f.device = device;
    f.at = static_cast<core::TimeNs>(atS * 1e9);
    f.until = sim::kNever;
    f.faultCode = 0x42;
    return f;
}
}  // namespace

// Must-show 2, late completion (timeout): the grinder takes 400 s, past the
// sample's ub of 300 s. At its ub the sample is timed out (by the executive,
// or, in the same run, by the grinder giving up at its max duration, the same
// ub: either is a late activity) and the plan regenerated from where it
// stands: the other method, a pause then image(target 1), whose window opens
// from an event not yet executed. Cost 15 before, 20 after.
TEST(LockstepPlanExecutive, ASampleTakingLongerThanItsUbIsTimedOutAndThePlanRegenerated) {
    sim::Scenario s = sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml");
    s.faults.clear();
    s.devices.grinder.sampleS = 400.0;
    start(s);
    uplink("plan late_sample\n"
           "event at1\n"
           "choice science1 sample image cost 2\n"
           "event w when science1.image\n"
           "event done1\n"
           "activity drive1 drive start at1 [30, 900] cost 10 at 10 0\n"
           "activity sample1 sample at1 done1 [120, 300] cost 5 target 1 ask grinder=ok when science1.sample\n"
           "activity pause wait at1 w [0, inf] cost 0 when science1.image\n"
           "activity image1 image w done1 [30, 60] cost 8 target 1 ask camera=ok when science1.image\n"
           "end\n");
    const bool done = rig->runUntil([&] { return complete(); }, 470 * kNsPerSec);
    rig->runFor(1100 * kNsPerMs);
    dumpOnFailure(done);
    CHECK_TRUE(done);
    LONGS_EQUAL(1, rig->consoleCount("EVT 959 WARN  plan_exec: sample sample1 "));
    LONGS_EQUAL(1, rig->consoleCount("EVT 963 WARN  plan_exec: plan late_sample regenerated (selected): cost 15.00 -> 20.00"));
    LONGS_EQUAL(1, rig->consoleCount("plan_exec: image image1 completed"));
    DOUBLES_EQUAL(4.0, field("state"), 0.0);
    DOUBLES_EQUAL(1.0, field("late"), 0.0);
    DOUBLES_EQUAL(0.0, field("failed"), 0.0);
    DOUBLES_EQUAL(1.0, field("last_regeneration"), 0.0);  // late
    DOUBLES_EQUAL(15.0, field("cost_before"), 1e-9);
    DOUBLES_EQUAL(20.0, field("cost"), 1e-9);
    DOUBLES_EQUAL(1.0, field("options", 0), 0.0);
}

// Must-show 2, an inconsistent plan refused at upload: the rover cannot drive
// 60 s and sample 120 s within a 100 s deadline. PLAN_START is refused (event
// 954, PLAN_EXEC last_refusal 7) and nothing moves.
TEST(LockstepPlanExecutive, AnInconsistentPlanIsRefusedAtUpload) {
    start(sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml"));
    const std::string plan =
        "plan too_tight\n"
        "event at1\n"
        "event done1\n"
        "activity drive1 drive start at1 [60, 900] cost 10 at 10 0\n"
        "activity sample1 sample at1 done1 [120, 300] cost 5 target 1 ask grinder=ok\n"
        "constraint start done1 [0, 100]\n"
        "end\n";
    uplink(plan);
    rig->runFor(2 * kNsPerSec);
    LONGS_EQUAL(1, rig->consoleCount("EVT 954 ERROR plan_exec: plan too_tight refused: no valid selection"));
    LONGS_EQUAL(0, rig->consoleCount("EVT 950 "));
    DOUBLES_EQUAL(7.0, field("last_refusal"), 0.0);
    DOUBLES_EQUAL(1.0, field("plans_refused"), 0.0);
    DOUBLES_EQUAL(0.0, field("state"), 0.0);
    // A bad CRC is refused before the text is read.
    uplink(plan, 1);
    rig->runFor(2 * kNsPerSec);
    LONGS_EQUAL(1, rig->consoleCount("EVT 952 ERROR plan_exec: refused (bad CRC-32)"));
    DOUBLES_EQUAL(3.0, field("last_refusal"), 0.0);
}

// Must-show 2, the operator called when no method remains: the camera fails
// too, after the grinder, while the rover drives to target 2: image(target 2)
// has nothing left to run on. Event 966, SafeRequestMsg (reason 7): SAFE.
TEST(LockstepPlanExecutive, WhenNoMethodRemainsTheOperatorIsCalled) {
    sim::Scenario s = sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml");
    s.faults.push_back(instrumentFails(sim::SimDevice::kCamera, 245.0));
    start(s);
    uplink(readTextFile("unit_test/fuzz/corpus/plan/two_targets.plan"));
    const bool failed = rig->runUntil(
        [&] { return rig->fsw().planExecutive().state() == msg::PlanExecutiveState::kFailed; }, 470 * kNsPerSec);
    rig->runFor(1100 * kNsPerMs);
    dumpOnFailure(failed);
    CHECK_TRUE(failed);
    LONGS_EQUAL(1, rig->consoleCount("EVT 963 WARN  plan_exec: plan two_targets regenerated"));  // image2, at 240 s
    LONGS_EQUAL(1, rig->consoleCount("EVT 972 WARN  plan_exec: camera now failed"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 966 CRIT  plan_exec: plan two_targets: no method remains"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 215 "));  // the mode owner: SAFE on the call home
    CHECK(rig->fsw().roverMode().mode() == cmdtlm::Mode::kSafe);
    DOUBLES_EQUAL(5.0, field("state"), 0.0);
    DOUBLES_EQUAL(1.0, field("operator_calls"), 0.0);
    DOUBLES_EQUAL(7.0, field("call_home"), 0.0);
}

// ---- A drive to a region (`at X Y within R`) ---------------------------------

namespace {
struct DriveRun {
    bool complete = false;
    double completeS = 0.0;  // plan time the drive's end event was executed
    double estimateOffM = 0.0;  // the rover's final estimated position to the point
    double truthOffM = 0.0;     // the same, the simulator's truth
};
}  // namespace

// Issue 16, "drive to a point or region": one drive to (10, 0) on the
// two-targets site (clear of the rocks; the grinder's fault removed), as a
// point, `within 3` and `within 2`. The region's goal reaches the deliberative
// layer with its radius, its last leg reaches the habitual layer with it, and
// the rover stops on the way in: the drive completes with the rover's estimate
// farther from the point than HABITUAL.goal_tolerance_m but within R of it,
// sooner than the same drive to the point. With 3 m the leg before the last
// already ends inside the region (the last is achieved without driving); with
// 2 m the last leg's trajectory is cut where it enters the region. No heap
// from the uplink to the plan's end.
TEST(LockstepPlanExecutive, ADriveWithinARegionStopsInsideItSoonerThanTheSameDriveToThePoint) {
    sim::Scenario s = sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml");
    s.faults.clear();
    // One session: the plan uplinked and run to its end (at most 200 s).
    const auto fly = [&](const char* region) {
        start(s);
        const std::string plan = std::string("plan region\nevent there\n"
                                             "activity drive1 drive start there [0, 900] at 10 0") +
                                 region + "\nend\n";
        DriveRun r;
        {
            test::AllocationWatch watch;
            uplink(plan);
            r.complete = rig->runUntil([&] { return complete(); }, 200 * kNsPerSec);
            LONGS_EQUAL(0, watch.count());
        }
        rig->runFor(1100 * kNsPerMs);  // the last PLAN_EXEC downlinked, the rover at rest
        dumpOnFailure(r.complete);
        r.completeS = rig->fsw().planExecutive().dispatcher().eventTimeMs(1) / 1000.0;
        const msg::PoseEstimateMsg& est = rig->fsw().poseEstimator().latest();
        r.estimateOffM = std::hypot(est.xM - 10.0, est.yM);
        const sim::Pose2 p = rig->rover().truth().pose;
        r.truthOffM = std::hypot(p.x - 10.0, p.y);
        LONGS_EQUAL(1, rig->consoleCount("EVT 964 INFO  plan_exec: plan region complete"));
        DOUBLES_EQUAL(4.0, field("state"), 0.0);
        return r;
    };
    const auto next = [&] {  // a fresh run, from the start
        session.reset();
        rig = nullptr;
        ground = nullptr;
    };
    const DriveRun point = fly("");
    CHECK_TRUE(point.complete);
    const double tolerance = static_cast<double>(rig->fsw().tables().habitual().goal_tolerance_m);
    CHECK(point.estimateOffM <= tolerance);  // the point, reached to the tolerance
    DOUBLES_EQUAL(0.0, rig->planGoal().goals.goals[0].radiusM, 0.0);
    next();

    const DriveRun within3 = fly(" within 3");
    CHECK_TRUE(within3.complete);
    DOUBLES_EQUAL(3.0, rig->planGoal().goals.goals[0].radiusM, 1e-6);
    LONGS_EQUAL(1, rig->consoleCount("to (10.00, 0.00) within 3.00 m"));  // the last leg, at the habitual layer
    LONGS_EQUAL(1, rig->consoleCount("deliberative: goal 0 (10.00, 0.00) reached within 3.00 m"));
    CHECK(within3.estimateOffM > tolerance);  // stopped short of the point
    CHECK(within3.estimateOffM <= 3.0);       // inside the region
    CHECK(within3.completeS < point.completeS);
    next();

    const DriveRun within2 = fly(" within 2");
    CHECK_TRUE(within2.complete);
    LONGS_EQUAL(1, rig->consoleCount("deliberative: goal 0 (10.00, 0.00) reached within 2.00 m"));
    CHECK(within2.estimateOffM > tolerance);
    CHECK(within2.estimateOffM <= 2.0);
    CHECK(within2.completeS < point.completeS);
    std::printf("\n  region: drive to (10, 0) complete at %.1f s, the estimate %.2f m off (truth %.2f m); within 3 m "
                "%.1f s, %.2f m (%.2f m); within 2 m %.1f s, %.2f m (%.2f m)\n",
                point.completeS, point.estimateOffM, point.truthOffM, within3.completeS, within3.estimateOffM,
                within3.truthOffM, within2.completeS, within2.estimateOffM, within2.truthOffM);
}

// ---- Opportunistic science (PLAN_EXTEND) -----------------------------------

namespace {
constexpr std::uint16_t kSample1 = 1;  // the two-targets plan's sample(target 1); also the deadline plan's

struct ScienceRun {
    bool complete = false;
    double sample1S = 0.0;   // sample1's duration, start to completion
    double completeS = 0.0;  // plan time at completion
};
}  // namespace

TEST_GROUP_BASE(LockstepExtension, TEST_GROUP_CppUTestGroupLockstepPlanExecutive) {
    // PLAN_EXTEND as the ground sends it: extra seconds (f32), the activity's name.
    void extend(const char* activity, float extraS) {
        std::uint8_t args[4 + 23];
        core::BeWriter w(args, sizeof args);
        w.f32(extraS);
        const std::size_t n = std::strlen(activity);
        w.bytes(activity, n);
        CHECK_TRUE(ground->send("PLAN_EXTEND", args, 4 + n));
    }
    const plan_executive::PlanDispatcher& dispatcher() { return rig->fsw().planExecutive().dispatcher(); }
    bool sampleRunning() { return dispatcher().state(kSample1) == plan_executive::ActivityState::kRunning; }
    ScienceRun finish() {
        ScienceRun r;
        r.complete = rig->runUntil([&] { return complete(); }, 700 * kNsPerSec);
        rig->runFor(1100 * kNsPerMs);  // the last PLAN_EXEC downlinked
        dumpOnFailure(r.complete);
        r.sample1S = (dispatcher().endMs(kSample1) - dispatcher().startMs(kSample1)) / 1000.0;
        std::int32_t last = 0;
        for (std::uint16_t e = 0; e < rig->fsw().planExecutive().plan().eventCount; ++e) {
            const std::int32_t t = dispatcher().eventTimeMs(e);
            last = t != plan_executive::kInfiniteMs && t > last ? t : last;
        }
        r.completeS = last / 1000.0;
        return r;
    }
    // The two-targets plan with the grinder healthy: both targets sampled.
    void startTwoTargets() {
        sim::Scenario s = sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml");
        s.faults.clear();
        start(s);
        uplink(test::readTextFile("unit_test/fuzz/corpus/plan/two_targets.plan"));
    }
};

// A running sample extended by a follow-on request: sample1 is asked for 60 s
// more a minute into its work (expected about 147 s, its ub 300 s); the
// grinder takes the follow-on, the sample completes 60 s later than in the
// same run without the request, within its ub, and the plan still completes.
// A first request for 500 s is refused (beyond its ub). No heap from the
// uplink to the plan's end.
TEST(LockstepExtension, AFollowOnExtendsARunningSampleWhichCompletesLaterWithinItsUb) {
    startTwoTargets();
    const ScienceRun plain = finish();
    CHECK_TRUE(plain.complete);
    session.reset();  // a second run, from the start
    rig = nullptr;
    ground = nullptr;

    startTwoTargets();
    ScienceRun extended;
    {
        test::AllocationWatch watch;
        CHECK_TRUE(rig->runUntil([&] { return sampleRunning(); }, 200 * kNsPerSec));
        rig->runFor(60 * kNsPerSec);
        extend("sample1", 500.0F);
        rig->runFor(500 * kNsPerMs);
        extend("sample1", 60.0F);
        extended = finish();
        LONGS_EQUAL(0, watch.count());
    }
    CHECK_TRUE(extended.complete);
    LONGS_EQUAL(1, rig->consoleCount("EVT 976 WARN  plan_exec: extend sample1 +500.0 s refused: beyond its ub"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 974 INFO  plan_exec: extend sample1 +60.0 s sent: end "));
    LONGS_EQUAL(1, rig->consoleCount("EVT 975 INFO  plan_exec: sample1 extended by 60.0 s: the grinder took it"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 977 INFO  plan_exec: sample1 extended 60.0 s: done after "));
    LONGS_EQUAL(1, rig->consoleCount("plan_exec: sample sample2 completed"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 964 INFO  plan_exec: plan two_targets complete"));
    LONGS_EQUAL(0, rig->consoleCount("EVT 959 "));  // nothing late
    LONGS_EQUAL(0, rig->consoleCount("EVT 962 "));  // nothing regenerated
    // Later than it would have been by the 60 s asked (the grinder works in
    // 0.1 s, the executive sees it at 10 Hz), and within its ub.
    DOUBLES_EQUAL(plain.sample1S + 60.0, extended.sample1S, 0.3);
    CHECK(extended.sample1S <= 300.0);
    CHECK(extended.completeS > plain.completeS + 55.0);
    LONGS_EQUAL(1, rig->rover().grinder().instrumentStats().extended);
    // The ground's view.
    DOUBLES_EQUAL(4.0, field("state"), 0.0);
    DOUBLES_EQUAL(1.0, field("extensions"), 0.0);
    DOUBLES_EQUAL(1.0, field("extensions_refused"), 0.0);
    DOUBLES_EQUAL(4.0, field("last_extension_refusal"), 0.0);  // beyond its ub
    DOUBLES_EQUAL(0.0, field("late"), 0.0);
    DOUBLES_EQUAL(0.0, field("regenerations"), 0.0);
    std::printf("\n  extension: sample1 %.1f s plain, %.1f s extended by 60 s (ub 300 s); plan complete at %.1f s, "
                "%.1f s plain\n",
                plain.sample1S, extended.sample1S, extended.completeS, plain.completeS);
}

// An extension refused because it would break a later deadline: after the
// sample a 20 s report must end by 270 s, so the sample must end by 250 s.
// Asked for 90 s more a minute in (expected end about 190 s), within its own
// ub (start + 300 s) but past 250 s: refused, the grinder never told; the
// sample completes in its own time and the plan completes as planned.
TEST(LockstepExtension, AnExtensionThatWouldBreakALaterDeadlineIsRefusedAndThePlanUnaffected) {
    sim::Scenario s = sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml");
    s.faults.clear();
    start(s);
    uplink("plan deadline\n"
           "event at1\n"
           "event done1\n"
           "event back\n"
           "activity drive1 drive start at1 [30, 900] cost 10 at 10 0\n"
           "activity sample1 sample at1 done1 [120, 300] cost 5 target 1 ask grinder=ok\n"
           "activity report communicate done1 back [20, 20] cost 1\n"
           "constraint start back [0, 270]\n"
           "end\n");
    CHECK_TRUE(rig->runUntil([&] { return sampleRunning(); }, 200 * kNsPerSec));
    LONGS_EQUAL(250000, dispatcher().network().window(2).latestMs);
    rig->runFor(60 * kNsPerSec);
    extend("sample1", 90.0F);
    const ScienceRun r = finish();
    CHECK_TRUE(r.complete);
    LONGS_EQUAL(1, rig->consoleCount("EVT 976 WARN  plan_exec: extend sample1 +90.0 s refused: plan inconsistent"));
    LONGS_EQUAL(1, rig->consoleCount(" > latest 250.0 s)"));
    LONGS_EQUAL(0, rig->consoleCount("EVT 974 "));
    LONGS_EQUAL(0, rig->consoleCount("EVT 975 "));
    LONGS_EQUAL(0, rig->rover().grinder().instrumentStats().extended);
    // The sample took its own time, the grinder's drawn work; the plan completed, nothing late.
    DOUBLES_EQUAL(rig->rover().grinder().workDurationS(), r.sample1S, 0.3);
    LONGS_EQUAL(1, rig->consoleCount("EVT 964 INFO  plan_exec: plan deadline complete"));
    DOUBLES_EQUAL(4.0, field("state"), 0.0);
    DOUBLES_EQUAL(0.0, field("extensions"), 0.0);
    DOUBLES_EQUAL(1.0, field("extensions_refused"), 0.0);
    DOUBLES_EQUAL(5.0, field("last_extension_refusal"), 0.0);  // would make the plan inconsistent
    DOUBLES_EQUAL(0.0, field("late"), 0.0);
    DOUBLES_EQUAL(0.0, field("regenerations"), 0.0);
    std::printf("\n  extension refused: sample1 %.1f s (drawn %.1f s), plan complete at %.1f s\n", r.sample1S,
                rig->rover().grinder().workDurationS(), r.completeS);
}

// The simulated science instruments (grinder/sampler, camera) on an in-memory
// bus: what they answer to command frames, how long their work takes, refusals, follow-ons (extend),
// cancel, max duration, reach, the fault hooks, NMT, dropout and crash. The
// frames are read with the protocol's own codec (hal/devices/instrument_protocol).
#include <cmath>
#include <cstdint>
#include <vector>

#include "hal/devices/instrument_protocol.hpp"
#include "sim_stub/devices/instrument_emulator.hpp"
#include "sim_stub/rover_sim.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;
using hal::CanFrame;
namespace inst = hal::instrument;
using inst::Action;
using inst::Refusal;
using inst::Result;
using inst::State;

namespace {

constexpr core::TimeNs kMs = core::kNsPerMs;
constexpr core::TimeNs kSec = core::kNsPerSec;

// extendsId: an extend's command continued (maxDurationDs then its extra work).
CanFrame commandFrame(inst::Kind kind, Action action, std::uint8_t target, std::uint16_t id,
                      std::uint16_t maxDurationDs = 0, std::uint16_t extendsId = 0) {
    inst::Command c;
    c.action = action;
    c.target = target;
    c.commandId = id;
    c.maxDurationDs = maxDurationDs;
    c.extendsCommandId = extendsId;
    CanFrame f;
    inst::encodeCommand(kind, c, &f);
    return f;
}

}  // namespace

struct SimInstrumentsBench : public Utest, public test::DeviceBench {};

TEST_GROUP_BASE(SimInstruments, SimInstrumentsBench) {
    std::vector<inst::Report> reports;  // every report of the instrument stepped, decoded, in order
    std::vector<ScienceTarget> targets;
    InstrumentEmulator* grinder = nullptr;
    InstrumentEmulator* camera = nullptr;

    void setup() override {
        open(Pose2{0.0, 0.0, 0.0});
        targets = {{1, {1.0, 0.0}}, {2, {4.0, 0.0}}, {3, {20.0, 0.0}}};
        InstrumentParams g = defaultInstrumentParams(inst::Kind::kGrinder);
        g.sampleS = 10.0;
        g.digS = 20.0;
        g.durationSigma = 0.0;
        grinder = new InstrumentEmulator(*simPort, *world, inst::Kind::kGrinder, g, targets, 7);
        InstrumentParams cam = defaultInstrumentParams(inst::Kind::kCamera);
        cam.imageS = 2.0;
        cam.durationSigma = 0.0;
        camera = new InstrumentEmulator(*simPort, *world, inst::Kind::kCamera, cam, targets, 7, false);
    }
    void teardown() override {
        delete camera;
        delete grinder;
        close();
    }

    // The bench's runUntil, with the instrument's reports decoded (each must decode).
    void run(InstrumentEmulator& device, core::TimeNs until) {
        const std::size_t from = frames.size();
        runUntil(device, until);
        for (std::size_t i = from; i < frames.size(); ++i) {
            if (frames[i].id == inst::idsOf(device.kind()).statusCobId) {
                inst::Report r;
                const char* why = nullptr;
                CHECK_TRUE_TEXT(inst::decodeReport(device.kind(), frames[i].data, &r, &why), why);
                reports.push_back(r);
            }
        }
    }
    void send(const CanFrame& f) { CHECK(core::Status::kOk == flight->send(f)); }
    const inst::Report& last() const { return reports.back(); }
    std::vector<inst::Report> refusals() const {
        std::vector<inst::Report> out;
        for (const inst::Report& r : reports) {
            if (r.kind == inst::ReportKind::kRefusal) {
                out.push_back(r);
            }
        }
        return out;
    }
};

TEST(SimInstruments, BootsHeartbeatsAndReportsIdleEveryHundredMilliseconds) {
    run(*grinder, kSec);
    LONGS_EQUAL(0x724, frames[0].id);  // boot-up
    LONGS_EQUAL(0x00, frames[0].data[0]);
    LONGS_EQUAL(11, test::countId(frames, 0x724));  // boot-up + 10 heartbeats
    // A report at boot, then one every 100 ms.
    LONGS_EQUAL(11, test::countId(frames, 0x6A5));
    LONGS_EQUAL(11, reports.size());
    for (const inst::Report& r : reports) {
        CHECK(r.kind == inst::ReportKind::kStatus);
        CHECK(r.state == State::kIdle);
        LONGS_EQUAL(0, r.commandId);
        LONGS_EQUAL(0, r.faultCode);
    }
    LONGS_EQUAL(0, test::countId(frames, 0x6A6));  // the camera is not stepped
}

TEST(SimInstruments, ASampleIsTakenReportsProgressAndIsDoneAfterItsDuration) {
    run(*grinder, 100 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 41));
    run(*grinder, 101 * kMs);
    CHECK(last().state == State::kBusy);  // at once, not at the next period
    CHECK(last().action == Action::kSample);
    LONGS_EQUAL(1, last().target);
    LONGS_EQUAL(41, last().commandId);
    LONGS_EQUAL(0, last().progressPct);
    DOUBLES_EQUAL(10.0, grinder->workDurationS(), 1e-9);  // sigma 0: the nominal
    run(*grinder, 6101 * kMs);
    CHECK(last().state == State::kBusy);
    CHECK(last().progressPct >= 59 && last().progressPct <= 60);
    run(*grinder, 10200 * kMs);
    CHECK(grinder->state() == State::kDone);
    // The first done report came when the 10 s were up, at once.
    std::size_t doneAt = 0;
    while (reports[doneAt].state != State::kDone) {
        ++doneAt;
    }
    LONGS_EQUAL(100, reports[doneAt].progressPct);
    LONGS_EQUAL(41, reports[doneAt].commandId);
    CHECK(reports[doneAt].result == Result::kNone);
    LONGS_EQUAL(1, grinder->instrumentStats().accepted);
    LONGS_EQUAL(1, grinder->instrumentStats().completed);
    // Progress never went backwards while busy.
    std::uint8_t previous = 0;
    for (std::size_t i = 0; i < doneAt; ++i) {
        CHECK(reports[i].progressPct >= previous);
        previous = reports[i].progressPct;
    }
    // Done, it takes the next command.
    send(commandFrame(inst::Kind::kGrinder, Action::kDig, 1, 42));
    run(*grinder, 10300 * kMs);
    CHECK(grinder->state() == State::kBusy);
    LONGS_EQUAL(42, grinder->commandId());
    DOUBLES_EQUAL(20.0, grinder->workDurationS(), 1e-9);
}

TEST(SimInstruments, DurationsCarrySeededNoiseOneDrawPerCommand) {
    InstrumentParams p = defaultInstrumentParams(inst::Kind::kCamera);
    p.imageS = 10.0;
    p.durationSigma = 0.2;
    InstrumentEmulator a(*simPort, *world, inst::Kind::kCamera, p, targets, 11, false);
    InstrumentEmulator b(*simPort, *world, inst::Kind::kCamera, p, targets, 11, false);
    InstrumentEmulator other(*simPort, *world, inst::Kind::kCamera, p, targets, 12, false);
    for (InstrumentEmulator* e : {&a, &b, &other}) {
        e->step(t);  // power-on: before it, an instrument hears nothing
    }
    double sum = 0.0;
    bool differs = false;
    for (std::uint16_t id = 1; id <= 20; ++id) {
        const CanFrame image = commandFrame(inst::Kind::kCamera, Action::kImage, 2, id);
        for (InstrumentEmulator* e : {&a, &b, &other}) {
            e->onFrame(image);
            e->step(t);
        }
        DOUBLES_EQUAL(a.workDurationS(), b.workDurationS(), 0.0);  // same seed, same durations
        differs = differs || a.workDurationS() != other.workDurationS();
        CHECK(a.workDurationS() >= 1.0);  // at least 10 % of the nominal
        sum += a.workDurationS();
        t += 30 * kSec;  // each done before the next
        for (InstrumentEmulator* e : {&a, &b, &other}) {
            e->step(t);
            CHECK(e->state() == State::kDone);
        }
    }
    CHECK_TRUE(differs);
    DOUBLES_EQUAL(10.0, sum / 20.0, 1.5);  // mean within ~3 sigma of the mean's spread
}

TEST(SimInstruments, EveryCommandItCannotTakeIsRefusedWithAReportNamingIt) {
    run(*grinder, 50 * kMs);
    CanFrame shortFrame = commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 5);
    shortFrame.dlc = 7;
    CanFrame reserved = commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 6);
    reserved.data[7] = 1;
    send(shortFrame);
    send(reserved);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 0));      // command id 0
    send(commandFrame(inst::Kind::kGrinder, Action::kImage, 1, 7));       // the camera's action
    send(commandFrame(inst::Kind::kGrinder, static_cast<Action>(9), 1, 8));
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 9, 9));      // no such target
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 0, 10));     // target 0
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 2, 11));     // 4 m away: beyond 1.5 m
    send(commandFrame(inst::Kind::kGrinder, Action::kCancel, 0, 12));     // nothing running
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 13));     // taken
    send(commandFrame(inst::Kind::kGrinder, Action::kDig, 1, 14));        // busy
    send(commandFrame(inst::Kind::kGrinder, Action::kCancel, 0, 99));     // not the one running
    run(*grinder, 51 * kMs);
    const std::vector<inst::Report> refused = refusals();
    const struct {
        std::uint16_t id;
        Refusal why;
    } expected[] = {{5, Refusal::kMalformed},        {6, Refusal::kMalformed},     {0, Refusal::kMalformed},
                    {7, Refusal::kUnsupportedAction}, {8, Refusal::kUnsupportedAction}, {9, Refusal::kUnknownTarget},
                    {10, Refusal::kUnknownTarget},   {11, Refusal::kOutOfReach},   {12, Refusal::kNoSuchCommand},
                    {14, Refusal::kBusy},            {99, Refusal::kNoSuchCommand}};
    LONGS_EQUAL(sizeof expected / sizeof expected[0], refused.size());
    for (std::size_t i = 0; i < refused.size(); ++i) {
        LONGS_EQUAL(expected[i].id, refused[i].commandId);
        LONGS_EQUAL(static_cast<int>(expected[i].why), static_cast<int>(refused[i].refusal));
    }
    CHECK(refused.back().state == State::kBusy);  // the state when it refused
    LONGS_EQUAL(11, grinder->instrumentStats().refused);
    LONGS_EQUAL(1, grinder->instrumentStats().accepted);
    LONGS_EQUAL(13, grinder->commandId());
    CHECK(grinder->state() == State::kBusy);
}

TEST(SimInstruments, MoreCommandFramesInAStepThanItHoldsAreCountedAndDropped) {
    run(*grinder, 50 * kMs);
    for (std::uint16_t id = 1; id <= kInstrumentRxQueue + 3; ++id) {
        send(commandFrame(inst::Kind::kGrinder, Action::kCancel, 0, id));
    }
    run(*grinder, 51 * kMs);
    LONGS_EQUAL(kInstrumentRxQueue, grinder->instrumentStats().refused);
    LONGS_EQUAL(3, grinder->instrumentStats().rxOverflow);
}

TEST(SimInstruments, ACancelStopsTheCommandRunningAndLeavesTheInstrumentIdle) {
    run(*grinder, 50 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kDig, 1, 300));
    run(*grinder, 5 * kSec);
    send(commandFrame(inst::Kind::kGrinder, Action::kCancel, 0, 300));
    run(*grinder, 5 * kSec + kMs);
    CHECK(last().state == State::kIdle);
    CHECK(last().result == Result::kCancelled);
    LONGS_EQUAL(300, last().commandId);
    CHECK(last().progressPct >= 24 && last().progressPct <= 25);  // stopped where it was (5 of 20 s)
    LONGS_EQUAL(1, grinder->instrumentStats().cancelled);
    run(*grinder, 30 * kSec);
    CHECK(grinder->state() == State::kIdle);  // it never finishes
    LONGS_EQUAL(0, grinder->instrumentStats().completed);
}

TEST(SimInstruments, ACommandNotDoneWithinItsMaxDurationFailsTimedOut) {
    run(*grinder, 50 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 8, 55));  // 5.5 s for 10 s of work
    run(*grinder, 5550 * kMs);
    CHECK(grinder->state() == State::kBusy);
    run(*grinder, 5560 * kMs);
    CHECK(last().state == State::kFailed);
    CHECK(last().result == Result::kTimedOut);
    LONGS_EQUAL(0, last().faultCode);
    LONGS_EQUAL(8, last().commandId);
    // A failed command does not fail the instrument: the next one is taken.
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 9, 200));
    run(*grinder, 5600 * kMs);
    CHECK(grinder->state() == State::kBusy);
    run(*grinder, 16 * kSec);
    CHECK(grinder->state() == State::kDone);
}

TEST(SimInstruments, DrivingTheTargetOutOfReachFailsTheCommand) {
    run(*grinder, 50 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 21));
    run(*grinder, kSec);
    CHECK(grinder->state() == State::kBusy);
    speeds = test::sides(-2.0, -2.0);  // backing away at 0.2 m/s: 1.5 m from target 1 after 2.5 s
    run(*grinder, 5 * kSec);
    CHECK(last().state == State::kFailed);
    CHECK(last().result == Result::kOutOfReach);
    CHECK(world->truth().pose.x < -0.4);
}

TEST(SimInstruments, AFaultAbortsTheCommandReportsFailedRefusesEverythingUntilCleared) {
    run(*grinder, 50 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 50));
    run(*grinder, 2 * kSec);
    CHECK_FALSE(grinder->fail(0, false));  // code 0 is no fault
    CHECK(grinder->state() == State::kBusy);
    CHECK_TRUE(grinder->fail(0x42, false));
    run(*grinder, 2 * kSec + kMs);
    CHECK(last().state == State::kFailed);
    LONGS_EQUAL(0x42, last().faultCode);
    CHECK(last().result == Result::kAborted);
    LONGS_EQUAL(50, last().commandId);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 51));
    send(commandFrame(inst::Kind::kGrinder, Action::kCancel, 0, 50));
    run(*grinder, 3 * kSec);
    const std::vector<inst::Report> refused = refusals();
    LONGS_EQUAL(2, refused.size());
    CHECK(refused[0].refusal == Refusal::kFaulted);
    CHECK(refused[1].refusal == Refusal::kFaulted);
    LONGS_EQUAL(0x42, refused[0].faultCode);
    CHECK(last().state == State::kFailed);  // and it keeps saying so
    grinder->clearFault();
    run(*grinder, 3 * kSec + kMs);
    CHECK(last().state == State::kIdle);
    LONGS_EQUAL(0, last().faultCode);
    CHECK(last().result == Result::kAborted);  // of command 50
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 52));
    run(*grinder, 3100 * kMs);
    CHECK(grinder->state() == State::kBusy);
}

TEST(SimInstruments, ASilentFaultStopsEveryReportAndIgnoresCommandsButNotTheHeartbeat) {
    run(*grinder, 50 * kMs);
    CHECK_TRUE(grinder->fail(7, true));
    frames.clear();
    reports.clear();
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 60));
    run(*grinder, 2 * kSec);
    CHECK(reports.empty());
    CHECK(test::countId(frames, 0x724) >= 19);
    LONGS_EQUAL(1, grinder->instrumentStats().ignored);
    LONGS_EQUAL(0, grinder->instrumentStats().refused);
    grinder->clearFault();
    run(*grinder, 2 * kSec + kMs);
    CHECK(last().state == State::kIdle);
}

TEST(SimInstruments, ADropoutSilencesReportsWhileTheWorkGoesOn) {
    run(*grinder, 50 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 70));
    run(*grinder, kSec);
    grinder->setDropout(true);
    reports.clear();
    run(*grinder, 12 * kSec);
    CHECK(reports.empty());
    CHECK(grinder->state() == State::kDone);
    grinder->setDropout(false);
    run(*grinder, 12100 * kMs);
    CHECK(last().state == State::kDone);
    LONGS_EQUAL(70, last().commandId);
}

TEST(SimInstruments, ACrashLosesTheCommandButAFaultSurvivesTheRestart) {
    run(*grinder, 50 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 80));
    run(*grinder, kSec);
    grinder->crash();
    reports.clear();
    send(commandFrame(inst::Kind::kGrinder, Action::kCancel, 0, 80));  // unheard
    run(*grinder, 2 * kSec);
    CHECK(reports.empty());
    grinder->restart();
    run(*grinder, 2 * kSec + kMs);
    CHECK(last().state == State::kIdle);
    LONGS_EQUAL(0, last().commandId);
    // An instrument fault is hardware: a reset (NMT reset node here) keeps it.
    CHECK_TRUE(grinder->fail(3, false));
    send(test::nmt(0x81, 0x24));
    run(*grinder, 3 * kSec);
    CHECK(last().state == State::kFailed);
    LONGS_EQUAL(3, last().faultCode);
    LONGS_EQUAL(0, last().commandId);
}

TEST(SimInstruments, NmtStoppedSendsNoReportsAndIgnoresCommands) {
    run(*grinder, 50 * kMs);
    send(test::nmt(0x02, 0x24));
    run(*grinder, 60 * kMs);
    reports.clear();
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 90));
    run(*grinder, kSec);
    CHECK(reports.empty());
    CHECK(grinder->state() == State::kIdle);
    LONGS_EQUAL(1, grinder->instrumentStats().ignored);
    send(test::nmt(0x01, 0x24));
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 91));
    run(*grinder, 1100 * kMs);
    CHECK(grinder->state() == State::kBusy);
}

TEST(SimInstruments, EachInstrumentAnswersOnlyItsOwnCommandsAndTheCameraImagesFromFarther) {
    run(*grinder, 20 * kMs);
    send(commandFrame(inst::Kind::kCamera, Action::kImage, 2, 100));  // the camera's COB-ID
    run(*grinder, 40 * kMs);
    CHECK(grinder->state() == State::kIdle);
    LONGS_EQUAL(0, grinder->instrumentStats().refused);
    // The camera (fed by its owner, as RoverSim does) takes it: target 2 is 4 m away, within 5 m.
    camera->step(t);  // power-on
    camera->onFrame(commandFrame(inst::Kind::kCamera, Action::kImage, 2, 100));
    camera->step(t + kMs);
    CHECK(camera->state() == State::kBusy);
    camera->onFrame(commandFrame(inst::Kind::kCamera, Action::kImage, 3, 101));  // busy
    camera->step(t + 10 * kMs);
    camera->step(t + 3 * kSec);
    CHECK(camera->state() == State::kDone);
    camera->onFrame(commandFrame(inst::Kind::kCamera, Action::kImage, 3, 102));  // 20 m away
    camera->onFrame(commandFrame(inst::Kind::kCamera, Action::kSample, 1, 103));
    camera->step(t + 3 * kSec + 10 * kMs);
    LONGS_EQUAL(3, camera->instrumentStats().refused);
    std::vector<inst::Report> cameraReports;
    CanFrame f;
    while (core::isOk(flight->receive(&f))) {
        if (f.id == 0x6A6) {
            inst::Report r;
            const char* why = nullptr;
            CHECK_TRUE(inst::decodeReport(inst::Kind::kCamera, f.data, &r, &why));
            cameraReports.push_back(r);
        }
    }
    LONGS_EQUAL(static_cast<int>(Refusal::kUnsupportedAction), static_cast<int>(cameraReports.back().refusal));
    LONGS_EQUAL(static_cast<int>(Refusal::kOutOfReach), static_cast<int>(cameraReports[cameraReports.size() - 2].refusal));
}

// RoverSim builds both instruments from the scenario (targets, timing) and
// applies instrument_failure through the fault schedule.
TEST(SimInstruments, RoverSimRunsTheScenarioInstrumentsAndTheirFaults) {
    const Scenario s = parseScenario(test::kOpenSiteScenario + R"(
[[targets]]
id = 4
x_m = 1.0
y_m = 0.5
[devices.grinder]
sample_s = 2
duration_sigma = 0
[[faults]]
type = "instrument_failure"
at_s = 5
device = "grinder"
fault_code = 9
until_s = 6
[[faults]]
type = "instrument_failure"
at_s = 5
device = "camera"
silent = true
)",
                                     "rover_instruments.toml");
    test::FakeWheels wheels;
    RoverSim rover(s, *simPort, wheels.models());
    std::vector<CanFrame> seen;
    auto run = [&](core::TimeNs until) {
        for (; t <= until; t += kMs) {
            clock.sleepUntil(t);
            rover.step(t);
            CanFrame f;
            while (core::isOk(flight->receive(&f))) {
                seen.push_back(f);
            }
        }
    };
    run(100 * kMs);
    CHECK(test::countId(seen, 0x6A5) >= 1);
    CHECK(test::countId(seen, 0x6A6) >= 1);
    CHECK(test::countId(seen, 0x724) >= 1);
    CHECK(test::countId(seen, 0x725) >= 1);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 4, 1));
    run(3 * kSec);
    CHECK(rover.grinder().state() == State::kDone);
    DOUBLES_EQUAL(2.0, rover.grinder().workDurationS(), 1e-9);
    run(5100 * kMs);
    LONGS_EQUAL(9, rover.grinder().faultCode());
    CHECK(rover.grinder().state() == State::kFailed);
    CHECK_TRUE(rover.camera().silent());
    run(6100 * kMs);
    LONGS_EQUAL(0, rover.grinder().faultCode());
    CHECK(rover.grinder().state() == State::kIdle);
    CHECK_TRUE(rover.camera().silent());  // no end: failed for good
    LONGS_EQUAL(3, rover.stats().faultsApplied);
    LONGS_EQUAL(0, rover.stats().faultsUnhandled);
    // The hook refuses what it cannot act on.
    rover.failInstrument(SimDevice::kImu, 1, false, true);
    rover.failInstrument(SimDevice::kGrinder, 0, false, true);
    LONGS_EQUAL(2, rover.stats().faultsUnhandled);
}

namespace {
CanFrame extendFrame(inst::Kind kind, std::uint8_t target, std::uint16_t id, std::uint16_t extendsId,
                     std::uint16_t extraDs) {
    return commandFrame(kind, Action::kExtend, target, id, extraDs, extendsId);
}
}  // namespace

// A follow-on (extend) naming the sample running: the work goes on 5 s more,
// under the follow-on's id from the report at once; done at 15 s, not 10.
TEST(SimInstruments, AFollowOnExtendsTheWorkRunningUnderItsNewId) {
    run(*grinder, 100 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 41));
    run(*grinder, 4100 * kMs);
    CHECK(last().progressPct >= 39 && last().progressPct <= 40);  // 4 s of 10 s
    send(extendFrame(inst::Kind::kGrinder, 1, 42, 41, 50));
    run(*grinder, 4101 * kMs);
    CHECK(last().kind == inst::ReportKind::kStatus);
    CHECK(last().state == State::kBusy);
    CHECK(last().action == Action::kSample);  // the work continued
    LONGS_EQUAL(42, last().commandId);
    CHECK(last().progressPct >= 26 && last().progressPct <= 27);  // 4 s of 15 s
    DOUBLES_EQUAL(15.0, grinder->workDurationS(), 1e-9);
    LONGS_EQUAL(1, grinder->instrumentStats().extended);
    LONGS_EQUAL(1, grinder->instrumentStats().accepted);  // one command's work
    run(*grinder, 14900 * kMs);
    CHECK(grinder->state() == State::kBusy);
    run(*grinder, 15200 * kMs);
    CHECK(grinder->state() == State::kDone);
    LONGS_EQUAL(42, last().commandId);
    LONGS_EQUAL(1, grinder->instrumentStats().completed);
    CHECK(refusals().empty());
}

// A follow-on naming no running command (another id, a finished one, another
// target), or malformed, is refused; the work goes on as it was.
TEST(SimInstruments, AFollowOnNamingNoRunningCommandIsRefused) {
    run(*grinder, 100 * kMs);
    send(extendFrame(inst::Kind::kGrinder, 1, 42, 41, 50));  // idle
    run(*grinder, 200 * kMs);
    send(commandFrame(inst::Kind::kGrinder, Action::kSample, 1, 41, 120));  // max 12 s
    run(*grinder, 300 * kMs);
    send(extendFrame(inst::Kind::kGrinder, 1, 43, 40, 50));  // another id
    send(extendFrame(inst::Kind::kGrinder, 2, 44, 41, 50));  // another target
    CanFrame bad = extendFrame(inst::Kind::kGrinder, 1, 45, 41, 0);  // no extra work
    send(bad);
    bad = extendFrame(inst::Kind::kGrinder, 1, 41, 41, 50);  // its own id
    send(bad);
    run(*grinder, 400 * kMs);
    const std::vector<inst::Report> r = refusals();
    LONGS_EQUAL(5, r.size());
    CHECK(r[0].refusal == Refusal::kNoSuchCommand);
    CHECK(r[0].action == Action::kExtend);
    LONGS_EQUAL(42, r[0].commandId);
    CHECK(r[1].refusal == Refusal::kNoSuchCommand);
    CHECK(r[2].refusal == Refusal::kNoSuchCommand);
    CHECK(r[3].refusal == Refusal::kMalformed);
    CHECK(r[4].refusal == Refusal::kMalformed);
    LONGS_EQUAL(41, grinder->commandId());
    DOUBLES_EQUAL(10.0, grinder->workDurationS(), 1e-9);
    // A follow-on past the command's max duration times out there (the limit
    // runs from the original start).
    send(extendFrame(inst::Kind::kGrinder, 1, 46, 41, 50));
    run(*grinder, 12500 * kMs);
    CHECK(grinder->state() == State::kFailed);
    CHECK(grinder->result() == Result::kTimedOut);
    LONGS_EQUAL(46, grinder->commandId());
}

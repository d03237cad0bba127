// Lockstep: the science instruments end to end. A command published on the
// flight software's bus (as the plan executive will) goes out over the
// in-memory CAN bus to the simulated grinder or camera, and the flight side's
// InstrumentStatusMsg follows it: accepted, busy, done; refused with the
// instrument's reason; cancelled; and, with the scenario's instrument_failure,
// failed with its fault code or offline. Only CAN frames pass between the two
// sides. The rover stays parked next to target 1 of two_targets.toml.
#include <cstdio>
#include <memory>
#include <string>

#include "hal/devices/device_events.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;
using msg::Instrument;
using msg::InstrumentAction;
using msg::InstrumentRefusal;
using msg::InstrumentResult;
using msg::InstrumentState;

namespace {

// two_targets.toml with the rover parked 1 m from target 1 (10, 0), 12 m from
// target 2 (20, 5): within the grinder's 1.5 m and the camera's 5 m of target 1,
// beyond both of target 2.
sim::Scenario parkedAtTargetOne(bool keepFaults) {
    sim::Scenario s = sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml");
    s.start = sim::Pose2{9.0, 0.0, 0.0};
    if (!keepFaults) {
        s.faults.clear();
    }
    return s;
}

sim::FaultSpec instrumentFailure(sim::SimDevice device, core::TimeNs at, core::TimeNs until, std::uint8_t code,
                                 bool silent) {
    sim::FaultSpec f;
    f.type = sim::FaultType::kInstrumentFailure;
    f.device = device;
    f.at = at;
    f.until = until;
    f.faultCode = code;
    f.silent = silent;
    return f;
}

bool bothOnline(sim::LockstepRig& rig) {
    return rig.instrumentStatus(Instrument::kGrinder).state != InstrumentState::kOffline &&
           rig.instrumentStatus(Instrument::kCamera).state != InstrumentState::kOffline;
}

double seconds(core::TimeNs t) { return static_cast<double>(t) / static_cast<double>(kNsPerSec); }

}  // namespace

TEST_GROUP(LockstepInstruments) {};

TEST(LockstepInstruments, ASampleCommandedOnTheFlightBusIsDoneByTheSimulatedGrinder) {
    sim::Scenario s = parkedAtTargetOne(false);
    s.devices.grinder.sampleS = 20.0;
    s.devices.camera.imageS = 5.0;
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(s);
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    CHECK_TRUE(rig.runUntil([&] { return bothOnline(rig); }, 200 * kNsPerMs));
    const msg::InstrumentStatusMsg& grinder = rig.instrumentStatus(Instrument::kGrinder);
    const msg::InstrumentStatusMsg& camera = rig.instrumentStatus(Instrument::kCamera);
    CHECK(grinder.state == InstrumentState::kIdle);
    LONGS_EQUAL(0, grinder.commandId);

    const core::TimeNs sent = rig.clock().now();
    rig.commandInstrument(Instrument::kGrinder, InstrumentAction::kSample, 1, 1, 60.0);
    CHECK_TRUE(rig.runUntil([&] { return grinder.state == InstrumentState::kBusy; }, 50 * kNsPerMs));
    CHECK(rig.clock().now() - sent <= 30 * kNsPerMs);  // sent this frame, taken next step, reported next frame
    LONGS_EQUAL(1, grinder.commandId);
    LONGS_EQUAL(1, grinder.targetId);
    CHECK(grinder.action == InstrumentAction::kSample);
    LONGS_EQUAL(1, rig.rover().grinder().instrumentStats().accepted);
    const double drawn = rig.rover().grinder().workDurationS();
    CHECK(drawn > 15.0 && drawn < 25.0);
    CHECK_TRUE(rig.runUntil([&] { return grinder.state == InstrumentState::kDone; }, 30 * kNsPerSec));
    const double doneAfter = seconds(rig.clock().now() - sent);
    DOUBLES_EQUAL(drawn, doneAfter, 0.05);
    LONGS_EQUAL(100, grinder.progressPct);
    CHECK(grinder.result == InstrumentResult::kNone);
    LONGS_EQUAL(1, grinder.commandsSent);
    LONGS_EQUAL(1, grinder.commandsAccepted);
    LONGS_EQUAL(0, grinder.framesBad);
    CHECK(grinder.lastReportNs > rig.clock().now() - 150 * kNsPerMs);

    // Target 2 is 12 m away: the camera refuses it and says why.
    rig.commandInstrument(Instrument::kCamera, InstrumentAction::kImage, 2, 2, 60.0);
    CHECK_TRUE(rig.runUntil([&] { return camera.commandsRefused == 1; }, 50 * kNsPerMs));
    CHECK(camera.lastRefusal == InstrumentRefusal::kOutOfReach);
    LONGS_EQUAL(2, camera.lastRefusedCommandId);
    CHECK(camera.state == InstrumentState::kIdle);
    // Target 1 it images.
    rig.commandInstrument(Instrument::kCamera, InstrumentAction::kImage, 1, 3, 60.0);
    CHECK_TRUE(rig.runUntil([&] { return camera.state == InstrumentState::kDone && camera.commandId == 3; },
                            10 * kNsPerSec));
    // A command the flight side can tell is wrong never reaches the bus.
    rig.commandInstrument(Instrument::kCamera, InstrumentAction::kDig, 1, 4, 60.0);
    CHECK_TRUE(rig.runUntil([&] { return camera.commandsNotSent == 1; }, 20 * kNsPerMs));
    CHECK(camera.lastRefusal == InstrumentRefusal::kUnsupportedAction);
    LONGS_EQUAL(2, camera.commandsSent);
    LONGS_EQUAL(2, rig.rover().camera().instrumentStats().refused + rig.rover().camera().instrumentStats().accepted);

    rig.runFor(200 * kNsPerMs);  // the console writes events at 10 Hz
    LONGS_EQUAL(2, rig.consoleCount("EVT 456 "));  // accepted: sample 1, image 3
    LONGS_EQUAL(2, rig.consoleCount("EVT 457 "));  // done
    LONGS_EQUAL(1, rig.consoleCount("EVT 459 "));  // refused by the camera
    LONGS_EQUAL(1, rig.consoleCount("EVT 460 "));  // not sent
    LONGS_EQUAL(0, rig.consoleCount("EVT 455 "));  // never offline
    LONGS_EQUAL(0, rig.consoleCount("EVT 420 "));  // every instrument frame has its owner
    char figures[160];
    std::snprintf(figures, sizeof figures, "sample target 1: drawn %.2f s, done on the flight bus %.2f s after the command",
                  drawn, doneAfter);
    UT_PRINT(figures);
}

TEST(LockstepInstruments, ACancelOnTheFlightBusStopsTheDigAndTheGrinderIsIdle) {
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(parkedAtTargetOne(false));
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    CHECK_TRUE(rig.runUntil([&] { return bothOnline(rig); }, 200 * kNsPerMs));
    const msg::InstrumentStatusMsg& grinder = rig.instrumentStatus(Instrument::kGrinder);
    rig.commandInstrument(Instrument::kGrinder, InstrumentAction::kDig, 1, 20, 0.0);
    CHECK_TRUE(rig.runUntil([&] { return grinder.state == InstrumentState::kBusy; }, 50 * kNsPerMs));
    rig.runFor(24 * kNsPerSec);  // about a tenth of the 240 s dig
    CHECK(grinder.progressPct >= 8 && grinder.progressPct <= 12);
    rig.commandInstrument(Instrument::kGrinder, InstrumentAction::kCancel, 0, 99);  // not the one running
    rig.commandInstrument(Instrument::kGrinder, InstrumentAction::kCancel, 0, 20);
    CHECK_TRUE(rig.runUntil([&] { return grinder.state == InstrumentState::kIdle; }, 50 * kNsPerMs));
    CHECK(grinder.result == InstrumentResult::kCancelled);
    LONGS_EQUAL(20, grinder.commandId);
    LONGS_EQUAL(1, grinder.commandsRefused);
    CHECK(grinder.lastRefusal == InstrumentRefusal::kNoSuchCommand);
    LONGS_EQUAL(99, grinder.lastRefusedCommandId);
    LONGS_EQUAL(1, rig.rover().grinder().instrumentStats().cancelled);
    rig.runFor(300 * kNsPerMs);
    LONGS_EQUAL(1, rig.consoleCount("EVT 461 "));
}

// The scenario's own fault: two_targets.toml fails the grinder for good at
// 240 s with fault code 0x42. A sample started at 200 s (150 s of work) is
// aborted by it; the flight side reports failed, and the next command is
// refused (faulted).
TEST(LockstepInstruments, TheScenariosGrinderFailureIsReportedFailedWithItsCodeAndCommandsAreRefused) {
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(parkedAtTargetOne(true));
    sim::LockstepRig& rig = *rigHolder;
    LONGS_EQUAL(1, rig.scenario().faults.size());
    CHECK(core::Status::kOk == rig.init());
    const msg::InstrumentStatusMsg& grinder = rig.instrumentStatus(Instrument::kGrinder);
    rig.runFor(200 * kNsPerSec);
    CHECK(grinder.state == InstrumentState::kIdle);
    rig.commandInstrument(Instrument::kGrinder, InstrumentAction::kSample, 1, 7, 300.0);
    CHECK_TRUE(rig.runUntil([&] { return grinder.state == InstrumentState::kBusy; }, 50 * kNsPerMs));
    CHECK(rig.rover().grinder().workDurationS() > 41.0);  // still sampling at 240 s
    CHECK_TRUE(rig.runUntil([&] { return grinder.state == InstrumentState::kFailed; }, 45 * kNsPerSec));
    DOUBLES_EQUAL(240.0, seconds(rig.clock().now()), 0.03);  // the report at once, read the next frame
    LONGS_EQUAL(0x42, grinder.faultCode);
    CHECK(grinder.result == InstrumentResult::kAborted);
    LONGS_EQUAL(7, grinder.commandId);
    rig.commandInstrument(Instrument::kGrinder, InstrumentAction::kSample, 1, 8, 300.0);
    CHECK_TRUE(rig.runUntil([&] { return grinder.commandsRefused == 1; }, 50 * kNsPerMs));
    CHECK(grinder.lastRefusal == InstrumentRefusal::kFaulted);
    LONGS_EQUAL(8, grinder.lastRefusedCommandId);
    rig.runFor(10 * kNsPerSec);
    CHECK(grinder.state == InstrumentState::kFailed);  // for good
    // The camera is not affected.
    CHECK(rig.instrumentStatus(Instrument::kCamera).state == InstrumentState::kIdle);
    LONGS_EQUAL(1, rig.rover().stats().faultsApplied);
    LONGS_EQUAL(1, rig.consoleCount("EVT 458 "));
    LONGS_EQUAL(1, rig.consoleCount("EVT 459 "));
}

// A silent failure: the camera stops answering (its heartbeat goes on). The
// flight side declares it offline, sends it nothing, and takes it back when it
// reports again.
TEST(LockstepInstruments, ASilentCameraGoesOfflineOnTheFlightSideAndComesBack) {
    sim::Scenario s = parkedAtTargetOne(false);
    s.faults.push_back(instrumentFailure(sim::SimDevice::kCamera, 5 * kNsPerSec, 8 * kNsPerSec, 3, true));
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(s);
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    const msg::InstrumentStatusMsg& camera = rig.instrumentStatus(Instrument::kCamera);
    rig.runFor(5 * kNsPerSec);
    CHECK(camera.state == InstrumentState::kIdle);
    CHECK_TRUE(rig.runUntil([&] { return camera.state == InstrumentState::kOffline; }, kNsPerSec));
    const double offlineAt = seconds(rig.clock().now());
    // The last report came within 100 ms before 5 s; offline 500 ms after it, at the next frame.
    CHECK_TEXT(offlineAt > 5.4 && offlineAt < 5.52, std::to_string(offlineAt).c_str());
    LONGS_EQUAL(1, camera.offlineCount);
    rig.commandInstrument(Instrument::kCamera, InstrumentAction::kImage, 1, 30, 0.0);
    CHECK_TRUE(rig.runUntil([&] { return camera.commandsNotSent == 1; }, 20 * kNsPerMs));
    CHECK(camera.lastRefusal == InstrumentRefusal::kOffline);
    LONGS_EQUAL(0, camera.commandsSent);
    CHECK_TRUE(rig.runUntil([&] { return camera.state == InstrumentState::kIdle; }, 3 * kNsPerSec));
    DOUBLES_EQUAL(8.0, seconds(rig.clock().now()), 0.03);
    CHECK(rig.instrumentStatus(Instrument::kGrinder).state == InstrumentState::kIdle);  // never affected
    rig.runFor(200 * kNsPerMs);
    LONGS_EQUAL(1, rig.consoleCount("EVT 455 "));
}

// The house rule holds with the instruments running: after initialisation
// nothing on the flight side (nor the simulator's step) allocates, while the
// instruments take, refuse, cancel and finish commands and one fails.
TEST(LockstepInstruments, NothingAllocatesWhileTheInstrumentsWork) {
    sim::Scenario s = parkedAtTargetOne(false);
    s.devices.grinder.sampleS = 3.0;
    s.devices.camera.imageS = 2.0;
    s.faults.push_back(instrumentFailure(sim::SimDevice::kGrinder, 14 * kNsPerSec, 15 * kNsPerSec, 5, false));
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(s);
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    rig.runFor(kNsPerSec);  // boot: tables, drives configured, consoles opened
    const msg::InstrumentStatusMsg& grinder = rig.instrumentStatus(Instrument::kGrinder);
    const msg::InstrumentStatusMsg& camera = rig.instrumentStatus(Instrument::kCamera);
    std::uint64_t allocations = 0;
    {
        rse::test::AllocationWatch watch;
        std::uint16_t id = 100;
        for (int round = 0; round < 3; ++round) {
            rig.commandInstrument(Instrument::kGrinder, InstrumentAction::kSample, 1, ++id, 10.0);
            rig.commandInstrument(Instrument::kCamera, InstrumentAction::kImage, 1, ++id, 10.0);
            rig.commandInstrument(Instrument::kCamera, InstrumentAction::kImage, 2, ++id, 10.0);  // refused
            rig.runFor(kNsPerSec);
            rig.commandInstrument(Instrument::kCamera, InstrumentAction::kCancel, 0, static_cast<std::uint16_t>(id - 1));
            rig.commandInstrument(Instrument::kGrinder, InstrumentAction::kImage, 1, ++id, 10.0);  // not sent
            rig.runFor(3 * kNsPerSec);
        }
        rig.runFor(3 * kNsPerSec);  // the fault at 14 s and its end at 15 s
        allocations = watch.count();
    }
    LONGS_EQUAL(0, allocations);
    // ...and they really worked.
    LONGS_EQUAL(3, grinder.commandsAccepted);
    CHECK(grinder.commandsNotSent >= 3);
    CHECK(camera.commandsRefused >= 3);
    LONGS_EQUAL(3, rig.rover().grinder().instrumentStats().completed);
    LONGS_EQUAL(3, rig.rover().camera().instrumentStats().cancelled);
    CHECK(rig.consoleCount("EVT 458 ") >= 1);  // the grinder's fault
    CHECK(rig.consoleCount("EVT 462 ") >= 1);  // and its clearing
    LONGS_EQUAL(0, rig.fsw().bus().stats().dropped);
}

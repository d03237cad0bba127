// Fault protection's decisions, one response kind at a time: what is held,
// which recovery is asked for and when, when a response gives up, and that the
// FAULT_PROTECTION and FAULT_RESPONSE fields change what it does.
#include <cstdint>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/fault_protection/fault_responder.hpp"
#include "fsw/tables/table_types.hpp"
#include "unit_test/support/event_probe.hpp"

#include <CppUTest/TestHarness.h>

using namespace rse;
using fault_protection::FaultResponder;
using fault_protection::ResponderActions;
using fault_protection::ResponderInputs;
using fault_protection::ResponderLimits;
using msg::DriveHealth;
using msg::DriveRecoveryAction;
using msg::FaultClass;
using msg::FaultResponseKind;
using msg::ResponseState;

namespace {

constexpr core::TimeNs kMs = core::kNsPerMs;
constexpr core::TimeNs kFrame = 10 * kMs;

std::uint64_t bitOf(std::uint32_t id) { return std::uint64_t{1} << id; }

struct Rig {
    core::VirtualClock clock;
    core::EventLog events{clock};
    FaultResponder responder{events};
    ResponderInputs in;
    ResponderLimits limits;
    ResponderActions out;

    Rig() {
        for (std::size_t c = 0; c < msg::kFaultClassCount; ++c) {
            limits.response[c] = FaultResponseKind::kHoldUntilClear;
            limits.attempts[c] = 3;
            limits.maxWait[c] = 1000 * kMs;
        }
        limits.response[static_cast<std::size_t>(FaultClass::kDriveLost)] = FaultResponseKind::kRecoverDrive;
        limits.response[static_cast<std::size_t>(FaultClass::kDriveFaulted)] = FaultResponseKind::kRecoverDrive;
        limits.response[static_cast<std::size_t>(FaultClass::kTaskStalled)] = FaultResponseKind::kRestartTask;
        limits.response[static_cast<std::size_t>(FaultClass::kOffMap)] = FaultResponseKind::kReplanFromPose;
        limits.attemptMemory = 5000 * kMs;
        limits.driveLostSettle = 500 * kMs;
        in.haveDrives = true;
        in.autonomous = true;
        for (DriveHealth& h : in.health) {
            h = DriveHealth::kOperational;
        }
    }
    // One run at the clock's time; the actions of that run stay in `out`.
    void step() {
        in.now = clock.now();
        out = ResponderActions{};
        responder.step(in, limits, &out);
    }
    // Runs frame by frame for `ns`; returns how many drive actions were asked for.
    std::size_t runFor(core::TimeNs ns, std::size_t* callHomes = nullptr) {
        std::size_t actions = 0;
        for (core::TimeNs t = 0; t < ns; t += kFrame) {
            clock.advance(kFrame);
            step();
            actions += out.driveActions.size();
            if (callHomes != nullptr && out.callHome) {
                ++*callHomes;
            }
        }
        return actions;
    }
    bool held(std::uint32_t reason) const { return (out.holdReasons & (1u << reason)) != 0; }
    unsigned drain(core::EventId id) { return test::drainEventsWithId(events, id); }
};

}  // namespace

TEST_GROUP(FaultResponder){};

TEST(FaultResponder, ALostDriveIsHeldAtOnceGivenItsSettleTimeThenResetAndResumedWhenHealthy) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kDriveHeartbeatLost + 2);
    rig.in.health[2] = DriveHealth::kLost;
    rig.step();
    CHECK(rig.held(msg::hold::kDriveRecovery));  // the e-stop hold in the run that sees the fault
    LONGS_EQUAL(0, rig.out.driveActions.size());
    LONGS_EQUAL(static_cast<int>(ResponseState::kSettling), static_cast<int>(rig.responder.wheel(2)->state));

    // Nothing is done to the drive before heartbeat_loss_ms: a short gap heals alone.
    LONGS_EQUAL(0, rig.runFor(480 * kMs));
    rig.runFor(30 * kMs);
    LONGS_EQUAL(static_cast<int>(ResponseState::kWaiting), static_cast<int>(rig.responder.wheel(2)->state));
    LONGS_EQUAL(1, rig.responder.wheel(2)->attemptsUsed);
    LONGS_EQUAL(static_cast<int>(DriveRecoveryAction::kResetNode), rig.responder.wheel(2)->lastAction);

    // The drive reboots and comes back; the interlock latched meanwhile.
    rig.in.activeFaults = 0;
    rig.in.health[2] = DriveHealth::kOperational;
    rig.in.interlockTripped = true;
    rig.clock.advance(kFrame);
    rig.step();
    CHECK(rig.held(msg::hold::kDriveRecovery));  // still held until the interlock is released
    LONGS_EQUAL(1, rig.out.driveActions.size());
    LONGS_EQUAL(static_cast<int>(DriveRecoveryAction::kResetInterlock), static_cast<int>(rig.out.driveActions.at(0)->action));
    rig.in.interlockTripped = false;
    rig.clock.advance(kFrame);
    rig.step();
    LONGS_EQUAL(0, rig.out.holdReasons);
    LONGS_EQUAL(static_cast<int>(ResponseState::kRecovered), static_cast<int>(rig.responder.wheel(2)->state));
    LONGS_EQUAL(1, rig.responder.recoveries());
}

TEST(FaultResponder, AHeartbeatGapShorterThanTheSettleTimeIsHeldButNeverReset) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kDriveHeartbeatLost + 0);
    rig.step();
    CHECK(rig.held(msg::hold::kDriveRecovery));
    LONGS_EQUAL(0, rig.runFor(200 * kMs));
    rig.in.activeFaults = 0;
    rig.step();
    LONGS_EQUAL(0, rig.out.holdReasons);
    LONGS_EQUAL(0, rig.responder.actionsSent());
    LONGS_EQUAL(static_cast<int>(ResponseState::kRecovered), static_cast<int>(rig.responder.wheel(0)->state));
}

TEST(FaultResponder, AFaultedDriveGetsAFaultResetThenNodeResetsThenIsDeclaredFailedWithoutACallHome) {
    Rig rig;
    rig.in.health[4] = DriveHealth::kFailed;  // the CAN master's own fault resets are spent
    rig.step();
    // Failed: no settle wait, the first try goes out at once.
    LONGS_EQUAL(1, rig.out.driveActions.size());
    LONGS_EQUAL(static_cast<int>(DriveRecoveryAction::kFaultReset), static_cast<int>(rig.out.driveActions.at(0)->action));
    LONGS_EQUAL(4, rig.out.driveActions.at(0)->wheel);
    std::size_t callHomes = 0;
    // Then one node reset per max_wait_ms while it stays failed, up to the 3 tries.
    LONGS_EQUAL(2, rig.runFor(2500 * kMs, &callHomes));
    LONGS_EQUAL(static_cast<int>(DriveRecoveryAction::kResetNode), rig.responder.wheel(4)->lastAction);
    rig.runFor(600 * kMs, &callHomes);
    LONGS_EQUAL(static_cast<int>(ResponseState::kGaveUp), static_cast<int>(rig.responder.wheel(4)->state));
    LONGS_EQUAL(3, rig.responder.wheel(4)->attemptsUsed);
    LONGS_EQUAL(0, callHomes);  // the deliberative layer decides (replan or call home)
    LONGS_EQUAL(0, rig.out.holdReasons);
    cmdtlm::event_data::FAULT_GAVE_UP gaveUp;  // what the ground reads
    CHECK_TRUE(test::lastEventData(rig.events, fault_protection::events::kGaveUp, &gaveUp));
    DOUBLES_EQUAL(static_cast<double>(FaultClass::kDriveFaulted), gaveUp.fault_class, 0.0);
    DOUBLES_EQUAL(msg::fault::kDriveHeartbeatLost + 4, gaveUp.fault_id, 0.0);
    DOUBLES_EQUAL(4.0, gaveUp.wheel, 0.0);
    DOUBLES_EQUAL(3.0, gaveUp.attempts, 0.0);
    DOUBLES_EQUAL(0.0, gaveUp.call_home, 0.0);
}

static_assert(cmdtlm::event_data::FAULT_GAVE_UP::kFirstId == fault_protection::events::kGaveUp &&
                  cmdtlm::event_data::FAULT_GAVE_UP::kLastId == fault_protection::events::kGaveUp,
              "933");
static_assert(cmdtlm::event_data::FAULT_CALL_HOME::kFirstId == fault_protection::events::kCallHome &&
                  cmdtlm::event_data::FAULT_CALL_HOME::kLastId == fault_protection::events::kCallHome,
              "941");

TEST(FaultResponder, DriveRestartAttemptsComeFromTheTable) {
    Rig rig;
    rig.limits.attempts[static_cast<std::size_t>(FaultClass::kDriveFaulted)] = 1;
    rig.in.health[1] = DriveHealth::kFailed;
    rig.step();
    LONGS_EQUAL(1, rig.out.driveActions.size());
    LONGS_EQUAL(0, rig.runFor(1100 * kMs));  // no second try
    LONGS_EQUAL(static_cast<int>(ResponseState::kGaveUp), static_cast<int>(rig.responder.wheel(1)->state));
}

TEST(FaultResponder, HoldsApplyOnlyInAutonomousAndReleaseWhenTheFaultClears) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kPoseUncertain);
    rig.in.autonomous = false;
    rig.step();
    LONGS_EQUAL(0, rig.out.holdReasons);
    rig.in.autonomous = true;
    rig.step();
    CHECK(rig.held(msg::hold::kPoseUncertain));
    rig.runFor(500 * kMs);
    CHECK(rig.held(msg::hold::kPoseUncertain));
    rig.in.activeFaults = 0;
    rig.step();
    LONGS_EQUAL(0, rig.out.holdReasons);
    LONGS_EQUAL(1, rig.responder.recoveries());
}

TEST(FaultResponder, AHoldThatOutlastsItsTriesCallsHomeOnce) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kBatteryLow);
    rig.step();
    CHECK(rig.held(msg::hold::kBatteryLow));
    std::size_t callHomes = 0;
    rig.runFor(2900 * kMs, &callHomes);  // 3 tries x 1000 ms
    LONGS_EQUAL(0, callHomes);
    rig.runFor(200 * kMs, &callHomes);
    LONGS_EQUAL(1, callHomes);
    rig.runFor(5000 * kMs, &callHomes);
    LONGS_EQUAL(1, callHomes);
}

TEST(FaultResponder, MaxWaitComesFromTheTable) {
    Rig rig;
    rig.limits.maxWait[static_cast<std::size_t>(FaultClass::kBatteryLow)] = 200 * kMs;
    rig.in.activeFaults = bitOf(msg::fault::kBatteryLow);
    rig.step();
    std::size_t callHomes = 0;
    rig.runFor(700 * kMs, &callHomes);
    LONGS_EQUAL(1, callHomes);
}

TEST(FaultResponder, ResponseKindsFromTheTable) {
    Rig rig;
    rig.limits.response[static_cast<std::size_t>(FaultClass::kPoseUncertain)] = FaultResponseKind::kEventOnly;
    rig.limits.response[static_cast<std::size_t>(FaultClass::kBusOvercurrent)] = FaultResponseKind::kSafeAndCallHome;
    rig.in.activeFaults = bitOf(msg::fault::kPoseUncertain);
    std::size_t callHomes = 0;
    rig.runFor(5000 * kMs, &callHomes);
    LONGS_EQUAL(0, rig.out.holdReasons);
    LONGS_EQUAL(0, callHomes);
    LONGS_EQUAL(1, rig.drain(fault_protection::events::kResponseStarted));
    rig.in.activeFaults |= bitOf(msg::fault::kBusOvercurrent);
    rig.step();
    CHECK(rig.out.callHome);
}

TEST(FaultResponder, AKindThatCannotApplyToItsClassHoldsInstead) {
    Rig rig;
    rig.limits.response[static_cast<std::size_t>(FaultClass::kBatteryLow)] = FaultResponseKind::kRecoverDrive;
    rig.in.activeFaults = bitOf(msg::fault::kBatteryLow);
    rig.step();
    CHECK(rig.held(msg::hold::kBatteryLow));
    LONGS_EQUAL(0, rig.out.driveActions.size());
}

TEST(FaultResponder, AStalledTaskIsRestartedThenCallsHomeWhenItStaysStalled) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kTaskStalled + 5);
    rig.step();
    LONGS_EQUAL(1, rig.out.taskRestarts.size());
    LONGS_EQUAL(5, *rig.out.taskRestarts.at(0));
    CHECK(rig.held(msg::hold::kTaskRestart));
    std::size_t callHomes = 0;
    rig.runFor(3100 * kMs, &callHomes);
    LONGS_EQUAL(3, rig.responder.fault(msg::fault::kTaskStalled + 5)->attemptsUsed);
    LONGS_EQUAL(1, callHomes);
}

TEST(FaultResponder, AStalledTaskThatRunsAgainIsRecovered) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kTaskStalled + 1);
    rig.step();
    rig.runFor(100 * kMs);
    rig.in.activeFaults = 0;
    rig.step();
    LONGS_EQUAL(0, rig.out.holdReasons);
    LONGS_EQUAL(static_cast<int>(ResponseState::kRecovered),
                static_cast<int>(rig.responder.fault(msg::fault::kTaskStalled + 1)->state));
}

TEST(FaultResponder, AttemptsAreRememberedForAttemptMemoryThenForgotten) {
    Rig rig;
    rig.limits.attempts[static_cast<std::size_t>(FaultClass::kPoseUncertain)] = 1;
    auto occurrence = [&rig](core::TimeNs lasting) {
        rig.in.activeFaults = bitOf(msg::fault::kPoseUncertain);
        rig.runFor(lasting);
        rig.in.activeFaults = 0;
        rig.step();
    };
    occurrence(100 * kMs);
    // Back within attempt_memory_ms with its one try used: gives up at once.
    rig.clock.advance(1000 * kMs);
    rig.in.activeFaults = bitOf(msg::fault::kPoseUncertain);
    rig.step();
    CHECK(rig.out.callHome);
    rig.in.activeFaults = 0;
    rig.step();
    // Clear for longer than the memory: a fresh try.
    rig.runFor(5100 * kMs);
    rig.in.activeFaults = bitOf(msg::fault::kPoseUncertain);
    rig.step();
    CHECK_FALSE(rig.out.callHome);
    CHECK(rig.held(msg::hold::kPoseUncertain));
}

TEST(FaultResponder, ConflictingDriveReportsTakeTheFault) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kDriveHeartbeatLost + 3);  // status still says operational
    rig.step();
    CHECK(rig.held(msg::hold::kDriveRecovery));
    LONGS_EQUAL(1, rig.responder.conflicts());
    LONGS_EQUAL(1, rig.drain(fault_protection::events::kConflictingReport));
}

TEST(FaultResponder, ALatchedInterlockWithEveryDriveHealthyIsResetEvenWithoutAResponse) {
    Rig rig;
    rig.in.interlockTripped = true;
    rig.step();
    LONGS_EQUAL(1, rig.out.driveActions.size());
    LONGS_EQUAL(static_cast<int>(DriveRecoveryAction::kResetInterlock), static_cast<int>(rig.out.driveActions.at(0)->action));
    rig.clock.advance(kFrame);
    rig.step();
    LONGS_EQUAL(0, rig.out.driveActions.size());  // asked again only after kInterlockResetRetry
    rig.in.health[0] = DriveHealth::kFaulted;
    rig.runFor(500 * kMs);
    CHECK(rig.held(msg::hold::kDriveRecovery));
}

TEST(FaultResponder, OffTheMapAsksForAReplanEachTryWithoutAHoldThenCallsHome) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kOffMap);
    rig.step();
    LONGS_EQUAL(1, rig.out.replans.size());
    LONGS_EQUAL(msg::fault::kOffMap, rig.out.replans.at(0)->faultId);
    LONGS_EQUAL(1, rig.out.replans.at(0)->attempt);
    LONGS_EQUAL(0, rig.out.holdReasons);  // the rover must drive to get back on
    LONGS_EQUAL(3, rig.responder.fault(msg::fault::kOffMap)->lastAction);
    LONGS_EQUAL(1, rig.drain(fault_protection::events::kReplanRequested));

    // Still off after max_wait_ms: another replan; after the third try, call home.
    std::size_t replans = 0;
    std::size_t callHomes = 0;
    for (core::TimeNs t = 0; t < 3100 * kMs; t += kFrame) {
        rig.clock.advance(kFrame);
        rig.step();
        replans += rig.out.replans.size();
        callHomes += rig.out.callHome ? 1U : 0U;
        LONGS_EQUAL(0, rig.out.holdReasons);
    }
    LONGS_EQUAL(2, replans);
    LONGS_EQUAL(1, callHomes);
    LONGS_EQUAL(static_cast<int>(ResponseState::kGaveUp),
                static_cast<int>(rig.responder.fault(msg::fault::kOffMap)->state));
}

TEST(FaultResponder, BackOnTheMapIsARecoveryAndNoReplanIsAskedOutsideAutonomous) {
    Rig rig;
    rig.in.activeFaults = bitOf(msg::fault::kOffMap);
    rig.step();
    rig.runFor(200 * kMs);
    rig.in.activeFaults = 0;
    rig.step();
    LONGS_EQUAL(static_cast<int>(ResponseState::kRecovered),
                static_cast<int>(rig.responder.fault(msg::fault::kOffMap)->state));

    Rig manual;
    manual.in.autonomous = false;  // no mission to replan: nothing asked, no call home
    manual.in.activeFaults = bitOf(msg::fault::kOffMap);
    std::size_t callHomes = 0;
    manual.step();
    LONGS_EQUAL(0, manual.out.replans.size());
    manual.runFor(5000 * kMs, &callHomes);
    LONGS_EQUAL(0, callHomes);
}

TEST(FaultResponder, AReplanAskedForAnyOtherClassHoldsInsteadAndAHoldOffTheMapHolds) {
    Rig rig;
    rig.limits.response[static_cast<std::size_t>(FaultClass::kSensorLost)] = FaultResponseKind::kReplanFromPose;
    rig.in.activeFaults = bitOf(msg::fault::kSensorStale + 2);
    rig.step();
    CHECK(rig.held(msg::hold::kSensorLost));
    LONGS_EQUAL(0, rig.out.replans.size());

    Rig hold;
    hold.limits.response[static_cast<std::size_t>(FaultClass::kOffMap)] = FaultResponseKind::kHoldUntilClear;
    hold.in.activeFaults = bitOf(msg::fault::kOffMap);
    hold.step();
    CHECK(hold.held(msg::hold::kOffMap));
    LONGS_EQUAL(0, hold.out.replans.size());
}

TEST(FaultResponder, LimitsAreTheTablesFields) {
    core::VirtualClock clock;
    core::EventLog events(clock);
    tables::FaultProtectionTable protection{};
    tables::FaultResponseTable faults{};
    for (std::size_t c = 0; c < msg::kFaultClassCount; ++c) {
        protection.response[c] = static_cast<std::uint8_t>(c % 6);
        protection.attempts[c] = static_cast<std::uint8_t>(c + 1);
        protection.max_wait_ms[c] = static_cast<std::uint32_t>(100 * (c + 1));
    }
    protection.attempt_memory_ms = 7000;
    faults.heartbeat_loss_ms = 321;
    const ResponderLimits l = fault_protection::responderLimitsFrom(protection, faults);
    for (std::size_t c = 0; c < msg::kFaultClassCount; ++c) {
        LONGS_EQUAL(c % 6, static_cast<int>(l.response[c]));
        LONGS_EQUAL(c + 1, l.attempts[c]);
        CHECK_EQUAL(static_cast<core::TimeNs>(100 * (c + 1)) * kMs, l.maxWait[c]);
    }
    CHECK_EQUAL(7000 * kMs, l.attemptMemory);
    CHECK_EQUAL(321 * kMs, l.driveLostSettle);
}

TEST(FaultResponder, HeartbeatLossMsSetsHowLongALostDriveIsLeftAlone) {
    Rig rig;
    rig.limits.driveLostSettle = 100 * kMs;
    rig.in.activeFaults = bitOf(msg::fault::kDriveHeartbeatLost + 5);
    rig.step();
    LONGS_EQUAL(1, rig.runFor(120 * kMs));
}

TEST(FaultResponder, EveryFaultIdHasAClass) {
    for (std::uint8_t id = 1; id < msg::fault::kCount; ++id) {
        FaultClass c{};
        CHECK_TEXT(fault_protection::classOf(id, &c), "a fault id no response covers");
    }
    FaultClass c{};
    CHECK_FALSE(fault_protection::classOf(0, &c));
    CHECK_FALSE(fault_protection::classOf(msg::fault::kCount, &c));
}

TEST(FaultResponder, AnEventOnlyFaultThatComesAndGoesNeverCallsHome) {
    Rig rig;
    rig.limits.response[static_cast<std::size_t>(FaultClass::kDriveOvercurrent)] = FaultResponseKind::kEventOnly;
    std::size_t callHomes = 0;
    for (int i = 0; i < 10; ++i) {
        rig.in.activeFaults = bitOf(msg::fault::kDriveOvercurrent + 1);
        rig.runFor(300 * kMs, &callHomes);
        CHECK_EQUAL(0u, rig.out.holdReasons);
        rig.in.activeFaults = 0;
        rig.runFor(100 * kMs, &callHomes);
    }
    LONGS_EQUAL(0, callHomes);
    LONGS_EQUAL(10, rig.drain(fault_protection::events::kResponseStarted));
}

TEST(FaultResponder, ADriveThatKeepsFaultingAndRecoveringByItselfIsGivenUpAndItsInterlockLeftLatched) {
    Rig rig;
    unsigned interlockAsks = 0;
    for (int trip = 0; trip < 6; ++trip) {
        rig.in.health[1] = DriveHealth::kFaulted;  // trips, the CAN master's own reset clears it
        rig.in.interlockTripped = true;
        rig.runFor(50 * kMs);
        rig.in.health[1] = DriveHealth::kOperational;
        for (int f = 0; f < 30; ++f) {
            rig.clock.advance(kFrame);
            rig.step();
            for (std::size_t i = 0; i < rig.out.driveActions.size(); ++i) {
                if (rig.out.driveActions.at(i)->action == DriveRecoveryAction::kResetInterlock) {
                    ++interlockAsks;
                    rig.in.interlockTripped = false;  // CAN I/O releases it
                }
            }
        }
    }
    // Occurrences 1..4 are recovered (the 2nd..4th spend a try each); the 5th
    // finds the tries used: declared failed, the interlock left latched.
    LONGS_EQUAL(static_cast<int>(ResponseState::kGaveUp), static_cast<int>(rig.responder.wheel(1)->state));
    LONGS_EQUAL(4, interlockAsks);
    CHECK(rig.in.interlockTripped);
    LONGS_EQUAL(0, rig.out.holdReasons);
}

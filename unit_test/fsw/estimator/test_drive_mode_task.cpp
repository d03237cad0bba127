// The drive mode task on the bus, fed by a drive model with the simulator's lag,
// current law and noise: false alarms, detection of degradation, failure and
// unmodelled faults, the time bounds documented in drive_mode_estimator.hpp,
// events, malformed input, table changes and the heap.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/estimator/drive_mode_events.hpp"
#include "fsw/estimator/drive_mode_task.hpp"
#include "fsw/tables/table_image.hpp"
#include "unit_test/fsw/estimator/drive_mode_rig.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using estimator::CurrentReading;
using estimator::FaultReading;
using estimator::TrackReading;
using msg::DriveMode;
using test::DriveModeRig;

namespace {

constexpr core::TimeNs kMs = core::kNsPerMs;
constexpr core::TimeNs kSec = core::kNsPerSec;
// The documented bounds (drive_mode_estimator.hpp).
constexpr core::TimeNs kDegradedBound = 600 * kMs;
constexpr core::TimeNs kFailedBound = 500 * kMs;

struct SeenEvent {
    core::EventId id;
    core::Severity severity;
    std::string text;
    core::EventData data;
};

std::vector<SeenEvent> drain(core::EventLog& log) {
    std::vector<SeenEvent> out;
    core::Event e;
    while (core::isOk(log.pop(&e))) {
        out.push_back({e.id, e.severity, e.text, e.data});
    }
    return out;
}

std::vector<SeenEvent> modeEvents(const std::vector<SeenEvent>& all) {
    std::vector<SeenEvent> out;
    for (const SeenEvent& e : all) {
        if (e.id >= estimator::events::kDriveModeDeclaredNominal &&
            e.id <= estimator::events::kDriveModeDeclaredUnknown) {
            out.push_back(e);
        }
    }
    return out;
}

bool contains(const std::string& text, const char* part) { return text.find(part) != std::string::npos; }

// Runs frames until wheel's declared mode is `mode` or `limit` passes; returns
// the time taken from the call, or -1.
core::TimeNs timeUntilDeclared(DriveModeRig& rig, std::size_t wheel, DriveMode mode, core::TimeNs limit,
                               bool* othersNominal) {
    const core::TimeNs start = rig.drives.now();
    while (rig.drives.now() - start < limit) {
        rig.frame();
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            if (w != wheel && rig.task.declared(w) != DriveMode::kNominal) {
                *othersNominal = false;
            }
        }
        if (rig.task.declared(wheel) == mode) {
            return rig.drives.now() - start;
        }
    }
    return -1;
}

}  // namespace

TEST_GROUP(DriveModeTask) {
    void setup() override {}
};

TEST(DriveModeTask, PublishesTheBeliefsEveryTenthFrameStartingNominal) {
    DriveModeRig rig(1);
    CHECK_TRUE(rig.init());
    CHECK(DriveMode::kNominal == rig.task.declared(0));
    CHECK(DriveMode::kUnknown == rig.task.declared(msg::kWheelCount));  // out of range
    DOUBLES_EQUAL(1.0, rig.task.latest().drives[5].powerFactor, 0.0);
    CHECK(rig.task.latest().drives[5].probability[0] > 0.999F);
    LONGS_EQUAL(0, rig.task.latest().updates);

    rig.drives.command(1.0, 1.0);
    for (int i = 0; i < 9; ++i) {
        rig.frame();
    }
    LONGS_EQUAL(0, rig.published);
    rig.frame();
    LONGS_EQUAL(1, rig.published);
    LONGS_EQUAL(1, rig.lastPublished.updates);
    LONGS_EQUAL(rig.clock.now(), rig.lastPublished.timeNs);
    rig.runFor(1 * kSec);
    LONGS_EQUAL(11, rig.published);
    LONGS_EQUAL(11, rig.task.updates());
    LONGS_EQUAL(110, rig.task.statusesTaken());
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        float sum = 0.0F;
        for (float p : rig.lastPublished.drives[w].probability) {
            sum += p;
        }
        DOUBLES_EQUAL(1.0, sum, 1e-5);
        CHECK(DriveMode::kNominal == rig.lastPublished.drives[w].declared);
    }
    CHECK(0 == std::memcmp(&rig.lastPublished, &rig.task.latest(), sizeof(msg::DriveModesMsg)));
}

TEST(DriveModeTask, ThirtyMinutesOfNominalDrivingRaiseNoAlarm) {
    DriveModeRig rig(2024);
    CHECK_TRUE(rig.init());
    test::DriveProfile profile(2024);
    const core::TimeNs end = 30 * 60 * kSec;
    unsigned alarms = 0;
    unsigned trackingReadings = 0;
    unsigned currentReadings = 0;
    unsigned idleReadings = 0;
    double maxNotNominal = 0.0;
    double minFactor = 10.0;
    double maxFactor = 0.0;
    std::uint32_t lastUpdate = 0;
    while (rig.drives.now() < end) {
        profile.apply(rig.drives.now(), &rig.drives);
        rig.frame();
        if (rig.task.updates() == lastUpdate) {
            continue;
        }
        lastUpdate = rig.task.updates();
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            alarms += rig.task.declared(w) != DriveMode::kNominal ? 1U : 0U;
            const estimator::DriveObservation& o = rig.task.estimator().lastObservation(w);
            trackingReadings += o.track == TrackReading::kTracking ? 1U : 0U;
            CHECK(o.track != TrackReading::kStall);
            currentReadings += o.current != CurrentReading::kNone ? 1U : 0U;
            idleReadings += o.track == TrackReading::kNone ? 1U : 0U;
            maxNotNominal = std::fmax(maxNotNominal, 1.0 - rig.task.latest().drives[w].probability[0]);
            minFactor = std::fmin(minFactor, rig.task.latest().drives[w].powerFactor);
            maxFactor = std::fmax(maxFactor, rig.task.latest().drives[w].powerFactor);
        }
    }
    LONGS_EQUAL(0, alarms);
    LONGS_EQUAL(0, modeEvents(drain(rig.events)).size());
    LONGS_EQUAL(0, rig.task.modeChanges());
    CHECK(maxNotNominal < 0.5);
    CHECK(minFactor > 0.96);
    CHECK(maxFactor < 1.04);
    // The run really gave evidence (and some idle time): the test could fail.
    const unsigned readings = 6U * rig.task.updates();
    CHECK(trackingReadings > readings / 2);
    CHECK(currentReadings > readings / 2);
    CHECK(idleReadings > readings / 20);
    LONGS_EQUAL(0, rig.task.malformed());
    LONGS_EQUAL(0, rig.task.windowsWithoutStatus());
}

TEST(DriveModeTask, DegradationIsDeclaredWithinTheBoundAndThePowerFactorFollows) {
    // Every phase of the onset against the 100 ms update window.
    for (int phase = 0; phase < 10; ++phase) {
        DriveModeRig rig(100 + static_cast<std::uint64_t>(phase));
        CHECK_TRUE(rig.init());
        const std::size_t wheel = static_cast<std::size_t>(phase) % msg::kWheelCount;
        rig.drives.command(1.8, 2.3);
        rig.runFor(10 * kSec + phase * 10 * kMs);
        LONGS_EQUAL(0, modeEvents(drain(rig.events)).size());
        rig.drives.degrade(wheel, 1.5);
        bool othersNominal = true;
        const core::TimeNs latency = timeUntilDeclared(rig, wheel, DriveMode::kDegraded, 5 * kSec, &othersNominal);
        CHECK(latency > 0);
        CHECK(latency <= kDegradedBound);
        // Several readings, not the first one: one noisy window is no alarm.
        CHECK(latency >= 200 * kMs);
        rig.runFor(10 * kSec);
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            if (w != wheel) {
                CHECK(rig.task.declared(w) == DriveMode::kNominal);
                DOUBLES_EQUAL(1.0, rig.task.latest().drives[w].powerFactor, 0.04);
            }
        }
        CHECK(othersNominal);
        CHECK(DriveMode::kDegraded == rig.task.declared(wheel));
        DOUBLES_EQUAL(1.5, rig.task.latest().drives[wheel].powerFactor, 0.075);
        const std::vector<SeenEvent> events = modeEvents(drain(rig.events));
        LONGS_EQUAL(1, events.size());
        LONGS_EQUAL(estimator::events::kDriveModeDeclaredDegraded, events[0].id);
        CHECK(core::Severity::kWarning == events[0].severity);
        const std::string expected = std::string("drive_modes: ") + msg::wheelName(wheel) +
                                     " nominal -> degraded";
        CHECK(contains(events[0].text, expected.c_str()));
    }
}

TEST(DriveModeTask, FailureIsDeclaredWithinTheBoundAndTheOthersStayNominal) {
    for (int phase = 0; phase < 10; ++phase) {
        DriveModeRig rig(200 + static_cast<std::uint64_t>(phase));
        CHECK_TRUE(rig.init());
        const std::size_t wheel = static_cast<std::size_t>(phase + 3) % msg::kWheelCount;
        rig.drives.command(2.2, 1.6);
        rig.runFor(10 * kSec + phase * 10 * kMs);
        rig.drives.failMotor(wheel);
        bool othersNominal = true;
        const core::TimeNs latency = timeUntilDeclared(rig, wheel, DriveMode::kFailed, 5 * kSec, &othersNominal);
        CHECK(latency > 0);
        CHECK(latency <= kFailedBound);
        CHECK(rig.drives.interlockTripped());  // the wheels were idle: the fault report decided
        rig.runFor(3 * kSec);
        CHECK(DriveMode::kFailed == rig.task.declared(wheel));
        CHECK(othersNominal);
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            CHECK(w == wheel || rig.task.declared(w) == DriveMode::kNominal);
        }
        const std::vector<SeenEvent> events = modeEvents(drain(rig.events));
        LONGS_EQUAL(1, events.size());  // straight to failed, nothing in between
        LONGS_EQUAL(estimator::events::kDriveModeDeclaredFailed, events[0].id);
        CHECK(core::Severity::kError == events[0].severity);
        const std::string expected = std::string(msg::wheelName(wheel)) + " nominal -> failed";
        CHECK(contains(events[0].text, expected.c_str()));
    }
}

TEST(DriveModeTask, DegradationThenFailureIsDeclaredDegradedFirstThenFailed) {
    DriveModeRig rig(300);
    CHECK_TRUE(rig.init());
    rig.drives.command(1.5, 1.5);
    rig.runFor(5 * kSec);
    rig.drives.degrade(2, 1.3);  // the mildest the benchmark injects
    bool othersNominal = true;
    CHECK(timeUntilDeclared(rig, 2, DriveMode::kDegraded, 3 * kSec, &othersNominal) > 0);
    rig.runFor(20 * kSec);
    CHECK(DriveMode::kDegraded == rig.task.declared(2));
    DOUBLES_EQUAL(1.3, rig.task.latest().drives[2].powerFactor, 0.065);
    rig.drives.failMotor(2);
    const core::TimeNs latency = timeUntilDeclared(rig, 2, DriveMode::kFailed, 3 * kSec, &othersNominal);
    CHECK(latency > 0 && latency <= kFailedBound);
    CHECK(othersNominal);
    const std::vector<SeenEvent> events = modeEvents(drain(rig.events));
    LONGS_EQUAL(2, events.size());
    LONGS_EQUAL(estimator::events::kDriveModeDeclaredDegraded, events[0].id);
    LONGS_EQUAL(estimator::events::kDriveModeDeclaredFailed, events[1].id);
    CHECK(contains(events[1].text, "RL degraded -> failed"));
    // The numbers the ground reads: the wheel, the modes, the estimate.
    cmdtlm::event_data::DRIVE_MODE_DECLARED declared;
    CHECK_TRUE(declared.unpack(events[1].id, events[1].data));
    DOUBLES_EQUAL(2.0, declared.wheel, 0.0);
    DOUBLES_EQUAL(static_cast<double>(DriveMode::kDegraded), declared.from, 0.0);
    DOUBLES_EQUAL(static_cast<double>(DriveMode::kFailed), declared.to, 0.0);
    CHECK(declared.probability > 0.5 && declared.probability <= 1.0);
    CHECK(declared.power_factor > 1.0);
    CHECK_TRUE(declared.unpack(events[0].id, events[0].data));
    DOUBLES_EQUAL(static_cast<double>(DriveMode::kDegraded), declared.to, 0.0);
    LONGS_EQUAL(2, rig.task.modeChanges());
}

TEST(DriveModeTask, AStallWithHighCurrentAndNoFaultReportIsUnknown) {
    DriveModeRig rig(400);
    CHECK_TRUE(rig.init());
    rig.drives.command(1.5, 1.5);
    rig.runFor(5 * kSec);
    rig.drives.jam(4, 0.3);  // held at 0 while the motor pushes: about twice the current, no fault
    bool othersNominal = true;
    const core::TimeNs latency = timeUntilDeclared(rig, 4, DriveMode::kUnknown, 5 * kSec, &othersNominal);
    CHECK(latency > 0 && latency <= 2 * kSec);
    rig.runFor(30 * kSec);  // persistently: it stays unknown
    CHECK(DriveMode::kUnknown == rig.task.declared(4));
    CHECK(othersNominal);
    const estimator::DriveObservation& o = rig.task.estimator().lastObservation(4);
    CHECK(TrackReading::kStall == o.track);
    CHECK(CurrentReading::kHigh == o.current);
    CHECK(FaultReading::kNo == o.fault);
    const std::vector<SeenEvent> events = modeEvents(drain(rig.events));
    CHECK(!events.empty());
    LONGS_EQUAL(estimator::events::kDriveModeDeclaredUnknown, events.back().id);
    CHECK(core::Severity::kError == events.back().severity);
    CHECK(contains(events.back().text, "MR "));
    CHECK(contains(events.back().text, "-> unknown"));
}

TEST(DriveModeTask, IdleWheelsGiveNoTrackingOrCurrentEvidence) {
    DriveModeRig rig(500);
    CHECK_TRUE(rig.init());
    rig.drives.setHealth(5, msg::DriveHealth::kLost);  // and a lost drive no fault evidence either
    rig.runFor(100 * kMs);
    const tables::DriveHealthModelTable& model = rig.tables.driveHealthModel();
    for (int update = 0; update < 20; ++update) {
        double before[msg::kWheelCount][msg::kDriveModeCount];
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            for (std::size_t m = 0; m < msg::kDriveModeCount; ++m) {
                before[w][m] = rig.task.estimator().drive(w).probability(static_cast<DriveMode>(m));
            }
        }
        rig.runFor(100 * kMs);
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            const estimator::DriveObservation& o = rig.task.estimator().lastObservation(w);
            CHECK(TrackReading::kNone == o.track);
            CHECK(CurrentReading::kNone == o.current);
            CHECK((w == 5 ? FaultReading::kNone : FaultReading::kNo) == o.fault);
            double expected[msg::kDriveModeCount] = {};
            double total = 0.0;
            for (std::size_t to = 0; to < msg::kDriveModeCount; ++to) {
                for (std::size_t from = 0; from < msg::kDriveModeCount; ++from) {
                    expected[to] += before[w][from] * estimator::transitionProbability(static_cast<DriveMode>(from),
                                                                                       static_cast<DriveMode>(to), model);
                }
                expected[to] *= estimator::observationLikelihood(static_cast<DriveMode>(to), o, model);
                total += expected[to];
            }
            for (std::size_t m = 0; m < msg::kDriveModeCount; ++m) {
                const double got = rig.task.estimator().drive(w).probability(static_cast<DriveMode>(m));
                DOUBLES_EQUAL(std::fmax(expected[m] / total, estimator::kProbabilityFloor), got, 1e-9);
            }
            DOUBLES_EQUAL(1.0, rig.task.estimator().drive(w).powerFactor(), 0.0);
        }
    }
    // The lost drive's belief moved by the transitions alone: degraded grew.
    CHECK(rig.task.estimator().drive(5).probability(DriveMode::kDegraded) > 10 * model.p_degrade);
}

TEST(DriveModeTask, OneSideIdleWhileTheOtherDrivesAndStepsDoNotReadAsStalls) {
    DriveModeRig rig(600);
    CHECK_TRUE(rig.init());
    rig.drives.command(0.0, 3.0);  // a pivot: left idle, right a 3 rad/s step
    rig.runFor(60 * kMs);
    // Inside the settling time after the step the right side gives no evidence...
    rig.runFor(40 * kMs);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        CHECK(TrackReading::kNone == rig.task.estimator().lastObservation(w).track);
    }
    rig.runFor(1 * kSec);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const estimator::DriveObservation& o = rig.task.estimator().lastObservation(w);
        if (w < 3) {
            CHECK(TrackReading::kNone == o.track);
            CHECK(CurrentReading::kNone == o.current);
        } else {
            CHECK(TrackReading::kTracking == o.track);
            CHECK(CurrentReading::kNormal == o.current);  // two reference wheels each
            DOUBLES_EQUAL(1.0, o.currentRatio, 0.05);
        }
    }
    // ...and a reversal (3 -> -3 rad/s) is lag, not a stall.
    for (int i = 0; i < 20; ++i) {
        rig.drives.command(i % 2 == 0 ? 3.0 : -3.0, i % 2 == 0 ? -3.0 : 3.0);
        rig.runFor(400 * kMs);
    }
    LONGS_EQUAL(0, rig.task.modeChanges());
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        CHECK(rig.task.estimator().drive(w).probability(DriveMode::kNominal) > 0.99);
    }
}

TEST(DriveModeTask, AccelerationCurrentIsComparedOnlyBetweenWheelsTakingTheSameStep) {
    DriveModeRig rig(650);
    CHECK_TRUE(rig.init());
    rig.runFor(1 * kSec);
    rig.drives.degrade(4, 1.5);  // while stopped: no evidence yet
    rig.runFor(1 * kSec);
    LONGS_EQUAL(0, rig.task.modeChanges());
    // From standstill into a turn: the right side accelerates three times as hard
    // as the left, so its acceleration current is far above the left side's.
    rig.drives.command(1.0, 3.0);
    rig.runFor(100 * kMs);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const estimator::DriveObservation& o = rig.task.estimator().lastObservation(w);
        CHECK(TrackReading::kNone == o.track);  // all settling: no tracking evidence
        CHECK(o.currentFrames >= 3);
        if (w == 4) {
            CHECK(CurrentReading::kHigh == o.current);
            DOUBLES_EQUAL(1.5, o.currentRatio, 0.1);
        } else if (w < 3) {
            CHECK(CurrentReading::kNormal == o.current);
            DOUBLES_EQUAL(1.0, o.currentRatio, 0.08);
        } else {
            // Two references, one the degraded wheel: their median is their mean,
            // 1.25 x a healthy draw, so these read low, which is no alarm.
            CHECK(CurrentReading::kNormal == o.current);
            DOUBLES_EQUAL(0.8, o.currentRatio, 0.08);
        }
    }
}

TEST(DriveModeTask, ADrivesOwnOverCurrentTripReadsAsHighCurrent) {
    DriveModeRig rig(660);
    CHECK_TRUE(rig.init());
    rig.runFor(100 * kMs);
    rig.drives.setHealth(1, msg::DriveHealth::kFaulted);
    rig.drives.setEmcy(1, 0x2310);
    rig.drives.setHealth(2, msg::DriveHealth::kFaulted);
    rig.drives.setEmcy(2, 0x4310);  // over-temperature: a fault, not a current reading
    rig.runFor(100 * kMs);
    const estimator::DriveObservation& tripped = rig.task.estimator().lastObservation(1);
    CHECK(FaultReading::kYes == tripped.fault);
    CHECK(CurrentReading::kHigh == tripped.current);
    CHECK_FALSE(tripped.ratioMeasured);  // idle: nothing compared, so no power-factor update
    DOUBLES_EQUAL(1.0, rig.task.estimator().drive(1).powerFactor(), 0.0);
    CHECK(FaultReading::kYes == rig.task.estimator().lastObservation(2).fault);
    CHECK(CurrentReading::kNone == rig.task.estimator().lastObservation(2).current);
    CHECK(CurrentReading::kNone == rig.task.estimator().lastObservation(0).current);
}

TEST(DriveModeTask, EveryDeclaredChangeIsEventedWithItsIdAndSeverity) {
    DriveModeRig rig(700);
    CHECK_TRUE(rig.init());
    rig.drives.command(2.0, 2.0);
    rig.runFor(3 * kSec);
    rig.drives.degrade(0, 1.8);
    rig.runFor(3 * kSec);
    rig.drives.degrade(0, 1.0);  // e.g. a thermal degradation that went away
    bool othersNominal = true;
    CHECK(timeUntilDeclared(rig, 0, DriveMode::kNominal, 10 * kSec, &othersNominal) > 0);
    const std::vector<SeenEvent> events = modeEvents(drain(rig.events));
    LONGS_EQUAL(2, events.size());
    LONGS_EQUAL(761, events[0].id);
    CHECK(core::Severity::kWarning == events[0].severity);
    CHECK(contains(events[0].text, "drive_modes: FL nominal -> degraded (p="));
    CHECK(contains(events[0].text, "power x"));
    LONGS_EQUAL(760, events[1].id);
    CHECK(core::Severity::kInfo == events[1].severity);
    CHECK(contains(events[1].text, "drive_modes: FL degraded -> nominal"));
    LONGS_EQUAL(762, estimator::events::declaredModeEventId(DriveMode::kFailed));
    LONGS_EQUAL(763, estimator::events::declaredModeEventId(DriveMode::kUnknown));
    // One event data layout for the four (dictionary.def: DRIVE_MODE_DECLARED).
    LONGS_EQUAL(estimator::events::kDriveModeDeclaredNominal, cmdtlm::event_data::DRIVE_MODE_DECLARED::kFirstId);
    LONGS_EQUAL(estimator::events::kDriveModeDeclaredUnknown, cmdtlm::event_data::DRIVE_MODE_DECLARED::kLastId);
}

TEST(DriveModeTask, MalformedInputIsCountedAndEventedThrottled) {
    DriveModeRig rig(800);
    CHECK_TRUE(rig.init());
    const std::uint8_t shortPayload[12] = {};
    rig.frameWith(shortPayload, sizeof shortPayload);
    LONGS_EQUAL(1, rig.task.malformed());
    std::vector<SeenEvent> events = drain(rig.events);
    LONGS_EQUAL(1, events.size());
    LONGS_EQUAL(estimator::events::kDriveModeMalformedInput, events[0].id);
    CHECK(core::Severity::kError == events[0].severity);
    CHECK(contains(events[0].text, "drive_modes: "));
    CHECK(contains(events[0].text, "refused: wrong-type"));  // core::InputPipe's wording: it does not decode

    msg::DriveStatusMsg status = rig.drives.step();
    status.wheels[3].velocityRadS = std::numeric_limits<double>::quiet_NaN();
    rig.frameWith(&status, sizeof status);
    status.wheels[3].velocityRadS = 0.0;
    status.wheels[1].health = static_cast<msg::DriveHealth>(42);
    rig.frameWith(&status, sizeof status);
    status.wheels[1].health = msg::DriveHealth::kOperational;
    status.wheels[0].currentA = std::numeric_limits<double>::infinity();
    rig.frameWith(&status, sizeof status);
    LONGS_EQUAL(4, rig.task.malformed());
    LONGS_EQUAL(0, rig.task.statusesTaken());
    events = drain(rig.events);
    unsigned malformedEvents = 0;
    for (const SeenEvent& e : events) {
        malformedEvents += e.id == estimator::events::kDriveModeMalformedInput ? 1U : 0U;
        if (e.id == estimator::events::kDriveModeMalformedInput) {
            CHECK(contains(e.text, "refused: invalid-argument"));  // a non-finite value or a bad health
        }
    }
    LONGS_EQUAL(2, malformedEvents);  // the 2nd and the 4th; the 3rd only counted

    // A zeroed status of the right size is well formed (drives booting): taken.
    std::uint8_t zeroed[sizeof(msg::DriveStatusMsg)] = {};
    rig.frameWith(zeroed, sizeof zeroed);
    LONGS_EQUAL(4, rig.task.malformed());
    LONGS_EQUAL(1, rig.task.statusesTaken());
}

TEST(DriveModeTask, AWindowWithoutDriveStatusIsEventedAndGivesNoEvidence) {
    DriveModeRig rig(900);
    CHECK_TRUE(rig.init());
    for (int i = 0; i < 10; ++i) {
        rig.frameWithoutStatus();
    }
    LONGS_EQUAL(1, rig.task.updates());
    LONGS_EQUAL(1, rig.task.windowsWithoutStatus());
    const std::vector<SeenEvent> events = drain(rig.events);
    LONGS_EQUAL(1, events.size());
    LONGS_EQUAL(estimator::events::kDriveModeNoDriveStatus, events[0].id);
    CHECK(core::Severity::kWarning == events[0].severity);
    CHECK(FaultReading::kNone == rig.task.estimator().lastObservation(0).fault);
}

TEST(DriveModeTask, TheTableIsReadAtEveryUpdate) {
    DriveModeRig rig(1000);
    CHECK_TRUE(rig.init());
    rig.drives.command(2.0, 2.0);
    rig.runFor(1 * kSec);
    CHECK(TrackReading::kTracking == rig.task.estimator().lastObservation(0).track);

    tables::DriveHealthModelTable model = rig.tables.driveHealthModel();
    model.active_speed_rad_s = 5.0F;  // 2 rad/s is now "idle"
    std::uint8_t image[tables::kMaxTableImageSize];
    const std::size_t length = tables::encodeTable(model, 2, image, sizeof image);
    CHECK(length > 0);
    CHECK(rig.tables.loadChunk(tables::TableId::kDriveHealthModel, 0, image, length).ok());
    CHECK(rig.tables.validate(tables::TableId::kDriveHealthModel).ok());
    CHECK(rig.tables.activate(tables::TableId::kDriveHealthModel).ok());
    rig.runFor(100 * kMs);  // applied at the first frame of this window
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        CHECK(TrackReading::kNone == rig.task.estimator().lastObservation(w).track);
    }
}

TEST(DriveModeTask, InitRefusalIsEventedAndTheTaskStaysInert) {
    core::VirtualClock clock;
    core::EventLog events(clock);
    core::SoftwareBus bus(clock, events);
    tables::TableService tables(events);
    CHECK(core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount)));
    estimator::DriveModeTask first(bus, events, tables);
    CHECK(core::isOk(first.init()));
    core::PipeId pipe = 0;
    for (std::size_t i = 1; i < core::kBusMaxPipes; ++i) {
        (void)bus.createPipe("filler", 1, &pipe);
    }
    (void)drain(events);
    estimator::DriveModeTask second(bus, events, tables);
    CHECK_FALSE(core::isOk(second.init()));
    bool evented = false;
    for (const SeenEvent& e : drain(events)) {
        evented = evented || e.id == estimator::events::kDriveModeInitFailed;
    }
    CHECK(evented);
    second.run(core::FrameContext{});
    LONGS_EQUAL(0, second.statusesTaken());
}

TEST(DriveModeTask, TenThousandFramesAllocateNothing) {
    DriveModeRig rig(1100);
    CHECK_TRUE(rig.init());
    test::DriveProfile profile(1100);
    rig.drives.degrade(1, 1.6);  // so events are reported inside the watch too
    rse::test::AllocationWatch watch;
    for (int i = 0; i < 10000; ++i) {
        profile.apply(rig.drives.now(), &rig.drives);
        rig.frame();
    }
    const auto allocations = watch.count();
    LONGS_EQUAL(0, allocations);
    LONGS_EQUAL(1000, rig.task.updates());
    LONGS_EQUAL(10000, rig.task.statusesTaken());
    CHECK(rig.task.modeChanges() >= 1);
}

// The contact reflex alone (no bus): which drive statuses read a contact and
// which do not (a turn, one degraded drive, five dragging a locked sixth, a
// start's lag), and the back-off's command, its ramp and each way it ends.
#include <cmath>

#include "fsw/reflexive/contact_reflex.hpp"
#include "fsw/tables/table_types.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using reflexive::BackoffEnd;
using reflexive::BackoffState;
using reflexive::ContactReflex;
using reflexive::ContactReading;

namespace {

constexpr core::TimeNs kFrame = 10 * core::kNsPerMs;

// The values of tables/follower.toml.
tables::FollowerTable follower() {
    tables::FollowerTable t{};
    t.lookahead_m = 0.8F;
    t.arrival_tolerance_m = 0.15F;
    t.max_cross_track_m = 1.0F;
    t.turn_in_place_rad = 0.8F;
    t.pose_timeout_ms = 200;
    t.contact_current_a = 4.0F;
    t.contact_stall_ratio = 0.3F;
    t.contact_wheels = 4;
    t.contact_backoff_m = 0.3F;
    t.contact_backoff_speed_m_s = 0.1F;
    return t;
}

}  // namespace

TEST_GROUP(ContactReflex) {
    ContactReflex reflex;
    tables::FollowerTable table = follower();
    core::TimeNs now = core::kNsPerSec;

    // Every wheel commanded `target` and turning at `speed`, drawing `current`.
    msg::DriveStatusMsg status(double target, double speed, double current) {
        msg::DriveStatusMsg d{};
        d.timeNs = now;
        for (msg::WheelStatus& w : d.wheels) {
            w.targetRadS = target;
            w.velocityRadS = speed;
            w.currentA = current;
            w.feedbackTimeNs = now;
            w.feedbackCount = 10;
            w.health = msg::DriveHealth::kOperational;
        }
        return d;
    }
    ContactReading frame(const msg::DriveStatusMsg& d) {
        const ContactReading r = reflex.observe(d, table);
        now += kFrame;
        return r;
    }
};

TEST(ContactReflex, RollingAndTurningAreNoContact) {
    for (int i = 0; i < 100; ++i) {
        CHECK_FALSE(frame(status(3.0, 3.0, 1.4)).contact);  // cruising: 1.4 A
    }
    msg::DriveStatusMsg turn = status(3.0, 3.0, 2.6);  // a turn: the outer side faster, more current
    for (int i = 0; i < 3; ++i) {
        turn.wheels[i].targetRadS = 1.5;
        turn.wheels[i].velocityRadS = 1.5;
    }
    for (int i = 0; i < 100; ++i) {
        const ContactReading r = frame(turn);
        CHECK_FALSE(r.contact);
        LONGS_EQUAL(0, r.wheelsPushing);
    }
}

TEST(ContactReflex, AllWheelsPushingIsAContactInTheFirstFrame) {
    for (int i = 0; i < 50; ++i) {
        (void)frame(status(3.0, 3.0, 1.4));
    }
    const ContactReading r = frame(status(3.0, 3.0, 7.5));  // the wheels slip, the current jumps
    CHECK_TRUE(r.contact);
    LONGS_EQUAL(6, r.wheelsPushing);
    DOUBLES_EQUAL(7.5, r.maxCurrentA, 1e-9);
}

TEST(ContactReflex, OneDegradedDriveOrFiveDraggingALockedOneAreNot) {
    msg::DriveStatusMsg d = status(3.0, 3.0, 2.0);
    d.wheels[1].currentA = 5.2;  // one drive at 1.8x in a turn, over the threshold alone
    for (int i = 0; i < 50; ++i) {
        const ContactReading r = frame(d);
        CHECK_FALSE(r.contact);
        LONGS_EQUAL(1, r.wheelsPushing);
    }
    msg::DriveStatusMsg dragging = status(3.0, 3.0, 3.8);  // five turning wheels dragging a locked one
    dragging.wheels[4].health = msg::DriveHealth::kFailed;
    dragging.wheels[4].velocityRadS = 0.0;
    dragging.wheels[4].currentA = 0.0;
    for (int i = 0; i < 50; ++i) {
        CHECK_FALSE(frame(dragging).contact);
    }
}

TEST(ContactReflex, StalledWheelsAreAContactOnceTheirCommandHasSettled) {
    // A start: the command steps up and the wheels lag behind it: not a stall yet.
    // The command changes in the first frame, then holds kSteadyFrames - 1 more.
    for (int i = 0; i < reflexive::kSteadyFrames; ++i) {
        CHECK_FALSE(frame(status(3.0, 0.2, 1.0)).contact);
    }
    // Still under 30 % of a command held long enough: stalled.
    const ContactReading r = frame(status(3.0, 0.2, 1.0));
    CHECK_TRUE(r.contact);
    LONGS_EQUAL(6, r.wheelsPushing);
    // A command that keeps changing never settles.
    ContactReflex other;
    for (int i = 0; i < 100; ++i) {
        msg::DriveStatusMsg d = status(1.0 + 0.1 * i, 0.0, 1.0);
        CHECK_FALSE(other.observe(d, table).contact);
    }
}

TEST(ContactReflex, WheelsNotCommandedStaleOrNotOperationalDoNotCount) {
    msg::DriveStatusMsg d = status(0.2, 0.0, 9.0);  // below kActiveWheelRadS
    CHECK_FALSE(frame(d).contact);
    d = status(3.0, 3.0, 9.0);
    for (msg::WheelStatus& w : d.wheels) {
        w.feedbackTimeNs = now - 2 * reflexive::kFeedbackMaxAgeNs;  // stale
    }
    CHECK_FALSE(frame(d).contact);
    d = status(3.0, 3.0, 9.0);
    for (int i = 0; i < 3; ++i) {
        d.wheels[i].health = msg::DriveHealth::kFaulted;
        d.wheels[i].currentA = std::nan("");
    }
    LONGS_EQUAL(3, frame(d).wheelsPushing);  // three left: under contact_wheels
    table.contact_wheels = 3;
    CHECK_TRUE(frame(d).contact);  // the table is read every frame
}

// A commanded, fresh, operational wheel whose current or speed is not a
// number says nothing: it is counted (the task's wheel_readings_not_finite)
// and not judged, and the other wheels decide.
TEST(ContactReflex, AReadingNotFiniteIsCountedAndNotJudged) {
    msg::DriveStatusMsg d = status(3.0, 0.0, 9.0);
    d.wheels[0].currentA = std::nan("");
    d.wheels[1].velocityRadS = INFINITY;
    ContactReading r = frame(d);
    LONGS_EQUAL(2, r.notFinite);
    LONGS_EQUAL(4, r.wheelsPushing);
    CHECK_TRUE(r.contact);  // contact_wheels 4 of the four judged
    d.wheels[2].currentA = std::nan("");
    r = frame(d);
    LONGS_EQUAL(3, r.notFinite);
    CHECK_FALSE(r.contact);  // three judged: under contact_wheels
    LONGS_EQUAL(0, frame(status(3.0, 3.0, 1.0)).notFinite);
}

TEST(ContactReflex, TheBackoffRampsToItsSpeedOppositeTheDirectionDrivenAndEndsAfterItsDistance) {
    reflex.startBackoff(5.0, 0.0, 1.0, now);  // felt driving forwards, east
    CHECK_TRUE(reflex.state() == BackoffState::kBacking);
    double x = 5.0, v = 0.0;
    BackoffEnd ended = BackoffEnd::kNone;
    int frames = 0;
    DOUBLES_EQUAL(0.0, reflex.backoffStep(true, x, 0.0, now, 0.01, 0.2, 0.3, table, &ended), 0.0);  // the contact's run
    now += kFrame;
    for (; frames < 1000; ++frames) {
        const double cmd = reflex.backoffStep(true, x, 0.0, now, 0.01, 0.2, 0.3, table, &ended);
        if (ended != BackoffEnd::kNone) {
            DOUBLES_EQUAL(0.0, cmd, 0.0);
            break;
        }
        CHECK(cmd <= 0.0);                       // backwards
        CHECK(std::fabs(cmd - v) <= 0.2 * 0.01 + 1e-12);  // within the acceleration limit
        CHECK(cmd >= -0.1 - 1e-6);  // the table's f32 0.1
        v = cmd;
        x += v * 0.01;
        now += kFrame;
    }
    CHECK_TRUE(ended == BackoffEnd::kDistance);
    CHECK(5.0 - x >= 0.3 - 0.002);
    CHECK(frames < 400);  // 0.3 m at 0.1 m/s plus the ramp: about 3.5 s
    CHECK_TRUE(reflex.state() == BackoffState::kNone);
}

TEST(ContactReflex, ABackoffEndsOnTimeoutWithoutAPoseOrWhenAborted) {
    reflex.startBackoff(0.0, 0.0, -1.0, now);  // felt backing: back off forwards
    now += kFrame;
    BackoffEnd ended = BackoffEnd::kNone;
    double cmd = 0.0;
    for (int i = 0; i < 10; ++i) {
        cmd = reflex.backoffStep(true, 0.0, 0.0, now, 0.01, 0.2, 0.3, table, &ended);
        now += kFrame;
    }
    CHECK(cmd > 0.0);
    // Stuck where it is: ends after 3 x 3 s + 1 s.
    int frames = 10;
    while (ended == BackoffEnd::kNone && frames < 5000) {
        (void)reflex.backoffStep(true, 0.0, 0.0, now, 0.01, 0.2, 0.3, table, &ended);
        now += kFrame;
        ++frames;
    }
    CHECK_TRUE(ended == BackoffEnd::kTimeout);
    CHECK(frames >= 999 && frames <= 1002);

    // Backing at most the body speed limit, its time reckoned at that speed:
    // 3 x 0.3 m / 0.3 m/s + 1 s = 4 s (at the table's 0.5 m/s it would be 2.8 s).
    table.contact_backoff_speed_m_s = 0.5F;
    reflex.startBackoff(0.0, 0.0, 1.0, now);
    now += kFrame;
    ended = BackoffEnd::kNone;
    for (int i = 0; i < 350 && ended == BackoffEnd::kNone; ++i) {
        cmd = reflex.backoffStep(true, 0.0, 0.0, now, 0.01, 0.2, 0.3, table, &ended);
        CHECK(cmd >= -0.3 - 1e-12);
        now += kFrame;
    }
    CHECK_TRUE(ended == BackoffEnd::kNone);
    CHECK_TRUE(reflex.state() == BackoffState::kBacking);
    (void)reflex.abortBackoff(BackoffEnd::kReleased);
    table.contact_backoff_speed_m_s = 0.1F;

    reflex.startBackoff(0.0, 0.0, 1.0, now);
    (void)reflex.backoffStep(false, 0.0, 0.0, now, 0.01, 0.2, 0.3, table, &ended);
    CHECK_TRUE(ended == BackoffEnd::kReleased);

    reflex.startBackoff(0.0, 0.0, 1.0, now);
    CHECK_TRUE(reflex.abortBackoff(BackoffEnd::kContact) == BackoffEnd::kContact);
    CHECK_TRUE(reflex.abortBackoff(BackoffEnd::kContact) == BackoffEnd::kNone);  // none in hand
}

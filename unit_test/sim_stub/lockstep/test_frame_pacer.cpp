// rse-demo --pace (sim_stub/lockstep/frame_pacer.hpp) on a fake wall clock:
// frame k of the run is due k x 10 ms / factor after the first frame paced,
// waited for when early; a frame reached late runs at once and is counted
// with its lateness, and lateness does not shift the frames after it (they
// run at once until the schedule is caught up). Factor 0: no pacing at all.
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "sim_stub/lockstep/frame_pacer.hpp"

#include "CppUTest/TestHarness.h"

using rse::sim::FramePacer;
using Clock = FramePacer::Clock;
using std::chrono::microseconds;
using std::chrono::milliseconds;

namespace {

// The fake wall clock: read by the pacer, moved by its waits and by the test
// (a slow frame).
// Every sleep_until asked for (a fixed table: the tests check the heap).
struct Waits {
    Clock::time_point due[16] = {};
    std::size_t count = 0;
    std::size_t size() const { return count; }
    const Clock::time_point& operator[](std::size_t i) const { return due[i]; }
    const Clock::time_point& back() const { return due[count - 1]; }
    void clear() { count = 0; }
};
Clock::time_point g_now{};
Waits g_waits;

Clock::time_point fakeNow() { return g_now; }
void fakeSleepUntil(Clock::time_point due) {
    if (g_waits.count < 16) {
        g_waits.due[g_waits.count++] = due;
    }
    g_now = due > g_now ? due : g_now;
}

// Milliseconds from t0 to t, as a double (compared within 1e-5 ms: the pacer
// rounds a due time down to the clock's nanoseconds).
double msSince(Clock::time_point t0, Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(t - t0).count();
}

}  // namespace

TEST_GROUP(FramePacer) {
    Clock::time_point t0 = Clock::time_point(std::chrono::seconds(1000));
    void setup() override {
        g_now = t0;
        g_waits.clear();
    }
};

// Factor 10: one 10 ms minor frame every 1 ms of wall time, counted from the
// first frame paced (the executive's frame 500 here, not 0).
TEST(FramePacer, EachFrameIsWaitedForUntilItsDueTime) {
    FramePacer pacer(10.0, &fakeNow, &fakeSleepUntil);
    pacer.beforeFrame(500);  // the start: due now, no wait
    LONGS_EQUAL(0, g_waits.size());
    pacer.beforeFrame(501);
    LONGS_EQUAL(1, g_waits.size());
    DOUBLES_EQUAL(1.0, msSince(t0, g_waits[0]), 1e-5);
    pacer.beforeFrame(501);  // the same frame again: nothing
    LONGS_EQUAL(1, g_waits.size());
    g_now += microseconds(300);  // the frame took 0.3 ms: 0.7 ms left to wait
    pacer.beforeFrame(502);
    LONGS_EQUAL(2, g_waits.size());
    DOUBLES_EQUAL(2.0, msSince(t0, g_waits[1]), 1e-5);
    pacer.beforeFrame(510);  // frames skipped: due by its own number
    DOUBLES_EQUAL(10.0, msSince(t0, g_waits[2]), 1e-5);
    LONGS_EQUAL(4, pacer.framesPaced());
    LONGS_EQUAL(0, pacer.framesBehind());
    DOUBLES_EQUAL(0.0, pacer.behindMaxMs(), 0.0);
    DOUBLES_EQUAL(10.0, pacer.factor(), 0.0);
}

// Factor 1 (real time): a 35 ms frame makes the next three late by 25, 15
// and 5 ms; they run at once (no wait) and are counted, the worst kept; the
// frame due exactly when it is reached is on time, and the one after waits
// again: the schedule never moved.
TEST(FramePacer, LateFramesRunAtOnceAreCountedAndDoNotShiftTheSchedule) {
    FramePacer pacer(1.0, &fakeNow, &fakeSleepUntil);
    pacer.beforeFrame(0);
    g_now += milliseconds(35);  // frame 0 took 35 ms
    pacer.beforeFrame(1);       // due at 10 ms
    LONGS_EQUAL(1, pacer.framesBehind());
    DOUBLES_EQUAL(25.0, pacer.behindMaxMs(), 1e-5);
    pacer.beforeFrame(2);  // due at 20 ms
    pacer.beforeFrame(3);  // due at 30 ms
    LONGS_EQUAL(0, g_waits.size());
    LONGS_EQUAL(3, pacer.framesBehind());
    DOUBLES_EQUAL(25.0, pacer.behindMaxMs(), 1e-5);    // the worst, not the latest (5 ms)
    g_now += milliseconds(5);  // now 40 ms
    pacer.beforeFrame(4);      // due at 40 ms: on time
    LONGS_EQUAL(3, pacer.framesBehind());
    LONGS_EQUAL(0, g_waits.size());
    pacer.beforeFrame(5);  // due at 50 ms: waited for
    LONGS_EQUAL(1, g_waits.size());
    DOUBLES_EQUAL(50.0, msSince(t0, g_waits[0]), 1e-5);
    LONGS_EQUAL(6, pacer.framesPaced());
    LONGS_EQUAL(3, pacer.framesBehind());
}

// Factor 0.5 (half real time): a frame every 20 ms; 1000: every 10 us.
TEST(FramePacer, TheFactorScalesThePeriod) {
    FramePacer slow(0.5, &fakeNow, &fakeSleepUntil);
    slow.beforeFrame(7);
    slow.beforeFrame(10);
    DOUBLES_EQUAL(60.0, msSince(t0, g_waits.back()), 1e-5);
    g_now = t0;
    FramePacer fast(1000.0, &fakeNow, &fakeSleepUntil);
    fast.beforeFrame(0);
    fast.beforeFrame(100);
    DOUBLES_EQUAL(1.0, msSince(t0, g_waits.back()), 1e-5);
}

// Without --pace (factor 0) the lockstep runs as fast as the CPU allows:
// nothing waited for, nothing counted, whatever the clock says.
TEST(FramePacer, FactorZeroPacesNothing) {
    for (double factor : {0.0, -1.0}) {
        FramePacer pacer(factor, &fakeNow, &fakeSleepUntil);
        pacer.beforeFrame(0);
        g_now += milliseconds(100);
        pacer.beforeFrame(1);
        pacer.beforeFrame(2);
        LONGS_EQUAL(0, pacer.framesPaced());
        LONGS_EQUAL(0, pacer.framesBehind());
        LONGS_EQUAL(0, g_waits.size());
    }
}

// The real wall clock: a frame paced at factor 100 (due 0.1 ms after the
// first) is not reached before its due time (a lower bound only: a loaded
// machine may be later).
TEST(FramePacer, TheWallClockWaitsAtLeastUntilTheDueTime) {
    FramePacer pacer(100.0);
    const Clock::time_point start = Clock::now();
    pacer.beforeFrame(0);
    pacer.beforeFrame(20);  // due 2 ms after frame 0
    CHECK(Clock::now() - start >= milliseconds(2));
    LONGS_EQUAL(2, pacer.framesPaced());
}

#include "fsw/core/clock.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::core;

TEST_GROUP(VirtualClock){};

TEST(VirtualClock, SleepJumpsToDeadlineAndNeverBackwards) {
    VirtualClock clock(100);
    clock.sleepUntil(250);
    CHECK_EQUAL(250, clock.now());
    clock.sleepUntil(200);  // already passed
    CHECK_EQUAL(250, clock.now());
    clock.advance(50);
    CHECK_EQUAL(300, clock.now());
    clock.advance(-10);  // ignored: time does not run backwards
    CHECK_EQUAL(300, clock.now());
}

TEST_GROUP(MonotonicClock){};

// Guarantees only (never a duration upper bound, which a loaded machine can break).
TEST(MonotonicClock, SleepUntilReturnsNoEarlierThanTheDeadline) {
    MonotonicClock clock;
    const TimeNs start = clock.now();
    for (int i = 1; i <= 5; ++i) {
        const TimeNs deadline = start + i * kNsPerMs;
        clock.sleepUntil(deadline);
        CHECK(clock.now() >= deadline);
    }
    const TimeNs before = clock.now();
    clock.sleepUntil(before - kNsPerSec);  // a past deadline returns at once
    CHECK(clock.now() >= before);
}

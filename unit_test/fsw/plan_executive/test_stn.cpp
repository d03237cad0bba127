// The Simple Temporal Network: consistency and negative cycles, windows and
// distances, the sliced check equal to the one-shot check, incremental
// execution and tightening equal to a full recomputation (randomised,
// seeded), early and late execution refused as inconsistent with the network
// left as it was, distances beyond the int32 range reported, bad arguments.
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>

#include "fsw/plan_executive/stn.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using rse::plan_executive::addDistances;
using rse::plan_executive::Bounds;
using rse::plan_executive::kInfiniteMs;
using rse::plan_executive::kMaxBoundMs;
using rse::plan_executive::Stn;
using rse::plan_executive::StnState;
using rse::plan_executive::StnUpdate;
using rse::plan_executive::Window;

namespace {

Stn stn;  // static storage, as in flight (256 KiB)
Stn reference;

// A chain start -> 1 -> 2 -> 3 with [10, 20] s each, and a deadline on 3.
void chain(Stn* s, std::int32_t deadlineMs) {
    CHECK(s->reset(4) == Status::kOk);
    for (std::size_t e = 1; e < 4; ++e) {
        CHECK(s->addBounds(e - 1, e, Bounds{10000, 20000}) == Status::kOk);
    }
    CHECK(s->addBounds(0, 3, Bounds{0, deadlineMs}) == Status::kOk);
}

// A random consistent network: a random order of events (a schedule), bounds
// that this schedule meets, some of them loose or open-ended.
void randomConsistent(std::mt19937& rng, std::size_t n, Stn* s, std::int32_t* times) {
    std::uniform_int_distribution<int> t(0, 100000), slack(0, 20000), pick(0, static_cast<int>(n) - 1), coin(0, 3);
    times[0] = 0;
    for (std::size_t e = 1; e < n; ++e) {
        times[e] = t(rng);
    }
    CHECK(s->reset(n) == Status::kOk);
    for (std::size_t e = 1; e < n; ++e) {
        CHECK(s->addBounds(0, e, Bounds{0, kInfiniteMs}) == Status::kOk);
    }
    for (std::size_t k = 0; k < 3 * n; ++k) {
        const auto a = static_cast<std::size_t>(pick(rng)), b = static_cast<std::size_t>(pick(rng));
        const std::int32_t gap = times[b] - times[a];
        const std::int32_t ub = coin(rng) == 0 ? kInfiniteMs : gap + slack(rng);
        CHECK(s->addBounds(a, b, Bounds{gap - slack(rng), ub}) == Status::kOk);
    }
}

void checkSameMatrix(const Stn& a, const Stn& b) {
    CHECK_EQUAL(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        for (std::size_t j = 0; j < a.size(); ++j) {
            if (a.distance(i, j) != b.distance(i, j)) {
                FAIL_TEST(("distance differs at " + std::to_string(i) + "," + std::to_string(j) + ": " +
                           std::to_string(a.distance(i, j)) + " vs " + std::to_string(b.distance(i, j)))
                              .c_str());
            }
        }
    }
}

}  // namespace

TEST_GROUP(Stn){};

TEST(Stn, ASaturatingSumKeepsNoBoundAndTheRange) {
    CHECK_EQUAL(kInfiniteMs, addDistances(kInfiniteMs, -5));
    CHECK_EQUAL(kInfiniteMs, addDistances(3, kInfiniteMs));
    CHECK_EQUAL(kInfiniteMs, addDistances(kInfiniteMs - 1, 10));
    CHECK_EQUAL(-kInfiniteMs, addDistances(-kInfiniteMs, -10));
    CHECK_EQUAL(-7, addDistances(3, -10));
}

TEST(Stn, AConsistentChainHasTheWindowsItsBoundsGive) {
    chain(&stn, 45000);
    CHECK(stn.check() == StnState::kConsistent);
    const Window w1 = stn.window(1);
    CHECK_EQUAL(10000, w1.earliestMs);
    CHECK_EQUAL(20000, w1.latestMs);
    const Window w3 = stn.window(3);
    CHECK_EQUAL(30000, w3.earliestMs);
    CHECK_EQUAL(45000, w3.latestMs);
    // Event 2: at most 40 s by its chain, 45 s - 10 s by the deadline reaching back.
    CHECK_EQUAL(35000, stn.window(2).latestMs);
    CHECK_EQUAL(35000, stn.distance(1, 3));
    CHECK_EQUAL(-20000, stn.distance(3, 1));
    CHECK_EQUAL(kInfiniteMs, stn.distance(0, 99));  // outside the network
}

TEST(Stn, ADeadlineBelowTheLeastDurationIsANegativeCycle) {
    chain(&stn, 29999);
    CHECK(stn.check() == StnState::kInconsistent);
    // Two events, t1 - t0 in [5, 10] and t0 - t1 >= -4 (t1 - t0 <= 4): a two-edge cycle.
    CHECK(stn.reset(2) == Status::kOk);
    CHECK(stn.addBounds(0, 1, Bounds{5, 10}) == Status::kOk);
    CHECK(stn.addBounds(1, 0, Bounds{-4, 0}) == Status::kOk);
    CHECK(stn.check() == StnState::kInconsistent);
    // A self loop that must take time.
    CHECK(stn.reset(3) == Status::kOk);
    CHECK(stn.addBounds(2, 2, Bounds{1, 5}) == Status::kOk);
    CHECK(stn.check() == StnState::kInconsistent);
    // A three-event cycle 0 -> 1 -> 2 -> 0 with a total of -1.
    CHECK(stn.reset(3) == Status::kOk);
    CHECK(stn.addBounds(0, 1, Bounds{0, 10}) == Status::kOk);
    CHECK(stn.addBounds(1, 2, Bounds{0, 10}) == Status::kOk);
    CHECK(stn.addBounds(0, 2, Bounds{21, 30}) == Status::kOk);
    CHECK(stn.check() == StnState::kInconsistent);
}

TEST(Stn, ASlicedCheckEqualsTheOneShotCheck) {
    std::mt19937 rng(11);
    std::int32_t times[40];
    randomConsistent(rng, 40, &stn, times);
    std::mt19937 twin(11);
    randomConsistent(twin, 40, &reference, times);
    CHECK(reference.check() == StnState::kConsistent);
    CHECK(stn.beginCheck() == Status::kOk);
    std::size_t calls = 0;
    while (!stn.step(7) && calls < 40 * 40) {
        ++calls;
    }
    CHECK(stn.state() == StnState::kConsistent);
    CHECK_EQUAL(40U * 40U, stn.work());
    checkSameMatrix(stn, reference);
}

TEST(Stn, IncrementalExecutionEqualsAFullRecomputation) {
    // Random consistent networks; events executed one by one in the order of
    // a schedule, each at a random time inside its current window; after
    // every execution the matrix equals the one a fresh full check gives with
    // every execution so far added as a bound from the start.
    for (std::uint32_t seed = 1; seed <= 25; ++seed) {
        std::mt19937 rng(seed);
        const std::size_t n = 4 + seed % 20;
        std::int32_t times[32];
        randomConsistent(rng, n, &stn, times);
        CHECK(stn.check() == StnState::kConsistent);
        std::int32_t executedAt[32];
        for (std::size_t e = 1; e < n; ++e) {
            const Window w = stn.window(e);
            CHECK(w.earliestMs <= w.latestMs);
            const std::int32_t hi = w.latestMs == kInfiniteMs ? w.earliestMs + 50000 : w.latestMs;
            executedAt[e] = std::uniform_int_distribution<std::int32_t>(w.earliestMs, hi)(rng);
            CHECK(stn.execute(e, executedAt[e]) == StnUpdate::kApplied);
            CHECK_EQUAL(executedAt[e], stn.window(e).earliestMs);
            CHECK_EQUAL(executedAt[e], stn.window(e).latestMs);
            std::mt19937 twin(seed);
            randomConsistent(twin, n, &reference, times);
            for (std::size_t k = 1; k <= e; ++k) {
                CHECK(reference.addBounds(0, k, Bounds{executedAt[k], executedAt[k]}) == Status::kOk);
            }
            CHECK(reference.check() == StnState::kConsistent);
            checkSameMatrix(stn, reference);
        }
    }
}

TEST(Stn, TighteningAnEdgeEqualsAFullRecomputation) {
    for (std::uint32_t seed = 100; seed < 120; ++seed) {
        std::mt19937 rng(seed);
        const std::size_t n = 5 + seed % 15;
        std::int32_t times[32];
        randomConsistent(rng, n, &stn, times);
        CHECK(stn.check() == StnState::kConsistent);
        std::uniform_int_distribution<int> pick(0, static_cast<int>(n) - 1);
        const auto a = static_cast<std::size_t>(pick(rng)), b = static_cast<std::size_t>(pick(rng));
        // Between the least it may be and its current bound: consistent.
        const std::int32_t most = stn.distance(a, b), least = -stn.distance(b, a);
        const std::int32_t w = most == kInfiniteMs ? least + 1000 : least + (most - least) / 2;
        CHECK(stn.tighten(a, b, w) == StnUpdate::kApplied);
        std::mt19937 twin(seed);
        randomConsistent(twin, n, &reference, times);
        CHECK(reference.addBounds(a, b, Bounds{-kMaxBoundMs, w}) == Status::kOk);
        CHECK(reference.check() == StnState::kConsistent);
        checkSameMatrix(stn, reference);
        if (a != b) {
            // Below the least it may be: a negative cycle, refused, nothing changed.
            CHECK(stn.tighten(a, b, least - 1) == StnUpdate::kInconsistent);
            checkSameMatrix(stn, reference);
        }
    }
}

TEST(Stn, EarlyAndLateExecutionAreInconsistentAndChangeNothing) {
    chain(&stn, 45000);
    CHECK(stn.check() == StnState::kConsistent);
    chain(&reference, 45000);
    CHECK(reference.check() == StnState::kConsistent);
    CHECK(stn.execute(1, 9999) == StnUpdate::kInconsistent);   // before its lower bound
    CHECK(stn.execute(1, 20001) == StnUpdate::kInconsistent);  // after what the deadline leaves it
    CHECK(stn.state() == StnState::kConsistent);
    checkSameMatrix(stn, reference);
    // On time; then the next one late against what that left it ([25, 35] s).
    CHECK(stn.execute(1, 15000) == StnUpdate::kApplied);
    CHECK_EQUAL(25000, stn.window(2).earliestMs);
    CHECK_EQUAL(35000, stn.window(2).latestMs);
    CHECK(stn.execute(2, 35001) == StnUpdate::kInconsistent);
    CHECK(stn.execute(2, 25000) == StnUpdate::kApplied);
    CHECK(stn.execute(3, 34000) == StnUpdate::kInconsistent);  // early: needs 10 s after event 2
    CHECK(stn.execute(3, 45000) == StnUpdate::kApplied);
}

TEST(Stn, DistancesBeyondTheRangeAreReportedNotTrusted) {
    // Five chained bounds of [0.9e9, 1e9] ms: the chain's end is 4.5e9 ms out,
    // beyond int32: the check cannot establish consistency.
    CHECK(stn.reset(6) == Status::kOk);
    for (std::size_t e = 1; e < 6; ++e) {
        CHECK(stn.addBounds(e - 1, e, Bounds{900000000, kMaxBoundMs}) == Status::kOk);
    }
    CHECK(stn.check() == StnState::kOutOfRange);
    CHECK(stn.rangeLosses() > 0);
    CHECK(stn.execute(1, 900000000) == StnUpdate::kRejected);
}

TEST(Stn, BadArgumentsAndWrongStatesAreRefused) {
    CHECK(stn.reset(0) == Status::kInvalidArgument);
    CHECK(stn.reset(Stn::kMaxNodes + 1) == Status::kInvalidArgument);
    CHECK(stn.reset(3) == Status::kOk);
    CHECK(stn.addBounds(0, 3, Bounds{0, 5}) == Status::kInvalidArgument);
    CHECK(stn.addBounds(0, 1, Bounds{6, 5}) == Status::kInvalidArgument);
    CHECK(stn.addBounds(0, 1, Bounds{kInfiniteMs, kInfiniteMs}) == Status::kInvalidArgument);
    CHECK(stn.addBounds(0, 1, Bounds{0, kMaxBoundMs + 1}) == Status::kInvalidArgument);
    CHECK(stn.execute(1, 0) == StnUpdate::kRejected);  // not checked yet
    CHECK(stn.step(10) == false);                       // no check under way
    CHECK(stn.check() == StnState::kConsistent);
    CHECK(stn.addBounds(0, 1, Bounds{0, 5}) == Status::kNotInitialized);
    CHECK(stn.beginCheck() == Status::kNotInitialized);
    CHECK(stn.execute(7, 0) == StnUpdate::kRejected);
    CHECK(stn.execute(1, kInfiniteMs) == StnUpdate::kRejected);
    CHECK(stn.tighten(0, 1, kInfiniteMs) == StnUpdate::kRejected);
    CHECK(stn.tighten(0, 1, 100) == StnUpdate::kApplied);
    CHECK_EQUAL(100, stn.window(1).latestMs);
    CHECK_EQUAL(-kInfiniteMs, stn.window(9).earliestMs);
}

TEST(Stn, TheLargestNetworkChecksAndUpdates) {
    // kMaxNodes events in a chain of [1, 2] s from the start: n^2 units.
    CHECK(stn.reset(Stn::kMaxNodes) == Status::kOk);
    for (std::size_t e = 1; e < Stn::kMaxNodes; ++e) {
        CHECK(stn.addBounds(e - 1, e, Bounds{1000, 2000}) == Status::kOk);
    }
    CHECK(stn.check() == StnState::kConsistent);
    CHECK_EQUAL(Stn::kMaxNodes * Stn::kMaxNodes, stn.work());
    const std::size_t last = Stn::kMaxNodes - 1;
    CHECK_EQUAL(static_cast<std::int32_t>(1000 * last), stn.window(last).earliestMs);
    CHECK_EQUAL(static_cast<std::int32_t>(2000 * last), stn.window(last).latestMs);
    CHECK(stn.execute(1, 1500) == StnUpdate::kApplied);
    CHECK_EQUAL(static_cast<std::int32_t>(1500 + 1000 * (last - 1)), stn.window(last).earliestMs);
}

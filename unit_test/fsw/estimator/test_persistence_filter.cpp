#include "fsw/core/clock.hpp"
#include "fsw/estimator/fault_book.hpp"
#include "fsw/estimator/persistence_filter.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::kNsPerMs;
using rse::core::TimeNs;
using rse::estimator::FaultBook;
using rse::estimator::PersistenceFilter;
using Edge = PersistenceFilter::Edge;

TEST_GROUP(PersistenceFilter) {
    PersistenceFilter filter;
    static constexpr TimeNs kPersist = 50 * kNsPerMs;

    // Feeds a 100 Hz sample; raise when value > 10, clear when value < 5.
    Edge feed(TimeNs tMs, double value) {
        return filter.update(tMs * kNsPerMs, value > 10.0, value < 5.0, kPersist);
    }
};

TEST(PersistenceFilter, RaisesAtTheFirstSampleThePersistenceTimeAfterTheConditionWasFirstSeen) {
    CHECK(Edge::kNone == feed(0, 1.0));
    for (TimeNs t = 10; t < 60; t += 10) {  // first seen at 10 ms; 50 ms later is 60 ms
        CHECK(Edge::kNone == feed(t, 20.0));
        CHECK_FALSE(filter.active());
    }
    CHECK(Edge::kRaised == feed(60, 20.0));
    CHECK(filter.active());
    CHECK(Edge::kNone == feed(70, 20.0));  // an edge, not a level
}

TEST(PersistenceFilter, ClearsOnlyAfterTheClearConditionHeldAsLong) {
    for (TimeNs t = 0; t <= 50; t += 10) {
        (void)feed(t, 20.0);
    }
    CHECK(filter.active());
    for (TimeNs t = 60; t < 110; t += 10) {
        CHECK(Edge::kNone == feed(t, 1.0));
    }
    CHECK(Edge::kCleared == feed(110, 1.0));
    CHECK_FALSE(filter.active());
}

TEST(PersistenceFilter, AValueBetweenTheThresholdsRestartsTheWaitAndChangesNothing) {
    (void)feed(0, 20.0);
    (void)feed(40, 20.0);
    CHECK(Edge::kNone == feed(45, 7.0));  // between: neither raise nor clear condition
    CHECK(Edge::kNone == feed(60, 20.0));  // the wait starts again here
    CHECK(Edge::kNone == feed(100, 20.0));
    CHECK(Edge::kRaised == feed(110, 20.0));
    for (TimeNs t = 120; t < 2000; t += 10) {
        CHECK(Edge::kNone == feed(t, 7.0));
    }
    CHECK(filter.active());
}

TEST(PersistenceFilter, AZeroPersistenceStillNeedsTwoSamplesSoAConditionTogglingEverySampleNeverChangesIt) {
    int edges = 0;
    for (TimeNs t = 0; t < 1000; t += 10) {
        const bool high = (t / 10) % 2 == 0;
        edges += filter.update(t * kNsPerMs, high, !high, 0) != Edge::kNone ? 1 : 0;
    }
    LONGS_EQUAL(0, edges);
    CHECK(Edge::kNone == filter.update(2000 * kNsPerMs, true, false, 0));
    CHECK(Edge::kNone == filter.update(2000 * kNsPerMs, true, false, 0));  // same sample again
    CHECK(Edge::kRaised == filter.update(2010 * kNsPerMs, true, false, 0));
}

TEST(PersistenceFilter, ASampleOlderThanTheWaitStartRestartsTheWait) {
    (void)feed(1000, 20.0);
    CHECK(Edge::kNone == feed(10, 20.0));  // the source's clock went back
    CHECK(Edge::kNone == feed(50, 20.0));
    CHECK(Edge::kRaised == feed(60, 20.0));
}

TEST_GROUP(FaultBook){};

TEST(FaultBook, CountsTransitionsOnlyAndRemembersTheLastOne) {
    FaultBook book;
    CHECK_FALSE(book.set(3, false, 10));
    CHECK(book.set(3, true, 20));
    CHECK_FALSE(book.set(3, true, 30));
    CHECK(book.set(35, true, 40));
    CHECK(book.isActive(3));
    CHECK(book.isActive(35));
    CHECK(book.activeMask() == ((std::uint64_t{1} << 3) | (std::uint64_t{1} << 35)));
    CHECK(book.set(3, false, 50));
    LONGS_EQUAL(2, book.raisedTotal());
    LONGS_EQUAL(1, book.clearedTotal());
    LONGS_EQUAL(1, book.raisedCount(3));
    LONGS_EQUAL(1, book.clearedCount(3));
    LONGS_EQUAL(3, book.lastFaultId());
    CHECK_FALSE(book.lastRaised());
    LONGS_EQUAL(50, book.changedAt(3));
}

TEST(FaultBook, IgnoresIdsOutsideTheCatalogue) {
    FaultBook book;
    CHECK_FALSE(book.set(0, true, 1));
    CHECK_FALSE(book.set(rse::msg::fault::kCount, true, 1));  // one past the last id
    CHECK_FALSE(book.isActive(0));
    LONGS_EQUAL(0, book.raisedTotal());
    CHECK(book.activeMask() == 0);
}

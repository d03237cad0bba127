#include <cstring>

#include "fsw/core/event_log.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::core;

TEST_GROUP(EventLog) {
    VirtualClock clock{5 * kNsPerSec};
    EventLog log{clock};
};

TEST(EventLog, RecordsIdSeverityTimeAndFormattedText) {
    log.report(42, Severity::kWarning, "pipe %s dropped %d", "nav", 3);
    Event e;
    CHECK(Status::kOk == log.pop(&e));
    LONGS_EQUAL(42, e.id);
    CHECK(Severity::kWarning == e.severity);
    CHECK_EQUAL(5 * kNsPerSec, e.time);
    STRCMP_EQUAL("pipe nav dropped 3", e.text);
    CHECK(Status::kEmpty == log.pop(&e));
}

TEST(EventLog, CountsPerSeverityWhetherReadOrNot) {
    log.report(1, Severity::kInfo, "a");
    log.report(2, Severity::kError, "b");
    log.report(3, Severity::kError, "c");
    LONGS_EQUAL(3, log.total());
    LONGS_EQUAL(1, log.count(Severity::kInfo));
    LONGS_EQUAL(2, log.count(Severity::kError));
    LONGS_EQUAL(0, log.count(Severity::kCritical));
}

TEST(EventLog, UnreadEventsOverwrittenAreCountedAsLost) {
    const unsigned extra = 5;
    for (unsigned i = 0; i < kEventRingDepth + extra; ++i) {
        log.report(7, Severity::kDebug, "n=%u", i);
    }
    LONGS_EQUAL(extra, log.lost());
    LONGS_EQUAL(kEventRingDepth, log.unread());
    Event e;
    CHECK(Status::kOk == log.pop(&e));
    LONGS_EQUAL(extra, e.sequence);  // the oldest surviving event; the gap shows the loss
    STRCMP_EQUAL("n=5", e.text);
}

TEST(EventLog, LongTextIsTruncatedNotOverflowed) {
    char big[400];
    std::memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    log.report(9, Severity::kInfo, "%s", big);
    Event e;
    CHECK(Status::kOk == log.pop(&e));
    LONGS_EQUAL(kEventTextSize - 1, std::strlen(e.text));
}

TEST(EventLog, RepeatedConditionsAreReportedOnPowersOfTwo) {
    CHECK_FALSE(isReportableOccurrence(0));
    CHECK_TRUE(isReportableOccurrence(1));
    CHECK_TRUE(isReportableOccurrence(2));
    CHECK_FALSE(isReportableOccurrence(3));
    CHECK_TRUE(isReportableOccurrence(1024));
    CHECK_FALSE(isReportableOccurrence(1000));
}

// An event's numbers travel with it: pop() and every cursor's read() give them
// back with the event; an event reported without any has none; more than
// kEventDataValues are cut to that many; a slot reused keeps no stale numbers.
TEST(EventLog, AnEventsNumbersComeBackWithItAndOnlyWithIt) {
    EventData data;
    data.count = 3;
    data.values[0] = 905.0;
    data.values[1] = -0.47;
    data.values[2] = 1e-12;
    log.report(905, Severity::kInfo, data, "leg %u", 4U);
    log.report(906, Severity::kInfo, "no numbers");
    EventLog::Cursor console;
    Event e;
    CHECK(Status::kOk == log.read(&console, &e));
    LONGS_EQUAL(905, e.id);
    STRCMP_EQUAL("leg 4", e.text);
    LONGS_EQUAL(3, e.data.count);
    DOUBLES_EQUAL(-0.47, e.data.values[1], 0.0);
    DOUBLES_EQUAL(1e-12, e.data.values[2], 0.0);
    CHECK(Status::kOk == log.pop(&e));
    LONGS_EQUAL(3, e.data.count);
    DOUBLES_EQUAL(905.0, e.data.values[0], 0.0);
    CHECK(Status::kOk == log.pop(&e));
    LONGS_EQUAL(906, e.id);
    LONGS_EQUAL(0, e.data.count);

    EventData tooMany;
    tooMany.count = 200;
    for (std::size_t i = 0; i < kEventDataValues; ++i) {
        tooMany.values[i] = static_cast<double>(i);
    }
    log.report(1, Severity::kDebug, tooMany, "cut");
    CHECK(Status::kOk == log.pop(&e));
    LONGS_EQUAL(kEventDataValues, e.data.count);
    DOUBLES_EQUAL(7.0, e.data.values[kEventDataValues - 1], 0.0);

    // Round the whole ring: a slot that held numbers, reused by an event without, has none.
    log.report(2, Severity::kDebug, data, "with");
    for (std::size_t i = 0; i < kEventRingDepth; ++i) {
        log.report(3, Severity::kDebug, "without");
    }
    while (Status::kOk == log.pop(&e)) {
        LONGS_EQUAL(3, e.id);
        LONGS_EQUAL(0, e.data.count);
    }
}

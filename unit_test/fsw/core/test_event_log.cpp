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

#include <cstring>

#include "fsw/core/input_pipe.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::core;

namespace {

constexpr EventId kMalformed = 4242;

struct PingMsg {
    static constexpr MsgId kMsgId = 0x0101;
    std::uint32_t value;
};

struct CountedMsg {
    static constexpr MsgId kMsgId = 0x0102;
    std::uint32_t count;  // at most 3
    double values[3];
};

struct BigMsg {
    static constexpr MsgId kMsgId = 0x0103;
    std::uint8_t bytes[1000];
};

// A task that takes pings as they are and refuses a counted message whose count
// is beyond what it holds, keeping the last good one.
struct Taker {
    std::uint32_t pings = 0;
    std::uint32_t lastPing = 0;
    CountedMsg counted{};
    std::uint32_t countedTaken = 0;
    std::uint32_t bigLast = 0;
    MsgId seenHeaderId = 0;
    InputPipe* pipe = nullptr;

    void takePing(const PingMsg& m) {
        ++pings;
        lastPing = m.value;
        if (pipe != nullptr) {
            seenHeaderId = pipe->current().id;
        }
    }
    Status takeCounted(const CountedMsg& m) {
        if (m.count > 3) {
            if (pipe != nullptr && m.count == 9) {
                pipe->explain("count %u beyond %u", static_cast<unsigned>(m.count), 3U);
            }
            return Status::kInvalidArgument;
        }
        counted = m;
        ++countedTaken;
        return Status::kOk;
    }
    void takeBig(const BigMsg& m) { bigLast = m.bytes[999]; }
};

// A task that counts a counted message that does not decode with its own
// refusals (as the trajectory follower counts a trajectory that does not).
struct OwnRefusals {
    std::uint32_t taken = 0;
    std::uint32_t undecodable = 0;
    std::uint16_t undecodableLength = 0;
    void takeCounted(const CountedMsg&) { ++taken; }
    void refuseUndecodable(const Message& m) {
        ++undecodable;
        undecodableLength = m.header.length;
    }
};

struct SecondTaker {
    std::uint32_t pings = 0;
    void takePing(const PingMsg&) { ++pings; }
};

}  // namespace

TEST_GROUP(InputPipe) {
    VirtualClock clock{1000};
    EventLog events{clock};
    SoftwareBus busStorage{clock, events};
    SoftwareBus* bus = &busStorage;
    InputPipe pipeStorage{*bus, events, InputPipeConfig{"taker", 4, kMalformed, "taker"}};
    InputPipe* pipe = &pipeStorage;
    Taker taker;

    void setup() override {
        CHECK(Status::kOk == pipe->create());
        CHECK(Status::kOk == (pipe->route<&Taker::takePing>(&taker)));
        CHECK(Status::kOk == (pipe->route<&Taker::takeCounted>(&taker)));
        taker.pipe = pipe;
    }
};

TEST(InputPipe, HandsEachMessageToItsHandlerDecoded) {
    CHECK(Status::kOk == bus->publish(PingMsg{7}));
    CountedMsg c{};
    c.count = 2;
    c.values[1] = 2.5;
    CHECK(Status::kOk == bus->publish(c));
    LONGS_EQUAL(2, pipe->drain());
    LONGS_EQUAL(1, taker.pings);
    LONGS_EQUAL(7, taker.lastPing);
    LONGS_EQUAL(PingMsg::kMsgId, taker.seenHeaderId);
    LONGS_EQUAL(1, taker.countedTaken);
    DOUBLES_EQUAL(2.5, taker.counted.values[1], 0.0);
    LONGS_EQUAL(0, pipe->malformed());
    LONGS_EQUAL(2, pipe->taken());
    LONGS_EQUAL(0, rse::test::drainEventsWithId(events, kMalformed));
}

TEST(InputPipe, RefusedContentIsCountedEventedAndKeepsTheLastGoodInput) {
    CountedMsg good{};
    good.count = 1;
    good.values[0] = 9.0;
    CHECK(Status::kOk == bus->publish(good));
    CountedMsg bad{};
    bad.count = 4;
    bad.values[0] = -1.0;
    CHECK(Status::kOk == bus->publish(bad));
    pipe->drain();
    LONGS_EQUAL(1, taker.countedTaken);
    DOUBLES_EQUAL(9.0, taker.counted.values[0], 0.0);
    LONGS_EQUAL(1, pipe->malformed());
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, kMalformed));
}

TEST(InputPipe, AMessageOfTheWrongSizeIsRefused) {
    // Published under the ping's id with a size the ping does not have.
    const std::uint8_t bytes[3] = {1, 2, 3};
    CHECK(Status::kOk == bus->publish(PingMsg::kMsgId, bytes, sizeof bytes));
    pipe->drain();
    LONGS_EQUAL(0, taker.pings);
    LONGS_EQUAL(1, pipe->malformed());
}

TEST(InputPipe, TheEventIsThrottledButEveryRefusalCounted) {
    const std::uint8_t bytes[3] = {1, 2, 3};
    unsigned evented = 0;
    for (int i = 0; i < 9; ++i) {
        CHECK(Status::kOk == bus->publish(PingMsg::kMsgId, bytes, sizeof bytes));
        pipe->drain();
        evented += rse::test::drainEventsWithId(events, kMalformed);
    }
    LONGS_EQUAL(9, pipe->malformed());
    LONGS_EQUAL(4, evented);  // the 1st, 2nd, 4th and 8th
}

TEST(InputPipe, TheEventNamesTheOwnerPipeIdAndReason) {
    const std::uint8_t bytes[3] = {1, 2, 3};
    CHECK(Status::kOk == bus->publish(PingMsg::kMsgId, bytes, sizeof bytes));
    pipe->drain();
    Event e;
    bool found = false;
    while (isOk(events.pop(&e))) {
        if (e.id == kMalformed) {
            found = true;
            CHECK(std::strstr(e.text, "taker: bus message 0x0101 (3 B) on pipe taker refused: wrong-type") != nullptr);
        }
    }
    CHECK(found);
}

TEST(InputPipe, ADrainTakesAtMostTheDepth) {
    // The bus keeps at most the depth (4) queued; the drain is bounded by it.
    for (std::uint32_t i = 0; i < 6; ++i) {
        CHECK(Status::kOk == bus->publish(PingMsg{i}));
    }
    LONGS_EQUAL(4, pipe->drain());
    LONGS_EQUAL(4, taker.pings);
    LONGS_EQUAL(3, taker.lastPing);
    LONGS_EQUAL(0, pipe->drain());
}

TEST(InputPipe, SeveralRoutesOfOneIdEachGetTheMessageInRouteOrder) {
    SecondTaker second;
    CHECK(Status::kOk == (pipe->route<&SecondTaker::takePing>(&second)));
    CHECK(Status::kOk == bus->publish(PingMsg{5}));
    pipe->drain();
    LONGS_EQUAL(1, taker.pings);
    LONGS_EQUAL(1, second.pings);
    LONGS_EQUAL(1, pipe->taken());
}

TEST(InputPipe, ALargeMessageDecodesInThePipesStorage) {
    CHECK(Status::kOk == (pipe->route<&Taker::takeBig>(&taker)));
    BigMsg big{};
    big.bytes[999] = 77;
    CHECK(Status::kOk == bus->publish(big));
    pipe->drain();
    LONGS_EQUAL(77, taker.bigLast);
}

TEST(InputPipe, RoutingIsRefusedBeforeCreateAndPastCapacity) {
    InputPipe fresh{*bus, events, InputPipeConfig{"fresh", 2, kMalformed, "fresh"}};
    CHECK(Status::kNotInitialized == (fresh.route<&Taker::takePing>(&taker)));
    CHECK(Status::kOk == fresh.create());
    CHECK(Status::kAlreadyExists == fresh.create());
    CHECK(Status::kInvalidArgument == (fresh.route<&Taker::takePing, Taker>(nullptr)));
    for (std::size_t i = 0; i < kMaxInputRoutes; ++i) {
        CHECK(Status::kOk == (fresh.route<&Taker::takePing>(&taker)));
    }
    CHECK(Status::kNoCapacity == (fresh.route<&Taker::takePing>(&taker)));
}

TEST(InputPipe, DrainBeforeCreateTakesNothing) {
    InputPipe fresh{*bus, events, InputPipeConfig{"fresh", 2, kMalformed, "fresh"}};
    LONGS_EQUAL(0, fresh.drain());
}

TEST(InputPipe, TheEventHasTheConfiguredSeverityErrorUnlessSaid) {
    const std::uint8_t bytes[3] = {1, 2, 3};
    CHECK(Status::kOk == bus->publish(PingMsg::kMsgId, bytes, sizeof bytes));
    pipe->drain();
    Event e;
    CHECK(isOk(events.pop(&e)));
    LONGS_EQUAL(kMalformed, e.id);
    CHECK(Severity::kError == e.severity);

    InputPipe warned{*bus, events, InputPipeConfig{"warned", 2, kMalformed, "warned", Severity::kWarning}};
    CHECK(Status::kOk == warned.create());
    CHECK(Status::kOk == (warned.route<&Taker::takePing>(&taker)));
    CHECK(Status::kOk == bus->publish(PingMsg::kMsgId, bytes, sizeof bytes));
    warned.drain();
    pipe->drain();
    bool found = false;
    while (isOk(events.pop(&e))) {
        if (std::strstr(e.text, "pipe warned") != nullptr) {
            found = true;
            CHECK(Severity::kWarning == e.severity);
        }
    }
    CHECK(found);
}

TEST(InputPipe, AnOwnersUndecodableHandlerTakesWhatDoesNotDecodeAndNothingIsCounted) {
    InputPipe own{*bus, events, InputPipeConfig{"own", 4, kMalformed, "own"}};
    OwnRefusals owner;
    CHECK(Status::kOk == own.create());
    CHECK(Status::kOk == (own.route<&OwnRefusals::takeCounted, &OwnRefusals::refuseUndecodable>(&owner)));
    LONGS_EQUAL(1, own.routeCount());
    const std::uint8_t bytes[5] = {1, 2, 3, 4, 5};
    CHECK(Status::kOk == bus->publish(CountedMsg::kMsgId, bytes, sizeof bytes));
    CHECK(Status::kOk == bus->publish(CountedMsg{}));
    LONGS_EQUAL(2, own.drain());
    LONGS_EQUAL(1, owner.undecodable);
    LONGS_EQUAL(5, owner.undecodableLength);
    LONGS_EQUAL(1, owner.taken);
    LONGS_EQUAL(0, own.malformed());
    LONGS_EQUAL(2, own.taken());
    // Another id nobody routed is still the pipe's to refuse.
    CHECK(Status::kOk == bus->subscribe(own.pipe(), PingMsg::kMsgId));
    CHECK(Status::kOk == bus->publish(PingMsg{1}));
    own.drain();
    LONGS_EQUAL(1, own.malformed());
    LONGS_EQUAL(1, owner.undecodable);
}

TEST(InputPipe, AHandlersExplanationNamesWhatIsWrongForThatMessageOnly) {
    CountedMsg explained{};
    explained.count = 9;  // the handler explains this one
    CountedMsg bare{};
    bare.count = 5;       // ... not this one: the status's name
    CHECK(Status::kOk == bus->publish(explained));
    CHECK(Status::kOk == bus->publish(bare));
    pipe->drain();
    LONGS_EQUAL(2, pipe->malformed());
    Event e;
    int seen = 0;
    while (isOk(events.pop(&e))) {
        if (e.id != kMalformed) {
            continue;
        }
        ++seen;
        if (seen == 1) {
            CHECK(std::strstr(e.text, "refused: count 9 beyond 3 (1 so far)") != nullptr);
        } else {
            CHECK(std::strstr(e.text, "refused: invalid-argument (2 so far)") != nullptr);
        }
    }
    LONGS_EQUAL(2, seen);
}

// EVENT_DATA paired with its EVENT (ground/event_data_pairing.hpp): by
// event_sequence and event id in the order received; numbers whose event never
// came are stray, events whose numbers never came are missing; the latest
// event with a sequence wins (a rover restarted); the window is bounded.
#include <cstdint>
#include <optional>

#include "fsw/cmdtlm/event_data.hpp"
#include "ground/event_data_pairing.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

constexpr std::uint16_t kLegSent = 905;  // carries numbers (LEG_SENT)
constexpr std::uint16_t kPlanSent = 803;  // carries none

ground::EventDataPacket numbers(std::uint32_t sequence, std::uint16_t id, double first) {
    ground::EventDataPacket d;
    d.sequence = sequence;
    d.id = id;
    d.data.count = 8;
    d.data.values[0] = first;
    return d;
}

}  // namespace

TEST_GROUP(EventDataPairing) {
    ground::EventDataPairing pairing;
};

TEST(EventDataPairing, EachEventDataGoesToItsEventInOrderOrNot) {
    pairing.onEvent(10, kLegSent, 100);
    pairing.onEvent(11, kPlanSent, 101);  // no numbers expected
    pairing.onEvent(12, kLegSent, 102);
    LONGS_EQUAL(2, pairing.missing());
    // 12's numbers before 10's: paired by sequence, not by position.
    std::optional<std::size_t> h = pairing.onData(numbers(12, kLegSent, 2.0));
    CHECK_TRUE(h.has_value());
    LONGS_EQUAL(102, *h);
    h = pairing.onData(numbers(10, kLegSent, 1.0));
    CHECK_TRUE(h.has_value());
    LONGS_EQUAL(100, *h);
    LONGS_EQUAL(2, pairing.paired());
    LONGS_EQUAL(0, pairing.missing());
    LONGS_EQUAL(0, pairing.stray());
    // Twice the same numbers: the second has no event left (stray).
    CHECK_FALSE(pairing.onData(numbers(10, kLegSent, 1.0)).has_value());
    LONGS_EQUAL(1, pairing.stray());
}

TEST(EventDataPairing, LostAndStrayAreCounted) {
    pairing.onEvent(20, kLegSent, 0);  // its numbers never come
    pairing.onEvent(21, kLegSent, 1);
    CHECK_TRUE(pairing.onData(numbers(21, kLegSent, 0.0)).has_value());
    LONGS_EQUAL(1, pairing.missing());
    // Numbers of an event never received, of another id at a known sequence, of an event without numbers.
    CHECK_FALSE(pairing.onData(numbers(30, kLegSent, 0.0)).has_value());
    CHECK_FALSE(pairing.onData(numbers(20, 906, 0.0)).has_value());
    pairing.onEvent(22, kPlanSent, 2);
    CHECK_FALSE(pairing.onData(numbers(22, kPlanSent, 0.0)).has_value());
    LONGS_EQUAL(3, pairing.stray());
    LONGS_EQUAL(1, pairing.paired());
    LONGS_EQUAL(1, pairing.missing());
}

TEST(EventDataPairing, TheLatestEventWithTheSequenceWinsAndTheWindowIsBounded) {
    pairing.onEvent(5, kLegSent, 1);  // before a restart, never paired
    pairing.onEvent(5, kLegSent, 2);  // after it: sequences began again
    const std::optional<std::size_t> h = pairing.onData(numbers(5, kLegSent, 0.0));
    CHECK_TRUE(h.has_value());
    LONGS_EQUAL(2, *h);
    for (std::uint32_t s = 100; s < 100 + ground::EventDataPairing::kPairingWindow + 5; ++s) {
        pairing.onEvent(s, kLegSent, s);
    }
    // The oldest fell out of the window: its numbers are stray now; the newest pair.
    CHECK_FALSE(pairing.onData(numbers(100, kLegSent, 0.0)).has_value());
    CHECK_TRUE(pairing.onData(numbers(100 + ground::EventDataPairing::kPairingWindow + 4, kLegSent, 0.0)).has_value());
}

TEST(EventDataPairing, AnEventDataPacketIsReadWithItsNumbers) {
    cmdtlm::EVENT_DATA_Tlm d{};
    d.event_sequence = 77;
    d.event_id = kLegSent;
    d.value_count = 3;
    d.value[0] = 4.0;
    d.value[2] = -0.47;
    d.data_withheld = 2;
    ground::EventDataPacket out;
    CHECK_TRUE(ground::readEventData(ground::decodeTelemetry(test::telemetryPacket(d)), &out));
    LONGS_EQUAL(77, out.sequence);
    LONGS_EQUAL(kLegSent, out.id);
    LONGS_EQUAL(3, out.data.count);
    DOUBLES_EQUAL(-0.47, out.data.values[2], 0.0);
    LONGS_EQUAL(2, out.withheld);
    cmdtlm::EVENT_Tlm e{};
    CHECK_FALSE(ground::readEventData(ground::decodeTelemetry(test::telemetryPacket(e)), &out));
    pairing.onEvent(77, kLegSent, 9);
    (void)pairing.onData(out);
    LONGS_EQUAL(2, pairing.withheld());
}

// Telemetry output: every packet goes to each active link with its downlink
// priority (CMD_ACK, then EVENT, then the rest), and every refusal is counted per
// priority and evented (the 1st, 2nd, 4th ... of each priority).
#include <cstdint>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/ground_links.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/link/packet_link.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::cmdtlm;

namespace {

// Records the priority of each packet offered; refuses those whose priority is
// in `refuse`.
class PriorityLink final : public hal::PacketLink {
public:
    core::Status receive(std::uint8_t*, std::size_t, std::size_t*) override { return core::Status::kEmpty; }
    core::Status send(const std::uint8_t* data, std::size_t length) override {
        plainSends++;
        return sendWithPriority(data, length, hal::TxPriority::kRoutine);
    }
    core::Status sendWithPriority(const std::uint8_t*, std::size_t, hal::TxPriority priority) override {
        last = priority;
        ++offered;
        return refuse[static_cast<std::size_t>(priority)] ? core::Status::kFull : core::Status::kOk;
    }
    bool downlinkActive() const override { return active; }
    const char* name() const override { return "prio"; }
    const hal::PacketLinkStats& stats() const override { return stats_; }

    bool active = true;
    bool refuse[hal::kTxPriorityCount] = {};
    hal::TxPriority last = hal::TxPriority::kRoutine;
    unsigned offered = 0;
    unsigned plainSends = 0;

private:
    hal::PacketLinkStats stats_;
};

}  // namespace

TEST_GROUP(TelemetryOutput) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    GroundLinks links;
    PriorityLink link;
    TelemetryOutput output{clock, events, links};

    void setup() override { CHECK(core::isOk(links.add(&link))); }
};

TEST(TelemetryOutput, AcknowledgementsAndEventsGoWithTheirPriority) {
    CHECK(hal::TxPriority::kAck == telemetryPriority(CMD_ACK_Tlm::kApid));
    CHECK(hal::TxPriority::kEvent == telemetryPriority(EVENT_Tlm::kApid));
    CHECK(hal::TxPriority::kRoutine == telemetryPriority(HK_Tlm::kApid));
    CHECK(hal::TxPriority::kRoutine == telemetryPriority(TABLE_DUMP_Tlm::kApid));

    output.send(CMD_ACK_Tlm{});
    CHECK(hal::TxPriority::kAck == link.last);
    output.send(EVENT_Tlm{});
    CHECK(hal::TxPriority::kEvent == link.last);
    output.send(HK_Tlm{});
    CHECK(hal::TxPriority::kRoutine == link.last);
    LONGS_EQUAL(3, link.offered);
    LONGS_EQUAL(0, link.plainSends);  // always through sendWithPriority
    LONGS_EQUAL(3, output.sent());
    LONGS_EQUAL(0, output.dropped());
}

TEST(TelemetryOutput, RefusalsAreCountedAndEventedPerPriority) {
    link.refuse[static_cast<std::size_t>(hal::TxPriority::kRoutine)] = true;
    for (int i = 0; i < 5; ++i) {
        output.send(HK_Tlm{});
    }
    LONGS_EQUAL(5, output.dropped());
    LONGS_EQUAL(5, output.dropped(hal::TxPriority::kRoutine));
    LONGS_EQUAL(3, rse::test::drainEventsWithId(events, events::kTelemetryDropped));  // 1st, 2nd, 4th
    // Routine drops do not use up the events of an acknowledgement's first drop.
    link.refuse[static_cast<std::size_t>(hal::TxPriority::kAck)] = true;
    output.send(CMD_ACK_Tlm{});
    LONGS_EQUAL(1, output.dropped(hal::TxPriority::kAck));
    LONGS_EQUAL(0, output.dropped(hal::TxPriority::kEvent));
    LONGS_EQUAL(6, output.dropped());
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(events::kTelemetryDropped, e.id);
    STRCMP_CONTAINS("1 acknowledgement packets dropped", e.text);
    output.resetCounters();
    LONGS_EQUAL(0, output.dropped());
    LONGS_EQUAL(0, output.dropped(hal::TxPriority::kAck));
    LONGS_EQUAL(0, output.dropped(hal::TxPriority::kRoutine));
}

TEST(TelemetryOutput, ALinkNotListeningIsNotOfferedAndNothingCountsAsDropped) {
    link.active = false;
    output.send(CMD_ACK_Tlm{});
    LONGS_EQUAL(0, link.offered);
    LONGS_EQUAL(0, output.sent());
    LONGS_EQUAL(0, output.dropped());
}

// The telemetry task, a scheduler that knows no packet: each run drains its one
// pipe into the packers that routed each id, sends the events, then has each
// packer pack in registration order. And the event downlink it runs: an
// event's numbers in an EVENT_DATA right after its EVENT, never in an EVENT's
// place.
#include <string>
#include <vector>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/telemetry_task.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "hal/link/memory_packet_link.hpp"
#include "unit_test/support/app_test_support.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

// Records the order of what it is asked, and sends one NOOP-sized packet per pack.
class FakePacker final : public cmdtlm::TelemetryPacker {
public:
    FakePacker(const char* name, std::vector<std::string>* log) : name_(name), log_(log) {}
    core::Status routeInputs(core::InputPipe& pipe) override {
        log_->push_back(std::string(name_) + " routes");
        return pipe.route<&FakePacker::takeMode>(this);
    }
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override {
        log_->push_back(std::string(name_) + " packs " + std::to_string(frame.frame) + " mode " +
                        std::to_string(static_cast<unsigned>(mode_.mode)));
        cmdtlm::POWER_Tlm tlm{};
        sink.send(tlm);
    }

private:
    core::Status takeMode(const msg::ModeMsg& m) {
        if (m.mode >= msg::mode::kCount) {
            return core::Status::kInvalidArgument;
        }
        log_->push_back(std::string(name_) + " takes");
        mode_ = m;
        return core::Status::kOk;
    }
    const char* name_;
    std::vector<std::string>* log_;
    msg::ModeMsg mode_{};
};

}  // namespace

TEST_GROUP(TelemetryTask) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    hal::MemoryPacketLink link;
    cmdtlm::GroundLinks links;
    cmdtlm::TelemetryOutput output{clock, events, links};
    cmdtlm::TelemetryTask task{bus, events, output};
    std::vector<std::string> log;
    FakePacker first{"first", &log};
    FakePacker second{"second", &log};
    void setup() override { CHECK(core::isOk(links.add(&link))); }
    // The APIDs the ground received, in order.
    std::vector<std::uint16_t> downlink() {
        std::vector<std::uint16_t> apids;
        for (const test::RecordingSink::Packet& p : received()) {
            apids.push_back(p.apid);
        }
        return apids;
    }
    // The packets the ground received, in order.
    std::vector<test::RecordingSink::Packet> received() {
        std::vector<test::RecordingSink::Packet> out;
        std::uint8_t bytes[hal::kMemoryLinkMaxPacket];
        std::size_t length = 0;
        while (core::isOk(link.groundReceive(bytes, sizeof bytes, &length))) {
            out.push_back(test::RecordingSink::Packet{cmdtlm::decodePrimaryHeader(bytes).apid,
                                                      {bytes + cmdtlm::kTelemetryHeaderSize, bytes + length}});
        }
        return out;
    }
    static core::EventData numbers(double first) {
        core::EventData d;
        d.count = 3;
        d.values[0] = first;
        d.values[1] = -0.5;
        d.values[2] = 1e-9;
        return d;
    }
};

TEST(TelemetryTask, DrainsThenSendsTheEventsThenPacksInRegistrationOrder) {
    CHECK(core::isOk(task.add(&first)));
    CHECK(core::isOk(task.add(&second)));
    CHECK(core::isOk(task.init()));
    LONGS_EQUAL(2, task.packerCount());
    (void)downlink();
    (void)test::drainEventsWithId(events, 0);
    msg::ModeMsg m{};
    m.mode = msg::mode::kManual;
    CHECK(core::isOk(bus.publish(m)));
    events.report(999, core::Severity::kInfo, "an event");
    task.run(test::frameAt(4));
    const std::vector<std::string> expected = {"first routes",        "second routes",       "first takes",
                                               "second takes",        "first packs 4 mode 3", "second packs 4 mode 3"};
    LONGS_EQUAL(expected.size(), log.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        STRCMP_EQUAL(expected[i].c_str(), log[i].c_str());
    }
    const std::vector<std::uint16_t> apids = downlink();
    LONGS_EQUAL(3, apids.size());
    LONGS_EQUAL(cmdtlm::EVENT_Tlm::kApid, apids[0]);
    LONGS_EQUAL(cmdtlm::POWER_Tlm::kApid, apids[1]);
    LONGS_EQUAL(1, task.eventsSent());
}

TEST(TelemetryTask, AnInputThatDoesNotDecodeOrThatAPackerRefusesIsCountedAndEvented) {
    CHECK(core::isOk(task.add(&first)));
    CHECK(core::isOk(task.init()));
    const std::uint8_t garbage[3] = {};
    CHECK(core::isOk(bus.publish(msg::ids::kMode, garbage, sizeof garbage)));
    msg::ModeMsg noMode{};
    noMode.mode = 9;
    CHECK(core::isOk(bus.publish(noMode)));
    task.run(test::frameAt(1));
    LONGS_EQUAL(2, task.malformed());
    // Evented (211, ERROR) as they are drained, so the same run sends the events down.
    LONGS_EQUAL(2, events.count(core::Severity::kError));
    std::uint8_t bytes[hal::kMemoryLinkMaxPacket];
    std::size_t length = 0;
    unsigned malformed = 0;
    while (core::isOk(link.groundReceive(bytes, sizeof bytes, &length))) {
        if (cmdtlm::decodePrimaryHeader(bytes).apid == cmdtlm::EVENT_Tlm::kApid) {
            test::RecordingSink::Packet p{cmdtlm::EVENT_Tlm::kApid,
                                          {bytes + cmdtlm::kTelemetryHeaderSize, bytes + length}};
            malformed += test::RecordingSink::field(p, "event_id") == cmdtlm::events::kBusMessageMalformed ? 1U : 0U;
        }
    }
    LONGS_EQUAL(2, malformed);
}

TEST(TelemetryTask, PackersAreRefusedWhenNullBeyondTheTableOrAfterInit) {
    CHECK(core::Status::kInvalidArgument == task.add(nullptr));
    for (std::size_t i = 0; i < cmdtlm::kMaxTelemetryPackers; ++i) {
        CHECK(core::isOk(task.add(&first)));
    }
    CHECK(core::Status::kNoCapacity == task.add(&second));
    LONGS_EQUAL(2, test::drainEventsWithId(events, cmdtlm::events::kAppRegistrationRefused));
    cmdtlm::TelemetryTask other{bus, events, output};
    CHECK(core::isOk(other.init()));
    CHECK(core::Status::kAlreadyExists == other.add(&first));
}

TEST(TelemetryTask, EventsGoAtMostEightAFrameAndNoFasterThanTheLinksTakeThem) {
    CHECK(core::isOk(task.init()));
    (void)downlink();
    (void)test::drainEventsWithId(events, 0);
    for (int i = 0; i < 40; ++i) {
        events.report(999, core::Severity::kInfo, "burst %d", i);
    }
    // The ground reads nothing: the link's 32 places fill in four frames.
    for (std::uint64_t n = 1; n <= 5; ++n) {
        task.run(test::frameAt(n));
        LONGS_EQUAL(n < 5 ? 8 * n : 32, link.downlinkQueued());
    }
    LONGS_EQUAL(32, downlink().size());
    task.run(test::frameAt(6));  // the rest waited in the event log
    LONGS_EQUAL(cmdtlm::kEventsPerFrame, downlink().size());
    LONGS_EQUAL(40, task.eventsSent());
    LONGS_EQUAL(0, events.lost());
    LONGS_EQUAL(0, output.dropped());
}

// Each event that carries numbers is followed at once by its EVENT_DATA (the
// same event_sequence, id and values); the frame's budget counts EVENT packets
// only, as before: eight events a frame with their numbers is sixteen packets.
TEST(TelemetryTask, AnEventsNumbersFollowItAndTheBudgetCountsEventsOnly) {
    CHECK(core::isOk(task.init()));
    (void)downlink();
    (void)test::drainEventsWithId(events, 0);
    for (int i = 0; i < 10; ++i) {
        if (i % 2 == 0) {
            events.report(905, core::Severity::kInfo, numbers(i), "with numbers %d", i);
        } else {
            events.report(803, core::Severity::kInfo, "without %d", i);
        }
    }
    task.run(test::frameAt(1));
    const std::vector<test::RecordingSink::Packet> got = received();
    LONGS_EQUAL(8 + 4, got.size());  // 8 EVENTs (the budget), the 4 of them with numbers followed by theirs
    LONGS_EQUAL(8, task.eventsSent());
    LONGS_EQUAL(4, task.eventDataSent());
    for (std::size_t i = 0, event = 0; i < got.size(); ++i, ++event) {
        LONGS_EQUAL(cmdtlm::EVENT_Tlm::kApid, got[i].apid);
        if (event % 2 != 0) {
            continue;
        }
        const test::RecordingSink::Packet& data = got[++i];
        LONGS_EQUAL(cmdtlm::EVENT_DATA_Tlm::kApid, data.apid);
        using test::RecordingSink;
        DOUBLES_EQUAL(RecordingSink::field(got[i - 1], "event_sequence"), RecordingSink::field(data, "event_sequence"),
                      0.0);
        DOUBLES_EQUAL(905, RecordingSink::field(data, "event_id"), 0.0);
        DOUBLES_EQUAL(3, RecordingSink::field(data, "value_count"), 0.0);
        DOUBLES_EQUAL(static_cast<double>(event), RecordingSink::field(data, "value", 0), 0.0);
        DOUBLES_EQUAL(1e-9, RecordingSink::field(data, "value", 2), 0.0);
        DOUBLES_EQUAL(0, RecordingSink::field(data, "value", 3), 0.0);
    }
    CHECK(hal::TxPriority::kEvent == cmdtlm::telemetryPriority(cmdtlm::EVENT_DATA_Tlm::kApid));
}

// A link whose event queue has room for ten packets: the eight EVENTs of the
// frame go out as they would without numbers; only the numbers that would take
// an EVENT's place are withheld (counted, evented 511 on the 1st, 2nd, 4th
// time), none refused by the link.
TEST(TelemetryTask, NumbersNeverTakeAnEventsPlaceOnAFullQueue) {
    CHECK(core::isOk(task.init()));
    (void)downlink();
    (void)test::drainEventsWithId(events, 0);
    for (int i = 0; i < 22; ++i) {
        output.send(cmdtlm::POWER_Tlm{});  // the queue keeps 10 places
    }
    for (int i = 0; i < 8; ++i) {
        events.report(905, core::Severity::kInfo, numbers(i), "burst %d", i);
    }
    task.run(test::frameAt(1));
    LONGS_EQUAL(hal::kMemoryLinkDownlinkDepth, link.downlinkQueued());
    LONGS_EQUAL(8, task.eventsSent());
    LONGS_EQUAL(2, task.eventDataSent());
    LONGS_EQUAL(6, task.eventDataWithheld());
    LONGS_EQUAL(0, output.dropped());
    std::size_t eventPackets = 0;
    for (std::uint16_t apid : downlink()) {
        eventPackets += apid == cmdtlm::EVENT_Tlm::kApid ? 1U : 0U;
    }
    LONGS_EQUAL(8, eventPackets);
    LONGS_EQUAL(3, test::drainEventsWithId(events, cmdtlm::events::kEventDataWithheld));
}

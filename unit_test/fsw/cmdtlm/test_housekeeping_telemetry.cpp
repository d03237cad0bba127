// HK and TASK_TIMING: HK in slot 0 and after REQUEST_HK, the executive's,
// bus's and event log's counters from the collection, every other field from
// its owner; TASK_TIMING row i in slot 10 + i, from the last HK's collection.
#include "fsw/cmdtlm/housekeeping_telemetry.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::RecordingSink;

namespace {

struct CountingTask final : core::Task {
    void run(const core::FrameContext&) override {}
};

// An owner of two HK fields.
struct CanFields final : cmdtlm::HousekeepingContributor {
    void fillHousekeeping(cmdtlm::HK_Tlm& hk) const override {
        hk.can_rx_frames = 123;
        hk.can_bus_off = 2;
    }
};

}  // namespace

TEST_GROUP(HousekeepingTelemetry) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    core::Executive executive{clock, events};
    cmdtlm::HousekeepingTask collection{executive, bus, events};
    cmdtlm::HousekeepingTelemetry packer{collection};
    CountingTask a, b;
    CanFields can;
    RecordingSink sink;
    void setup() override {
        const core::RateGroupEntry table[] = {{"alpha", &a, 1, 0, 1000}, {"beta", &b, 10, 0, 1000}};
        CHECK(core::isOk(executive.init(core::ExecutiveConfig{10 * core::kNsPerMs, 100}, table, 2)));
    }
};

TEST(HousekeepingTelemetry, HkGoesInSlotZeroWithTheCollectionAndEachOwnersFields) {
    CHECK(core::isOk(packer.addContributor(&can)));
    packer.setUtcAtMetZero(1.7e9);
    packer.setTimeScale(4);
    events.report(999, core::Severity::kError, "one error");
    for (std::uint64_t n = 0; n < 100; ++n) {
        packer.pack(test::frameAt(n), sink);
    }
    LONGS_EQUAL(1, sink.count<cmdtlm::HK_Tlm>());
    LONGS_EQUAL(1, packer.housekeepingSent());
    const RecordingSink::Packet& hk = sink.last<cmdtlm::HK_Tlm>();
    DOUBLES_EQUAL(1.7e9, RecordingSink::field(hk, "utc_at_met_zero"), 0.0);
    DOUBLES_EQUAL(4, RecordingSink::field(hk, "time_scale"), 0.0);
    DOUBLES_EQUAL(2, RecordingSink::field(hk, "task_count"), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(hk, "events_total"), 0.0);
    DOUBLES_EQUAL(1, RecordingSink::field(hk, "events_by_severity", static_cast<std::size_t>(core::Severity::kError)),
                  0.0);
    DOUBLES_EQUAL(123, RecordingSink::field(hk, "can_rx_frames"), 0.0);
    DOUBLES_EQUAL(2, RecordingSink::field(hk, "can_bus_off"), 0.0);
    DOUBLES_EQUAL(0, RecordingSink::field(hk, "cmd_accepted"), 0.0);  // nobody registered for it
}

TEST(HousekeepingTelemetry, ARequestSendsHkInTheNextRunOnly) {
    packer.pack(test::frameAt(1), sink);
    packer.requestHousekeeping();
    packer.pack(test::frameAt(2), sink);
    packer.pack(test::frameAt(3), sink);
    LONGS_EQUAL(1, sink.count<cmdtlm::HK_Tlm>());
}

TEST(HousekeepingTelemetry, TaskTimingRowIGoesInSlotTenPlusIFromTheLastCollection) {
    for (std::uint64_t n = 0; n < 100; ++n) {
        packer.pack(test::frameAt(n), sink);
    }
    LONGS_EQUAL(2, sink.count<cmdtlm::TASK_TIMING_Tlm>());
    const RecordingSink::Packet& second = sink.packets.back();
    LONGS_EQUAL(cmdtlm::TASK_TIMING_Tlm::kApid, second.apid);
    DOUBLES_EQUAL(1, RecordingSink::field(second, "task_index"), 0.0);
    DOUBLES_EQUAL('b', RecordingSink::field(second, "task_name"), 0.0);  // "beta"
    // The rows follow HK's collection: none before the first HK.
    cmdtlm::HousekeepingTelemetry fresh{collection};
    RecordingSink other;
    fresh.pack(test::frameAt(10), other);
    LONGS_EQUAL(0, other.packets.size());
}

TEST(HousekeepingTelemetry, ContributorsAreBoundedAndNeverNull) {
    CHECK(core::Status::kInvalidArgument == packer.addContributor(nullptr));
    for (std::size_t i = 0; i < cmdtlm::kMaxHousekeepingContributors; ++i) {
        CHECK(core::isOk(packer.addContributor(&can)));
    }
    CHECK(core::Status::kNoCapacity == packer.addContributor(&can));
}

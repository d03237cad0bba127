// The command router: each accepted command to the application that owns its
// APID, the onboard requests to their owners, RESET_COUNTERS to every
// application; registrations refused with a status and an event.
#include <string>
#include <vector>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/command_router.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "unit_test/support/app_test_support.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using cmdtlm::CommandCode;

namespace {

// An application that records what reached it.
class FakeApp final : public cmdtlm::AppCommands {
public:
    FakeApp(std::uint16_t apid, std::vector<std::string>* log, const char* name) : apid_(apid), log_(log), name_(name) {}
    std::uint16_t apid() const override { return apid_; }
    cmdtlm::CommandOutcome execute(const cmdtlm::CommandVerdict& verdict) override {
        log_->push_back(std::string(name_) + " " + verdict.command->name);
        return cmdtlm::commandFailed(42);
    }
    void serviceOnboardRequests(cmdtlm::Mode mode) override {
        log_->push_back(std::string(name_) + " serviced in mode " + std::to_string(static_cast<int>(mode)));
    }
    void resetCounters() override { log_->push_back(std::string(name_) + " reset"); }

private:
    std::uint16_t apid_;
    std::vector<std::string>* log_;
    const char* name_;
};

}  // namespace

TEST_GROUP(CommandRouter) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    cmdtlm::RoverMode mode{clock, bus, events};
    cmdtlm::CommandRouter router{bus, events, mode};
    std::vector<std::string> log;
    FakeApp goals{0x181, &log, "goals"};
    FakeApp tables{0x183, &log, "tables"};
};

TEST(CommandRouter, EachCommandGoesToTheOwnerOfItsApid) {
    CHECK(core::isOk(router.add(&goals)));
    CHECK(core::isOk(router.add(&tables)));
    LONGS_EQUAL(2, router.size());
    const test::AcceptedCommand dump(CommandCode::TABLE_DUMP, cmdtlm::TABLE_DUMP_Args{1, 0});
    const test::AcceptedCommand clear(CommandCode::CLEAR_GOALS);
    const cmdtlm::CommandOutcome outcome = router.execute(dump.verdict());
    CHECK_FALSE(outcome.ok);
    LONGS_EQUAL(42, outcome.detail);  // the owner's outcome, as it is
    (void)router.execute(clear.verdict());
    LONGS_EQUAL(2, log.size());
    STRCMP_EQUAL("tables TABLE_DUMP", log[0].c_str());
    STRCMP_EQUAL("goals CLEAR_GOALS", log[1].c_str());
}

TEST(CommandRouter, ACommandNobodyOwnsFailsAndIsCountedAndEvented) {
    CHECK(core::isOk(router.add(&goals)));
    const test::AcceptedCommand noop(CommandCode::NOOP);
    const cmdtlm::CommandOutcome outcome = router.execute(noop.verdict());
    CHECK_FALSE(outcome.ok);
    LONGS_EQUAL(-1, outcome.detail);
    LONGS_EQUAL(1, router.commandsWithoutOwner());
    LONGS_EQUAL(1, test::drainEventsWithId(events, cmdtlm::events::kCommandWithoutOwner));
    CHECK(log.empty());
}

TEST(CommandRouter, AnApidOwnedTwiceANullOwnerAndAFullTableAreRefused) {
    CHECK(core::isOk(router.add(&goals)));
    FakeApp again{0x181, &log, "again"};
    CHECK(core::Status::kAlreadyExists == router.add(&again));
    CHECK(core::Status::kInvalidArgument == router.add(nullptr));
    LONGS_EQUAL(2, test::drainEventsWithId(events, cmdtlm::events::kAppRegistrationRefused));
    std::vector<FakeApp> more;
    more.reserve(cmdtlm::kMaxAppCommands);
    for (std::uint16_t i = 0; i < cmdtlm::kMaxAppCommands; ++i) {
        more.emplace_back(static_cast<std::uint16_t>(0x190 + i), &log, "more");
    }
    for (std::size_t i = 0; i + 1 < cmdtlm::kMaxAppCommands; ++i) {
        CHECK(core::isOk(router.add(&more[i])));
    }
    CHECK(core::Status::kNoCapacity == router.add(&more.back()));
    LONGS_EQUAL(cmdtlm::kMaxAppCommands, router.size());
}

TEST(CommandRouter, TheModeIsTheModeOwners) {
    CHECK(cmdtlm::Mode::kSafe == router.mode());
    mode.setMode(cmdtlm::Mode::kManual);
    CHECK(cmdtlm::Mode::kManual == router.mode());
}

TEST(CommandRouter, OnboardRequestsGoToTheirOwnersThenEachAppIsServicedInRegistrationOrder) {
    CHECK(core::isOk(router.init()));
    CHECK(core::isOk(mode.routeRequests(router.requests())));
    CHECK(core::isOk(router.add(&tables)));
    CHECK(core::isOk(router.add(&goals)));
    mode.setMode(cmdtlm::Mode::kAutonomous);
    msg::SafeRequestMsg call{};
    call.reason = msg::CallHomeReason::kMobilityLost;
    CHECK(core::isOk(bus.publish(call)));
    router.serviceOnboardRequests();
    CHECK(cmdtlm::Mode::kSafe == mode.mode());
    LONGS_EQUAL(1, mode.safeRequests());
    LONGS_EQUAL(2, log.size());
    // Each in the mode the onboard requests left: SAFE (0) after the call home.
    STRCMP_EQUAL("tables serviced in mode 0", log[0].c_str());
    STRCMP_EQUAL("goals serviced in mode 0", log[1].c_str());
    // One that does not decode: counted by the pipe, evented (211), not acted on.
    const std::uint8_t shortRequest[3] = {};
    CHECK(core::isOk(bus.publish(msg::ids::kSafeRequest, shortRequest, sizeof shortRequest)));
    (void)test::drainEventsWithId(events, 0);
    router.serviceOnboardRequests();
    LONGS_EQUAL(1, router.malformedRequests());
    LONGS_EQUAL(1, mode.safeRequests());
    LONGS_EQUAL(1, test::drainEventsWithId(events, cmdtlm::events::kBusMessageMalformed));
    // No request: each application in the mode as it is (MANUAL, 3).
    mode.setMode(cmdtlm::Mode::kManual);
    log.clear();
    router.serviceOnboardRequests();
    STRCMP_EQUAL("tables serviced in mode 3", log[0].c_str());
    STRCMP_EQUAL("goals serviced in mode 3", log[1].c_str());
}

TEST(CommandRouter, ResetReachesEveryApplication) {
    CHECK(core::isOk(router.add(&goals)));
    CHECK(core::isOk(router.add(&tables)));
    router.resetAppCounters();
    LONGS_EQUAL(2, log.size());
    STRCMP_EQUAL("goals reset", log[0].c_str());
    STRCMP_EQUAL("tables reset", log[1].c_str());
}

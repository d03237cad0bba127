// Opportunistic science, PLAN_EXTEND (plan_extension.hpp), on the executive's
// parts without the task: refused (976, counted, the reason kept) for an
// extra time out of range, an unknown name, a waiting activity, beyond its
// ub, and while another awaits its instrument; accepted: the follow-on sent
// (974: a fresh id continuing the command, the extra work), committed when
// the instrument's status names it (975; the activity's command is the
// follow-on's from then on) and the activity completing with it (977); the
// instrument refusing it (976, the activity goes on); the activity ending
// before the answer dropping it.
#include <cstdint>
#include <cstring>

#include "fsw/plan_executive/plan_executive_events.hpp"
#include "unit_test/fsw/plan_executive/executive_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using msg::PlanExtensionRefusal;
using plan_executive::ActivityState;
namespace ev = plan_executive::events;

namespace {

// A sample of [10, 100] s, then a wait.
constexpr const char* kSampleThenWait =
    "plan ext;event e;event f;activity s sample start e [10, 100] cost 1 target 1;activity w wait e f [1, 2];end";

test::ExecutiveParts* parts = nullptr;

msg::PlanCommandMsg extend(const char* name, std::uint32_t extraMs) {
    msg::PlanCommandMsg m{};
    m.kind = msg::PlanCommandKind::kExtend;
    m.extendMs = extraMs;
    m.length = static_cast<std::uint16_t>(std::strlen(name));
    std::memcpy(m.data, name, m.length);
    return m;
}

}  // namespace

TEST_GROUP(PlanExtension) {
    std::uint16_t sampleId = 0;

    void setup() override {
        parts = new test::ExecutiveParts();
        CHECK_TRUE(parts->init());
        CHECK_TRUE(parts->adopt(kSampleThenWait));
        parts->advance();
        CHECK(parts->state(0) == ActivityState::kRunning);
        sampleId = parts->lastInstrument.commandId;
        parts->tick(50);  // 5 s into the sample
    }
    void teardown() override {
        delete parts;
        parts = nullptr;
    }
    void refused(const char* name, std::uint32_t extraMs, PlanExtensionRefusal why) {
        const std::uint32_t before = parts->extension.counters().refused;
        const std::uint32_t sent = parts->instrumentCommands;
        parts->extension.request(extend(name, extraMs));
        parts->drain();
        LONGS_EQUAL(before + 1, parts->extension.counters().refused);
        LONGS_EQUAL(static_cast<long>(why), static_cast<long>(parts->extension.counters().lastRefusal));
        LONGS_EQUAL(sent, parts->instrumentCommands);  // nothing sent
    }
    // The follow-on for the sample sent: its id.
    std::uint16_t followOnSent(std::uint32_t extraMs) {
        parts->extension.request(extend("s", extraMs));
        parts->drain();
        LONGS_EQUAL(1, parts->count(ev::kExtensionRequested));
        CHECK_TRUE(parts->extension.pendingFor(0));
        CHECK(parts->lastInstrument.action == msg::InstrumentAction::kExtend);
        LONGS_EQUAL(sampleId, parts->lastInstrument.extendsCommandId);
        CHECK(parts->lastInstrument.commandId != sampleId);
        return parts->lastInstrument.commandId;
    }
};

TEST(PlanExtension, RequestsAreRefusedWithTheirReasonAndNothingSent) {
    refused("s", 0, PlanExtensionRefusal::kInvalid);
    refused("s", plan_executive::PlanExtension::kMaxExtendMs + 1, PlanExtensionRefusal::kInvalid);
    refused("nope", 1000, PlanExtensionRefusal::kUnknownActivity);
    refused("w", 1000, PlanExtensionRefusal::kNotRunning);      // waiting
    refused("s", 200000, PlanExtensionRefusal::kBeyondUb);       // 5 s + 200 s > its ub, 100 s
    parts->ctx.job = plan_executive::SelectionJob::kRegenerate;  // a selection under way
    refused("s", 1000, PlanExtensionRefusal::kBusy);
    parts->ctx.job = plan_executive::SelectionJob::kNone;
    LONGS_EQUAL(6, parts->count(ev::kExtensionRefused));
    LONGS_EQUAL(0, parts->extension.counters().accepted);
}

TEST(PlanExtension, AFollowOnTakenIsCommittedAndTheActivityCompletesWithIt) {
    const std::uint16_t followOn = followOnSent(20000);
    DOUBLES_EQUAL(20.0, parts->lastInstrument.maxDurationS, 1e-9);
    refused("s", 1000, PlanExtensionRefusal::kBusy);  // one at a time
    parts->tick();
    parts->reportInstrument(parts->instrumentStatus(msg::Instrument::kGrinder, msg::InstrumentState::kBusy, followOn));
    LONGS_EQUAL(1, parts->count(ev::kExtensionAccepted));
    LONGS_EQUAL(1, parts->extension.counters().accepted);
    CHECK_FALSE(parts->extension.pendingFor(0));
    LONGS_EQUAL(followOn, parts->devices.commandId(0));
    CHECK(parts->extension.endBeforeExtensionMs(0) > 0);
    LONGS_EQUAL(0, parts->regenerationsStarted);  // the network stays in its range
    // Done under the follow-on's id: completed, with how much later.
    parts->tick(200);
    parts->reportInstrument(parts->instrumentStatus(msg::Instrument::kGrinder, msg::InstrumentState::kDone, followOn));
    CHECK(parts->state(0) == ActivityState::kDone);
    LONGS_EQUAL(1, parts->count(ev::kExtendedCompleted));
}

TEST(PlanExtension, TheInstrumentRefusingTheFollowOnLeavesTheActivityAsItWas) {
    const std::uint16_t followOn = followOnSent(5000);
    msg::InstrumentStatusMsg m = parts->instrumentStatus(msg::Instrument::kGrinder, msg::InstrumentState::kBusy, sampleId);
    m.lastRefusal = msg::InstrumentRefusal::kBusy;
    m.lastRefusedCommandId = followOn;
    parts->reportInstrument(m);
    LONGS_EQUAL(static_cast<long>(PlanExtensionRefusal::kInstrument),
                static_cast<long>(parts->extension.counters().lastRefusal));
    CHECK_FALSE(parts->extension.pendingFor(0));
    CHECK(parts->state(0) == ActivityState::kRunning);
    LONGS_EQUAL(sampleId, parts->devices.commandId(0));
}

TEST(PlanExtension, TheActivityEndingBeforeTheAnswerDropsTheFollowOn) {
    followOnSent(5000);
    parts->tick(100);
    parts->reportInstrument(parts->instrumentStatus(msg::Instrument::kGrinder, msg::InstrumentState::kDone, sampleId));
    CHECK(parts->state(0) == ActivityState::kDone);
    CHECK_FALSE(parts->extension.pendingFor(0));
    LONGS_EQUAL(static_cast<long>(PlanExtensionRefusal::kNotRunning),
                static_cast<long>(parts->extension.counters().lastRefusal));
    LONGS_EQUAL(0, parts->count(ev::kExtendedCompleted));
}

TEST(PlanExtension, CancelledWhilePendingBothTheCommandAndItsFollowOnAreCancelled) {
    const std::uint16_t followOn = followOnSent(5000);
    const std::uint32_t before = parts->instrumentCommands;
    parts->lifecycle.cancelDispatch();
    parts->drain();
    LONGS_EQUAL(before + 2, parts->instrumentCommands);  // the command's cancel, then the follow-on's
    CHECK(parts->lastInstrument.action == msg::InstrumentAction::kCancel);
    LONGS_EQUAL(followOn, parts->lastInstrument.commandId);
    CHECK_FALSE(parts->extension.pendingFor(0));
    LONGS_EQUAL(1, parts->extension.counters().refused);  // dropped: not running
}

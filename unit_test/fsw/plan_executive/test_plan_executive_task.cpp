// The plan executive task on a software bus (plan_executive_task.hpp): the
// plan commands' PlanCommandMsg in (chunks, start with length and CRC-32,
// the short form, abort), the status and safe requests out. Uploads in chunks
// and started; a bad CRC, a bad length, a gap and an overflow refused with the
// plan running kept; a parse error refused with its reason, line and token; a
// plan with no valid selection refused; the short form; abort; wait
// activities completed at their lb to the plan's end; a science activity
// timed out and the plan regenerated; no heap across many runs; with the
// devices; PLAN_EXTEND taken (a follow-on, committed when the instrument names
// it) and refused for each reason; GOTO and goal lists as plans of drives.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/crc32.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "fsw/plan_executive/plan_executive_task.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using msg::PlanExecutiveState;
using msg::PlanRefusal;
using plan_executive::PlanExecutiveTask;
namespace ev = plan_executive::events;

namespace {

// Two waits in a row, then a communicate window: runs to the end by itself.
constexpr const char* kWaitsText =
    "plan waits\n"
    "event a\n"
    "event b\n"
    "event c\n"
    "activity w1 wait start a [1, 5] cost 1\n"
    "activity w2 wait a b [2, 5] cost 1\n"
    "activity talk communicate b c [1, 2] cost 1\n"
    "end\n";

constexpr const char* kShortText = "plan quick;event e;activity w wait start e [1, 2] cost 1;end";

// A plan that parses but cannot be scheduled: 10 s of waiting within 5 s.
constexpr const char* kInconsistentText =
    "plan tight\n"
    "event a\n"
    "activity w wait start a [10, 20] cost 1\n"
    "constraint start a [0, 5]\n"
    "end\n";

struct Rig {
    static constexpr core::TimeNs kRun = 100 * core::kNsPerMs;
    core::VirtualClock clock;
    core::EventLog events;
    core::SoftwareBus bus;
    PlanExecutiveTask task;
    core::PipeId probe = 0;
    core::Message inbox{};
    msg::PlanExecutiveStatusMsg status{};
    std::uint32_t statuses = 0;
    std::uint32_t safeRequests = 0;
    msg::CallHomeReason safeReason = msg::CallHomeReason::kNone;
    std::uint32_t seen[100] = {};  // events 950.. seen
    // What the executive asked of the devices and the deliberative layer.
    msg::InstrumentCommandMsg lastInstrument{};
    std::uint32_t instrumentCommands = 0;
    msg::PlanGoalMsg lastGoal{};
    std::uint32_t goals = 0;
    std::uint64_t frames = 0;
    msg::PlanCommandMsg command{};

    Rig() : events(clock), bus(clock, events), task(bus, events) {}

    bool init() {
        return core::isOk(bus.createPipe("probe", 32, &probe)) &&
               core::isOk(bus.subscribe(probe, msg::ids::kPlanExecutiveStatus)) &&
               core::isOk(bus.subscribe(probe, msg::ids::kSafeRequest)) &&
               core::isOk(bus.subscribe(probe, msg::ids::kInstrumentCommand)) &&
               core::isOk(bus.subscribe(probe, msg::ids::kPlanGoal)) && core::isOk(task.init());
    }
    // ---- what the devices, mode estimation and the deliberative layer say ----
    void instrument(msg::Instrument which, msg::InstrumentState state, std::uint16_t commandId,
                    std::uint8_t faultCode = 0, msg::InstrumentRefusal refusal = msg::InstrumentRefusal::kNone) {
        msg::InstrumentStatusMsg m{};
        m.timeNs = clock.now();
        m.instrument = which;
        m.state = state;
        m.commandId = commandId;
        m.faultCode = faultCode;
        m.lastRefusal = refusal;
        m.lastRefusedCommandId = refusal == msg::InstrumentRefusal::kNone ? 0 : commandId;
        CHECK_TRUE(core::isOk(bus.publish(m)));
    }
    // A status with the command's progress, reported now; a refusal of another id if given.
    void instrumentProgress(msg::Instrument which, msg::InstrumentState state, std::uint16_t commandId,
                            std::uint8_t progress, std::uint16_t refusedId = 0,
                            msg::InstrumentRefusal refusal = msg::InstrumentRefusal::kNone) {
        msg::InstrumentStatusMsg m{};
        m.timeNs = clock.now();
        m.lastReportNs = clock.now();
        m.instrument = which;
        m.state = state;
        m.commandId = commandId;
        m.progressPct = progress;
        m.lastRefusal = refusal;
        m.lastRefusedCommandId = refusedId;
        CHECK_TRUE(core::isOk(bus.publish(m)));
    }
    // PLAN_EXTEND as the plan commands pass it.
    void extend(const char* activity, std::uint32_t extraMs) {
        command = msg::PlanCommandMsg{};
        command.timeNs = clock.now();
        command.kind = msg::PlanCommandKind::kExtend;
        command.extendMs = extraMs;
        command.length = static_cast<std::uint16_t>(std::strlen(activity));
        std::memcpy(command.data, activity, command.length);
        CHECK_TRUE(core::isOk(bus.publish(command)));
    }
    void deliberative(msg::DeliberativeState state, std::uint32_t revision) {
        msg::PlanStatusMsg m{};
        m.timeNs = clock.now();
        m.state = state;
        m.goalRevision = revision;
        CHECK_TRUE(core::isOk(bus.publish(m)));
    }
    void driveModes(std::size_t wheel, msg::DriveMode declared) {
        msg::DriveModesMsg m{};
        m.timeNs = clock.now();
        m.drives[wheel].declared = declared;
        CHECK_TRUE(core::isOk(bus.publish(m)));
    }
    void riskBound(double risk) {
        msg::GoalListMsg g{};
        g.timeNs = clock.now();
        g.riskBound = risk;
        g.revision = 1;
        CHECK_TRUE(core::isOk(bus.publish(g)));
    }
    // The goal commands' goal list (GOTO, ADD_TARGET, CLEAR_GOALS, SET_RISK_BOUND).
    void goalList(std::uint32_t revision, const double (*xy)[2], std::size_t count, double risk = 1e-3) {
        double xyr[msg::kMaxGoals][3] = {};
        for (std::size_t i = 0; i < count && i < msg::kMaxGoals; ++i) {
            xyr[i][0] = xy[i][0];
            xyr[i][1] = xy[i][1];
        }
        goalListWithRadii(revision, xyr, count, risk);
    }
    // The same with each goal's region radius (the goal commands' goals are points: 0).
    void goalListWithRadii(std::uint32_t revision, const double (*xyr)[3], std::size_t count, double risk = 1e-3) {
        msg::GoalListMsg g{};
        g.timeNs = clock.now();
        g.riskBound = risk;
        g.revision = revision;
        g.count = static_cast<std::uint8_t>(count);
        for (std::size_t i = 0; i < count; ++i) {
            g.goals[i].xM = xyr[i][0];
            g.goals[i].yM = xyr[i][1];
            g.goals[i].radiusM = static_cast<float>(xyr[i][2]);
        }
        CHECK_TRUE(core::isOk(bus.publish(g)));
    }
    void send(msg::PlanCommandKind kind, const char* data = nullptr, std::size_t length = 0, std::uint32_t offset = 0) {
        command = msg::PlanCommandMsg{};
        command.timeNs = clock.now();
        command.kind = kind;
        command.offset = offset;
        command.length = static_cast<std::uint16_t>(length);
        if (data != nullptr) {
            std::memcpy(command.data, data, length);
        }
        CHECK_TRUE(core::isOk(bus.publish(command)));
    }
    void start(std::uint32_t length, std::uint32_t crc) {
        command = msg::PlanCommandMsg{};
        command.timeNs = clock.now();
        command.kind = msg::PlanCommandKind::kStart;
        command.textLength = length;
        command.crc32 = crc;
        CHECK_TRUE(core::isOk(bus.publish(command)));
    }
    // Uploads text in chunks of `chunk` bytes (a run after each, as the ground link would).
    void upload(const char* text, std::size_t chunk = 200) {
        const std::size_t n = std::strlen(text);
        for (std::size_t at = 0; at < n; at += chunk) {
            send(msg::PlanCommandKind::kChunk, text + at, n - at < chunk ? n - at : chunk,
                 static_cast<std::uint32_t>(at));
            run();
        }
    }
    void uploadAndStart(const char* text, std::size_t chunk = 200) {
        upload(text, chunk);
        const std::size_t n = std::strlen(text);
        start(static_cast<std::uint32_t>(n), core::crc32(text, n));
        run();
    }
    void run() {
        clock.advance(kRun);
        core::FrameContext frame{};
        frame.frame = ++frames;
        frame.scheduledStart = clock.now();
        frame.actualStart = clock.now();
        task.run(frame);
        drain();
    }
    void runFor(int runs) {
        for (int i = 0; i < runs; ++i) {
            run();
        }
    }
    bool runUntil(PlanExecutiveState s, int runs) {
        for (int i = 0; i < runs && task.state() != s; ++i) {
            run();
        }
        return task.state() == s;
    }
    void drain() {
        while (core::isOk(bus.receive(probe, &inbox))) {
            if (inbox.header.id == msg::ids::kPlanExecutiveStatus) {
                CHECK_TRUE(core::isOk(inbox.decode(&status)));
                ++statuses;
            } else if (inbox.header.id == msg::ids::kInstrumentCommand) {
                CHECK_TRUE(core::isOk(inbox.decode(&lastInstrument)));
                ++instrumentCommands;
            } else if (inbox.header.id == msg::ids::kPlanGoal) {
                CHECK_TRUE(core::isOk(inbox.decode(&lastGoal)));
                ++goals;
            } else if (inbox.header.id == msg::ids::kSafeRequest) {
                msg::SafeRequestMsg s{};
                CHECK_TRUE(core::isOk(inbox.decode(&s)));
                ++safeRequests;
                safeReason = s.reason;
            }
        }
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            if (e.id >= 950 && e.id < 1050) {
                ++seen[e.id - 950];
            }
        }
    }
    std::uint32_t count(core::EventId id) const { return seen[id - 950]; }
};

Rig* rig = nullptr;

}  // namespace

TEST_GROUP(PlanExecutiveTask) {
    void setup() override {
        rig = new Rig();
        CHECK_TRUE(rig->init());
    }
    void teardown() override {
        delete rig;
        rig = nullptr;
    }
    // The waits plan accepted and running.
    void startWaits() {
        rig->uploadAndStart(kWaitsText, 40);
        CHECK_TRUE(rig->runUntil(PlanExecutiveState::kDispatching, 20));
        rig->runFor(2);
        LONGS_EQUAL(1, rig->count(ev::kPlanAccepted));
        STRCMP_EQUAL("waits", rig->status.planName);
    }
};

TEST(PlanExecutiveTask, UploadInChunksThenStartRunsThePlanToItsEnd) {
    startWaits();
    CHECK(rig->count(ev::kChunkAccepted) >= 3);
    LONGS_EQUAL(1, rig->count(ev::kSelectionDone));
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 200));
    LONGS_EQUAL(1, rig->count(ev::kPlanComplete));
    LONGS_EQUAL(3, rig->count(ev::kActivityStarted));
    LONGS_EQUAL(3, rig->count(ev::kActivityCompleted));
    rig->run();
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kComplete), static_cast<long>(rig->status.state));
    LONGS_EQUAL(1, rig->status.plansAccepted);
    LONGS_EQUAL(0, rig->status.plansRefused);
    LONGS_EQUAL(3, rig->status.activitiesStarted);
    LONGS_EQUAL(3, rig->status.activitiesCompleted);
    DOUBLES_EQUAL(3.0, rig->status.cost, 1e-9);
    LONGS_EQUAL(3, rig->status.activityCount);
    // Activities 0, 1 (byte 0) and 2 (byte 1) done (3).
    LONGS_EQUAL(0x33, rig->status.activityStates[0]);
    LONGS_EQUAL(0x03, rig->status.activityStates[1]);
}

TEST(PlanExecutiveTask, BadCrcIsRefusedAndThePlanRunningKept) {
    startWaits();
    rig->upload(kShortText);
    const std::size_t n = std::strlen(kShortText);
    rig->start(static_cast<std::uint32_t>(n), core::crc32(kShortText, n) ^ 1U);
    rig->runFor(2);
    LONGS_EQUAL(1, rig->count(ev::kUploadRefused));
    LONGS_EQUAL(static_cast<long>(PlanRefusal::kBadCrc), static_cast<long>(rig->status.lastRefusal));
    LONGS_EQUAL(1, rig->status.plansRefused);
    STRCMP_EQUAL("waits", rig->status.planName);
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kDispatching), static_cast<long>(rig->task.state()));
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 200));
}

TEST(PlanExecutiveTask, BadLengthIsRefusedAndThePlanRunningKept) {
    startWaits();
    rig->upload(kShortText);
    const std::size_t n = std::strlen(kShortText);
    rig->start(static_cast<std::uint32_t>(n + 1), core::crc32(kShortText, n));
    rig->runFor(2);
    LONGS_EQUAL(1, rig->count(ev::kUploadRefused));
    LONGS_EQUAL(static_cast<long>(PlanRefusal::kBadLength), static_cast<long>(rig->status.lastRefusal));
    STRCMP_EQUAL("waits", rig->status.planName);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 200));
}

TEST(PlanExecutiveTask, GapIsRefusedSpoilsTheUploadAndThePlanRunningIsKept) {
    startWaits();
    rig->send(msg::PlanCommandKind::kChunk, kShortText, 10, 0);
    rig->send(msg::PlanCommandKind::kChunk, kShortText + 20, 10, 20);  // 10..20 missing
    rig->send(msg::PlanCommandKind::kChunk, kShortText + 10, 10, 10);  // too late: spoiled
    rig->run();
    LONGS_EQUAL(2, rig->count(ev::kUploadRefused));
    LONGS_EQUAL(static_cast<long>(PlanRefusal::kGap), static_cast<long>(rig->status.lastRefusal));
    rig->start(30, core::crc32(kShortText, 30));
    rig->runFor(2);
    LONGS_EQUAL(3, rig->count(ev::kUploadRefused));
    LONGS_EQUAL(static_cast<long>(PlanRefusal::kGap), static_cast<long>(rig->status.lastRefusal));
    LONGS_EQUAL(3, rig->status.plansRefused);
    STRCMP_EQUAL("waits", rig->status.planName);
    // Offset 0 starts over: the same plan now goes in.
    rig->uploadAndStart(kShortText);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kDispatching, 20));
    rig->runFor(2);
    STRCMP_EQUAL("quick", rig->status.planName);
    LONGS_EQUAL(1, rig->count(ev::kPlanSuperseded));
}

TEST(PlanExecutiveTask, OverflowIsRefusedAndThePlanRunningKept) {
    startWaits();
    static char filler[200];
    std::memset(filler, '#', sizeof filler);
    rig->send(msg::PlanCommandKind::kChunk, filler, sizeof filler, 0);
    rig->run();
    // Chunks up to the end of the buffer are taken; one past it is not.
    std::uint32_t at = 200;
    for (; at + 200 <= plan_executive::kMaxPlanText; at += 200) {
        rig->send(msg::PlanCommandKind::kChunk, filler, sizeof filler, at);
        rig->run();
    }
    LONGS_EQUAL(0, rig->count(ev::kUploadRefused));
    rig->send(msg::PlanCommandKind::kChunk, filler, sizeof filler, at);
    rig->run();
    LONGS_EQUAL(1, rig->count(ev::kUploadRefused));
    LONGS_EQUAL(static_cast<long>(PlanRefusal::kOverflow), static_cast<long>(rig->status.lastRefusal));
    LONGS_EQUAL(at, static_cast<long>(rig->task.uploadLength()));
    STRCMP_EQUAL("waits", rig->status.planName);
    LONGS_EQUAL(1, rig->status.plansAccepted);
    LONGS_EQUAL(0, rig->count(ev::kPlanSuperseded));
}

TEST(PlanExecutiveTask, ParseErrorIsRefusedWithReasonLineAndToken) {
    startWaits();
    rig->uploadAndStart("plan bad\nevent a\nactivity x fly start a [1, 2] cost 1\nend\n");
    rig->run();
    LONGS_EQUAL(1, rig->count(ev::kParseRefused));
    LONGS_EQUAL(static_cast<long>(PlanRefusal::kParse), static_cast<long>(rig->status.lastRefusal));
    LONGS_EQUAL(static_cast<long>(plan_executive::PlanError::kUnknownActivityKind),
                static_cast<long>(rig->status.lastParseError));
    LONGS_EQUAL(3, rig->status.refusalLine);
    STRCMP_EQUAL("fly", rig->status.refusalToken);
    STRCMP_EQUAL("waits", rig->status.planName);
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kDispatching), static_cast<long>(rig->task.state()));
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 200));
}

// An empty text is refused; a plan of only its end marker is legal and
// empty (the parser's rule): accepted and complete at once, nothing started.
TEST(PlanExecutiveTask, EmptyPlanIsRefusedAndAnEndOnlyPlanCompletesAtOnce) {
    rig->send(msg::PlanCommandKind::kShort, "  ", 2);
    rig->run();
    LONGS_EQUAL(1, rig->count(ev::kParseRefused));
    LONGS_EQUAL(static_cast<long>(plan_executive::PlanError::kEmptyText),
                static_cast<long>(rig->status.lastParseError));
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kIdle), static_cast<long>(rig->task.state()));
    rig->send(msg::PlanCommandKind::kShort, "end", 3);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 10));
    LONGS_EQUAL(1, rig->count(ev::kPlanAccepted));
    LONGS_EQUAL(1, rig->count(ev::kPlanComplete));
    LONGS_EQUAL(0, rig->count(ev::kActivityStarted));
}

TEST(PlanExecutiveTask, InconsistentPlanIsRefusedAtUpload) {
    startWaits();
    rig->uploadAndStart(kInconsistentText);
    rig->runFor(5);
    LONGS_EQUAL(1, rig->count(ev::kSelectionRefused));
    LONGS_EQUAL(static_cast<long>(PlanRefusal::kNoSelection), static_cast<long>(rig->status.lastRefusal));
    STRCMP_EQUAL("waits", rig->status.planName);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 200));
    LONGS_EQUAL(0, rig->safeRequests);
}

TEST(PlanExecutiveTask, ShortFormIsParsedAndStartedAtOnce) {
    rig->send(msg::PlanCommandKind::kShort, kShortText, std::strlen(kShortText));
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 100));
    LONGS_EQUAL(1, rig->count(ev::kPlanAccepted));
    LONGS_EQUAL(1, rig->count(ev::kActivityCompleted));
    STRCMP_EQUAL("quick", rig->task.plan().name);
    // The upload buffer was not touched: nothing to start.
    rig->start(10, 0);
    rig->run();
    LONGS_EQUAL(static_cast<long>(PlanRefusal::kNoUpload), static_cast<long>(rig->status.lastRefusal));
}

TEST(PlanExecutiveTask, AbortStopsThePlan) {
    startWaits();
    rig->send(msg::PlanCommandKind::kAbort);
    rig->run();
    LONGS_EQUAL(1, rig->count(ev::kPlanAborted));
    CHECK(rig->count(ev::kActivityCancelled) >= 1);
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kIdle), static_cast<long>(rig->task.state()));
    rig->runFor(100);
    LONGS_EQUAL(0, rig->count(ev::kPlanComplete));
    LONGS_EQUAL(0, rig->status.running);
}

// Stage 1 commands no device: a sample runs to its ub and is timed out; the
// plan regenerates. The two-targets plan's drive1 has ub 900 s: far off; a
// plan of one sample with ub 2 s shows it.
TEST(PlanExecutiveTask, TimedOutActivityRegeneratesAndNoMethodCallsTheOperator) {
    const char* lone = "plan lone;event e;activity s sample start e [1, 2] cost 1 target 1;end";
    rig->send(msg::PlanCommandKind::kShort, lone, std::strlen(lone));
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kDispatching, 20));
    rig->runFor(40);
    LONGS_EQUAL(1, rig->count(ev::kActivityStarted));
    LONGS_EQUAL(1, rig->count(ev::kActivityLate));
    LONGS_EQUAL(1, rig->count(ev::kRegenerating));
    LONGS_EQUAL(1, rig->status.regenerations);
    LONGS_EQUAL(static_cast<long>(msg::PlanRegeneration::kLate), static_cast<long>(rig->status.lastRegeneration));
    // The start is fixed at 0 and the sample must end by 2 s: from where
    // execution stands no selection exists, so the operator is called.
    LONGS_EQUAL(1, rig->count(ev::kOperatorCalled));
    LONGS_EQUAL(0, rig->count(ev::kRegenerated));
    LONGS_EQUAL(1, rig->safeRequests);
    LONGS_EQUAL(static_cast<long>(msg::CallHomeReason::kPlanNoMethod), static_cast<long>(rig->safeReason));
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kFailed), static_cast<long>(rig->status.state));
    LONGS_EQUAL(1, rig->status.operatorCalls);
    LONGS_EQUAL(1, rig->status.activitiesLate);
    LONGS_EQUAL(7, rig->status.callHomeReason);
}

TEST(PlanExecutiveTask, MalformedCommandsAreDroppedAndCounted) {
    rig->send(msg::PlanCommandKind::kChunk, "x", 1);
    rig->command.length = 201;
    CHECK_TRUE(core::isOk(rig->bus.publish(rig->command)));
    rig->command.length = 1;
    rig->command.kind = static_cast<msg::PlanCommandKind>(9);
    CHECK_TRUE(core::isOk(rig->bus.publish(rig->command)));
    rig->run();
    LONGS_EQUAL(2, rig->task.malformed());
    LONGS_EQUAL(2, rig->count(ev::kMalformedInput));  // the 1st, 2nd, 4th ... evented
}

TEST(PlanExecutiveTask, TwoTargetsPlanIsAcceptedWithItsCheapestSelection) {
    rig->uploadAndStart(test::plan::kTwoTargetsText, 200);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kDispatching, 20));
    rig->runFor(2);
    LONGS_EQUAL(0, rig->status.options[0]);  // sample target 1
    LONGS_EQUAL(0, rig->status.options[1]);  // sample target 2
    DOUBLES_EQUAL(32.5, rig->status.cost, 1e-9);  // as rse-ground plan check says
    LONGS_EQUAL(1, rig->count(ev::kActivityStarted));  // drive1
}

TEST(PlanExecutiveTask, NoHeapAcrossManyRuns) {
    startWaits();
    test::AllocationWatch watch;
    for (int k = 0; k < 5; ++k) {
        rig->uploadAndStart(kWaitsText, 30);
        rig->runFor(120);
        rig->send(msg::PlanCommandKind::kShort, kShortText, std::strlen(kShortText));
        rig->extend("w", 1000);  // refused: a wait
        rig->runFor(60);
        rig->uploadAndStart(kInconsistentText);
        rig->runFor(10);
        rig->send(msg::PlanCommandKind::kAbort);
        rig->runFor(5);
    }
    LONGS_EQUAL(0, watch.count());
}

// ---- Stage 2: the devices and the deliberative layer ------------------------

namespace {
// The two-targets plan's activities (parse order).
constexpr std::uint16_t kDrive1 = 0, kSample1 = 1, kDrive2 = 3, kSample2 = 4, kImage2 = 5;
}  // namespace

TEST_GROUP(PlanExecutiveDevices) {
    void setup() override {
        rig = new Rig();
        CHECK_TRUE(rig->init());
        rig->riskBound(2e-3);
        rig->run();
        rig->uploadAndStart(test::plan::kTwoTargetsText, 200);
        CHECK_TRUE(rig->runUntil(PlanExecutiveState::kDispatching, 20));
        rig->runFor(2);
    }
    void teardown() override {
        delete rig;
        rig = nullptr;
    }
    plan_executive::ActivityState state(std::uint16_t a) { return rig->task.dispatcher().state(a); }
    // drive1 reached, as the deliberative layer says.
    void reachTarget1() {
        rig->deliberative(msg::DeliberativeState::kPlanning, rig->lastGoal.goals.revision);
        rig->runFor(600);  // drive1's lb is 60 s
        rig->deliberative(msg::DeliberativeState::kComplete, rig->lastGoal.goals.revision);
        rig->run();
        CHECK(state(kDrive1) == plan_executive::ActivityState::kDone);
    }
};

TEST(PlanExecutiveDevices, DriveIsAGoalForTheDeliberativeLayerAndCompletesWhenItIsReached) {
    LONGS_EQUAL(1, rig->goals);
    LONGS_EQUAL(1, rig->lastGoal.goals.count);
    DOUBLES_EQUAL(10.0, rig->lastGoal.goals.goals[0].xM, 1e-12);
    DOUBLES_EQUAL(0.0, rig->lastGoal.goals.goals[0].yM, 1e-12);
    DOUBLES_EQUAL(2e-3, rig->lastGoal.goals.riskBound, 1e-15);
    DOUBLES_EQUAL(0.0, rig->lastGoal.goals.goals[0].radiusM, 0.0);  // no `within`: the point
    CHECK(rig->lastGoal.goals.revision >= PlanExecutiveTask::kGoalRevisionBase);
    // A status about another goal list before this one is adopted is not news.
    rig->deliberative(msg::DeliberativeState::kComplete, 1);
    rig->run();
    CHECK(state(kDrive1) == plan_executive::ActivityState::kRunning);
    reachTarget1();
    // sample1 starts: the grinder, target 1, ub 300 s, a fresh command id.
    LONGS_EQUAL(1, rig->instrumentCommands);
    CHECK(rig->lastInstrument.instrument == msg::Instrument::kGrinder);
    CHECK(rig->lastInstrument.action == msg::InstrumentAction::kSample);
    LONGS_EQUAL(1, rig->lastInstrument.targetId);
    DOUBLES_EQUAL(300.0, rig->lastInstrument.maxDurationS, 1e-9);
    CHECK(rig->lastInstrument.commandId != 0);
}

TEST(PlanExecutiveDevices, GrinderFailingDeprecatesSample2AndRegeneratesWithImage2) {
    reachTarget1();
    const std::uint16_t sampleId = rig->lastInstrument.commandId;
    rig->instrument(msg::Instrument::kGrinder, msg::InstrumentState::kBusy, sampleId);
    rig->runFor(1300);
    rig->instrument(msg::Instrument::kGrinder, msg::InstrumentState::kDone, sampleId);
    rig->run();
    CHECK(state(kSample1) == plan_executive::ActivityState::kDone);
    CHECK(state(kDrive2) == plan_executive::ActivityState::kRunning);
    LONGS_EQUAL(2, rig->goals);
    DOUBLES_EQUAL(20.0, rig->lastGoal.goals.goals[0].xM, 1e-12);
    const std::uint32_t drive2Revision = rig->lastGoal.goals.revision;
    rig->deliberative(msg::DeliberativeState::kExecuting, drive2Revision);
    rig->runFor(10);
    // The grinder faults while the rover drives to target 2.
    rig->instrument(msg::Instrument::kGrinder, msg::InstrumentState::kFailed, sampleId, 3);
    rig->runFor(5);
    LONGS_EQUAL(1, rig->count(ev::kComponentFailed));
    LONGS_EQUAL(1, rig->count(ev::kRegenerating));
    LONGS_EQUAL(1, rig->count(ev::kRegenerated));
    LONGS_EQUAL(static_cast<long>(msg::PlanRegeneration::kComponentFailed),
                static_cast<long>(rig->status.lastRegeneration));
    DOUBLES_EQUAL(32.5, rig->status.costBefore, 1e-9);
    DOUBLES_EQUAL(37.5, rig->status.cost, 1e-9);
    LONGS_EQUAL(1, rig->status.options[1]);  // science2: image
    LONGS_EQUAL(1, rig->status.deprecatedCount);
    // drive2 carried over, not restarted: no new goal.
    CHECK(state(kDrive2) == plan_executive::ActivityState::kRunning);
    LONGS_EQUAL(2, rig->goals);
    rig->runFor(600);
    rig->deliberative(msg::DeliberativeState::kComplete, drive2Revision);
    rig->run();
    CHECK(state(kImage2) == plan_executive::ActivityState::kRunning);
    CHECK(state(kSample2) == plan_executive::ActivityState::kInactive);
    CHECK(rig->lastInstrument.instrument == msg::Instrument::kCamera);
    CHECK(rig->lastInstrument.action == msg::InstrumentAction::kImage);
    LONGS_EQUAL(2, rig->lastInstrument.targetId);
    rig->runFor(350);
    rig->instrument(msg::Instrument::kCamera, msg::InstrumentState::kDone, rig->lastInstrument.commandId);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 20));
    rig->run();
    LONGS_EQUAL(4, rig->status.activitiesCompleted);
    LONGS_EQUAL(0, rig->status.operatorCalls);
    LONGS_EQUAL(0, rig->safeRequests);
}

TEST(PlanExecutiveDevices, RefusedOrOfflineInstrumentFailsTheActivity) {
    reachTarget1();
    const std::uint16_t sampleId = rig->lastInstrument.commandId;
    rig->instrument(msg::Instrument::kGrinder, msg::InstrumentState::kIdle, 0, 0, msg::InstrumentRefusal::kOutOfReach);
    rig->command.timeNs = 0;  // (the refusal names command 0: not ours)
    rig->run();
    CHECK(state(kSample1) == plan_executive::ActivityState::kRunning);
    rig->instrument(msg::Instrument::kGrinder, msg::InstrumentState::kIdle, sampleId, 0,
                    msg::InstrumentRefusal::kOutOfReach);
    rig->runFor(3);
    LONGS_EQUAL(1, rig->count(ev::kActivityFailed));
    LONGS_EQUAL(1, rig->status.activitiesFailed);
    LONGS_EQUAL(1, rig->count(ev::kRegenerating));
    // Re-selected from where it stands: science1 not under way any more (a
    // failed activity is not "started"), so image1 may take its place.
    CHECK(rig->count(ev::kRegenerated) + rig->count(ev::kOperatorCalled) == 1);
}

TEST(PlanExecutiveDevices, CallHomeFailsTheDriveAndAFailedDriveModeCallsTheOperator) {
    rig->driveModes(1, msg::DriveMode::kFailed);  // drive_ML: drive1 asks drive_ML != failed
    rig->runFor(5);
    LONGS_EQUAL(1, rig->count(ev::kComponentFailed));
    LONGS_EQUAL(1, rig->count(ev::kActivityFailed));
    LONGS_EQUAL(1, rig->count(ev::kOperatorCalled));
    LONGS_EQUAL(1, rig->safeRequests);
    CHECK(rig->safeReason == msg::CallHomeReason::kPlanNoMethod);
    LONGS_EQUAL(0, rig->lastGoal.goals.count);  // the drive's goal cleared
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kFailed), static_cast<long>(rig->status.state));
}

// The deliberative layer's call home fails the drive; the plan, regenerated
// from where it stands, runs drive1 again (its window is still open): a new goal.
TEST(PlanExecutiveDevices, DeliberativeCallHomeFailsTheDriveAndTheRegeneratedPlanRunsItAgain) {
    const std::uint32_t first = rig->lastGoal.goals.revision;
    rig->deliberative(msg::DeliberativeState::kCalledHome, first);
    rig->runFor(3);
    LONGS_EQUAL(1, rig->count(ev::kActivityFailed));
    LONGS_EQUAL(1, rig->count(ev::kRegenerated));
    LONGS_EQUAL(static_cast<long>(msg::PlanRegeneration::kActivityFailed),
                static_cast<long>(rig->status.lastRegeneration));
    LONGS_EQUAL(2, rig->goals);
    CHECK(rig->lastGoal.goals.revision > first);
    CHECK(state(kDrive1) == plan_executive::ActivityState::kRunning);
    // Another goal list (a GOTO) replacing the drive's, once adopted, fails it too.
    rig->deliberative(msg::DeliberativeState::kExecuting, rig->lastGoal.goals.revision);
    rig->run();
    rig->deliberative(msg::DeliberativeState::kWaiting, 7);
    rig->runFor(3);
    LONGS_EQUAL(2, rig->count(ev::kActivityFailed));
}

TEST(PlanExecutiveDevices, AbortCancelsTheInstrumentCommandAndClearsTheGoal) {
    reachTarget1();
    const std::uint16_t sampleId = rig->lastInstrument.commandId;
    rig->send(msg::PlanCommandKind::kAbort);
    rig->run();
    CHECK(rig->lastInstrument.action == msg::InstrumentAction::kCancel);
    LONGS_EQUAL(sampleId, rig->lastInstrument.commandId);
    LONGS_EQUAL(1, rig->count(ev::kActivityCancelled));
}

// `at X Y within R`: the drive's goal for the deliberative layer carries the
// region (the deliberative layer claims it, the habitual layer stops, within R),
// and the drive completes on the deliberative layer's complete as any drive.
TEST(PlanExecutiveTask, ADriveWithinARegionGivesTheDeliberativeLayerItsRadius) {
    rig->uploadAndStart("plan region\n"
                        "event at1\n"
                        "event at2\n"
                        "activity d1 drive start at1 [0, 900] at 10 0 within 3\n"
                        "activity d2 drive at1 at2 [0, 900] at 20 5 within 0.25\n"
                        "end\n");
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kDispatching, 20));
    rig->runFor(2);
    LONGS_EQUAL(1, rig->goals);
    DOUBLES_EQUAL(10.0, rig->lastGoal.goals.goals[0].xM, 0.0);
    DOUBLES_EQUAL(3.0, rig->lastGoal.goals.goals[0].radiusM, 1e-6);
    CHECK_TRUE(msg::goalListUsable(rig->lastGoal.goals));
    const std::uint32_t first = rig->lastGoal.goals.revision;
    rig->deliberative(msg::DeliberativeState::kExecuting, first);
    rig->run();
    rig->deliberative(msg::DeliberativeState::kComplete, first);
    rig->runFor(2);
    CHECK(rig->task.dispatcher().state(0) == plan_executive::ActivityState::kDone);
    // The next drive's goal with its own radius (below the goal tolerance: the
    // deliberative layer reaches it as the point, but it is carried as given).
    LONGS_EQUAL(2, rig->goals);
    DOUBLES_EQUAL(20.0, rig->lastGoal.goals.goals[0].xM, 0.0);
    DOUBLES_EQUAL(0.25, rig->lastGoal.goals.goals[0].radiusM, 1e-6);
}

TEST(PlanExecutiveDevices, AbortWhileDrivingClearsTheGoal) {
    rig->send(msg::PlanCommandKind::kAbort);
    rig->run();
    LONGS_EQUAL(2, rig->goals);
    LONGS_EQUAL(0, rig->lastGoal.goals.count);
}

// GOTO and the goal list (docs/plan_executive.md "Goal lists"): plans of drive
// activities run by the executive, the deliberative layer given one goal at a time.
TEST_GROUP_BASE(PlanExecutiveGoalLists, TEST_GROUP_CppUTestGroupPlanExecutiveTask) {
    // The deliberative layer reaches the goal it was last given.
    void reachGoal() {
        const std::uint32_t revision = rig->lastGoal.goals.revision;
        rig->deliberative(msg::DeliberativeState::kExecuting, revision);
        rig->run();
        rig->deliberative(msg::DeliberativeState::kComplete, revision);
        rig->runFor(2);
    }
};

TEST(PlanExecutiveGoalLists, GotoIsAPlanOfOneDriveCompletedWhenTheGoalIsReached) {
    const double xy[1][2] = {{12.5, -3.25}};
    rig->goalList(5, xy, 1, 2e-3);
    rig->runFor(2);
    LONGS_EQUAL(1, rig->count(ev::kGoalPlan));
    LONGS_EQUAL(1, rig->count(ev::kPlanAccepted));
    STRCMP_EQUAL("goal_list", rig->status.planName);
    LONGS_EQUAL(1, rig->status.activityCount);
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kDispatching), static_cast<long>(rig->task.state()));
    LONGS_EQUAL(1, rig->goals);
    LONGS_EQUAL(1, rig->lastGoal.goals.count);
    DOUBLES_EQUAL(12.5, rig->lastGoal.goals.goals[0].xM, 1e-9);
    DOUBLES_EQUAL(-3.25, rig->lastGoal.goals.goals[0].yM, 1e-9);
    DOUBLES_EQUAL(2e-3, rig->lastGoal.goals.riskBound, 1e-15);
    LONGS_EQUAL(0, rig->lastGoal.listIndex);
    CHECK(rig->lastGoal.goals.revision >= PlanExecutiveTask::kGoalRevisionBase);
    reachGoal();
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kComplete), static_cast<long>(rig->task.state()));
    LONGS_EQUAL(1, rig->count(ev::kPlanComplete));
    LONGS_EQUAL(1, rig->status.activitiesCompleted);
    LONGS_EQUAL(1, rig->goals);  // nothing more sent: no cancel of a drive that completed
    // The same revision again (the goal commands republish): nothing new.
    rig->goalList(5, xy, 1, 2e-3);
    rig->runFor(2);
    LONGS_EQUAL(1, rig->count(ev::kGoalPlan));
}

TEST(PlanExecutiveGoalLists, AGoalListIsDrivenGoalByGoalInItsOrder) {
    const double xy[3][2] = {{1.0, 0.0}, {2.0, 0.5}, {3.0, 1.5}};
    rig->goalList(7, xy, 3);
    rig->runFor(2);
    LONGS_EQUAL(3, rig->status.activityCount);
    for (std::size_t i = 0; i < 3; ++i) {
        LONGS_EQUAL(i + 1, rig->goals);
        LONGS_EQUAL(1, rig->lastGoal.goals.count);  // one goal at a time
        DOUBLES_EQUAL(xy[i][0], rig->lastGoal.goals.goals[0].xM, 1e-9);
        DOUBLES_EQUAL(xy[i][1], rig->lastGoal.goals.goals[0].yM, 1e-9);
        LONGS_EQUAL(i, rig->lastGoal.listIndex);  // as the operator numbers it
        reachGoal();
    }
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kComplete), static_cast<long>(rig->task.state()));
    LONGS_EQUAL(3, rig->status.activitiesCompleted);
    LONGS_EQUAL(3, rig->goals);
}

TEST(PlanExecutiveGoalLists, ANewGoalListReplacesTheGoalPlanAndAMissionPlan) {
    const double first[2][2] = {{1.0, 0.0}, {2.0, 0.0}};
    rig->goalList(2, first, 2);
    rig->runFor(2);
    const std::uint32_t firstRevision = rig->lastGoal.goals.revision;
    const double second[1][2] = {{-4.0, 4.0}};
    rig->goalList(3, second, 1);
    rig->runFor(2);
    LONGS_EQUAL(2, rig->count(ev::kGoalPlan));
    LONGS_EQUAL(1, rig->count(ev::kPlanSuperseded));
    CHECK(rig->lastGoal.goals.revision > firstRevision);
    DOUBLES_EQUAL(-4.0, rig->lastGoal.goals.goals[0].xM, 1e-9);
    LONGS_EQUAL(1, rig->status.activityCount);
    // A mission plan replaces the goal plan; a GOTO then replaces the mission plan.
    rig->uploadAndStart(kWaitsText, 40);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kDispatching, 20));
    rig->runFor(2);
    STRCMP_EQUAL("waits", rig->status.planName);
    LONGS_EQUAL(0, rig->lastGoal.goals.count);  // the goal plan's drive cancelled
    rig->goalList(4, second, 1);
    rig->runFor(2);
    STRCMP_EQUAL("goal_list", rig->status.planName);
    LONGS_EQUAL(3, rig->count(ev::kPlanSuperseded));
    LONGS_EQUAL(1, rig->lastGoal.goals.count);
}

TEST(PlanExecutiveGoalLists, AnEmptyGoalListStopsAGoalPlanButNotAMissionPlan) {
    const double xy[1][2] = {{5.0, 0.0}};
    rig->goalList(2, xy, 1);
    rig->runFor(2);
    rig->goalList(3, nullptr, 0);  // CLEAR_GOALS
    rig->runFor(2);
    LONGS_EQUAL(1, rig->count(ev::kGoalListEmpty));
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kIdle), static_cast<long>(rig->task.state()));
    LONGS_EQUAL(2, rig->goals);
    LONGS_EQUAL(0, rig->lastGoal.goals.count);  // the drive cancelled: the deliberative layer idles
    // A mission plan runs on through an empty list (SET_RISK_BOUND with no
    // goals); the new risk bound is what its next drive gets.
    rig->uploadAndStart(kWaitsText, 40);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kDispatching, 20));
    rig->goalList(4, nullptr, 0, 4e-3);
    rig->runFor(2);
    LONGS_EQUAL(2, rig->count(ev::kGoalListEmpty));
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kDispatching), static_cast<long>(rig->task.state()));
    STRCMP_EQUAL("waits", rig->status.planName);
    CHECK_TRUE(rig->runUntil(PlanExecutiveState::kComplete, 200));
}

TEST(PlanExecutiveGoalLists, ACallHomeStopsTheGoalPlanWithoutASecondCall) {
    const double xy[2][2] = {{5.0, 0.0}, {9.0, 0.0}};
    rig->goalList(2, xy, 2);
    rig->runFor(2);
    const std::uint32_t revision = rig->lastGoal.goals.revision;
    rig->deliberative(msg::DeliberativeState::kPlanning, revision);
    rig->run();
    rig->deliberative(msg::DeliberativeState::kCalledHome, revision);  // its own SafeRequestMsg sent
    rig->runFor(3);
    LONGS_EQUAL(1, rig->count(ev::kActivityFailed));
    LONGS_EQUAL(1, rig->count(ev::kGoalPlanStopped));
    LONGS_EQUAL(0, rig->count(ev::kRegenerating));
    LONGS_EQUAL(0, rig->count(ev::kOperatorCalled));
    LONGS_EQUAL(0, rig->safeRequests);
    LONGS_EQUAL(0, rig->status.operatorCalls);
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kFailed), static_cast<long>(rig->task.state()));
    LONGS_EQUAL(1, rig->goals);  // the second goal never given
    // A new GOTO after the operator looked: a new plan.
    rig->goalList(3, xy, 1);
    rig->runFor(2);
    LONGS_EQUAL(static_cast<long>(PlanExecutiveState::kDispatching), static_cast<long>(rig->task.state()));
    LONGS_EQUAL(2, rig->goals);
}

TEST(PlanExecutiveGoalLists, ARiskBoundChangeReplansTheGoalsAtTheNewBound) {
    const double xy[2][2] = {{5.0, 0.0}, {9.0, 0.0}};
    rig->goalList(2, xy, 2, 1e-3);
    rig->runFor(2);
    reachGoal();
    LONGS_EQUAL(1, rig->lastGoal.listIndex);
    rig->goalList(3, xy, 2, 1e-2);  // SET_RISK_BOUND: a new revision, the same goals
    rig->runFor(2);
    LONGS_EQUAL(2, rig->count(ev::kGoalPlan));
    DOUBLES_EQUAL(1e-2, rig->lastGoal.goals.riskBound, 1e-15);
    LONGS_EQUAL(0, rig->lastGoal.listIndex);  // from the list's start, as the deliberative layer always did
}

TEST(PlanExecutiveGoalLists, AGoalListWhileASelectionRunsIsTakenWhenItEnds) {
    const std::size_t n = std::strlen(kWaitsText);
    rig->upload(kWaitsText, 40);
    rig->start(static_cast<std::uint32_t>(n), core::crc32(kWaitsText, n));
    const double xy[1][2] = {{5.0, 0.0}};
    rig->goalList(2, xy, 1);  // the same run as PLAN_START: the selection first
    rig->runFor(4);
    LONGS_EQUAL(2, rig->count(ev::kPlanAccepted));
    LONGS_EQUAL(1, rig->count(ev::kGoalPlan));
    STRCMP_EQUAL("goal_list", rig->status.planName);  // the later one wins
    LONGS_EQUAL(0, rig->count(ev::kUploadRefused));
}

// A goal list's regions go into the plan made from it (`within R`) and out
// with each goal; a goal of radius 0 (GOTO, ADD_TARGET) stays the point.
TEST(PlanExecutiveGoalLists, AGoalsRegionIsKeptInItsPlanAndGivenWithTheGoal) {
    const double xyr[2][3] = {{6.0, 1.0, 2.5}, {9.0, -1.0, 0.0}};
    rig->goalListWithRadii(4, xyr, 2);
    rig->runFor(2);
    LONGS_EQUAL(1, rig->count(ev::kPlanAccepted));
    LONGS_EQUAL(2500, rig->task.plan().activities[0].radiusMm);
    LONGS_EQUAL(0, rig->task.plan().activities[1].radiusMm);
    DOUBLES_EQUAL(2.5, rig->lastGoal.goals.goals[0].radiusM, 1e-6);
    reachGoal();
    LONGS_EQUAL(2, rig->goals);
    DOUBLES_EQUAL(9.0, rig->lastGoal.goals.goals[0].xM, 1e-9);
    DOUBLES_EQUAL(0.0, rig->lastGoal.goals.goals[0].radiusM, 0.0);
}

TEST(PlanExecutiveGoalLists, AMalformedGoalListIsDroppedAndCounted) {
    const double xy[1][2] = {{NAN, 0.0}};
    rig->goalList(2, xy, 1);
    rig->goalList(3, nullptr, 0, 0.7);  // risk bound out of (0, 0.5)
    // A region radius that is no number, negative, or beyond kMaxGoalRadiusM.
    const double badRadii[3][3] = {{1.0, 0.0, NAN}, {1.0, 0.0, -0.5}, {1.0, 0.0, 50.5}};
    for (std::size_t i = 0; i < 3; ++i) {
        rig->goalListWithRadii(static_cast<std::uint32_t>(4 + i), &badRadii[i], 1);
    }
    rig->runFor(2);
    LONGS_EQUAL(5, rig->task.malformed());
    LONGS_EQUAL(0, rig->count(ev::kGoalPlan));
    LONGS_EQUAL(0, rig->count(ev::kGoalListEmpty));
}

// ---- Opportunistic science: PLAN_EXTEND -------------------------------------

namespace {
using msg::PlanExtensionRefusal;
constexpr std::uint16_t kImage1 = 2;
constexpr std::uint16_t kDone1 = 2;  // event
}  // namespace

// The devices' group: the two-targets plan running, drive1 under way.
TEST_GROUP_BASE(PlanExecutiveExtension, TEST_GROUP_CppUTestGroupPlanExecutiveDevices) {
    std::uint16_t sampleId = 0;
    std::int32_t t0 = 0;  // plan time sample1 started, ms

    // drive1 reached: sample1 starts on the grinder.
    void startSample1() {
        reachTarget1();
        CHECK(state(kSample1) == plan_executive::ActivityState::kRunning);
        sampleId = rig->lastInstrument.commandId;
        t0 = rig->task.dispatcher().startMs(kSample1);
    }
    // The grinder says it is `progress` % through sample1 after `elapsedS` (taken by the next run).
    void grinderAt(int elapsedS, std::uint8_t progress) {
        rig->runFor(elapsedS * 10 - static_cast<int>((rig->clock.now() / core::kNsPerMs - t0) / 100));
        rig->instrumentProgress(msg::Instrument::kGrinder, msg::InstrumentState::kBusy, sampleId, progress);
        rig->run();
    }
    // A PLAN_EXTEND refused with `why`: evented, counted, nothing sent, the network as it was.
    void refused(const char* name, std::uint32_t extraMs, PlanExtensionRefusal why) {
        const std::uint32_t events = rig->count(ev::kExtensionRefused);
        const std::uint32_t commands = rig->instrumentCommands;
        const std::uint32_t refusedBefore = rig->status.extensionsRefused;
        const plan_executive::Window w = rig->task.dispatcher().network().window(kDone1);
        rig->extend(name, extraMs);
        rig->run();
        LONGS_EQUAL(events + 1, rig->count(ev::kExtensionRefused));
        LONGS_EQUAL(refusedBefore + 1, rig->status.extensionsRefused);
        LONGS_EQUAL(static_cast<long>(why), static_cast<long>(rig->status.lastExtensionRefusal));
        LONGS_EQUAL(commands, rig->instrumentCommands);
        LONGS_EQUAL(w.earliestMs, rig->task.dispatcher().network().window(kDone1).earliestMs);
        LONGS_EQUAL(w.latestMs, rig->task.dispatcher().network().window(kDone1).latestMs);
        LONGS_EQUAL(0, rig->count(ev::kExtensionAccepted));
    }
};

// Expected from the grinder's progress (80 % after 120 s: 150 s in all), 60 s
// more ends at 210 s, within the ub (300 s) and done1's latest: a follow-on
// goes to the grinder; once it reports working on it the extension is
// committed (done1 no earlier than the request + 60 s) and the sample
// completes when the grinder says the follow-on is done.
TEST(PlanExecutiveExtension, AFollowOnWithinTheBoundsIsSentCommittedWhenTakenAndCompletesTheActivity) {
    startSample1();
    grinderAt(120, 80);
    const std::uint32_t commands = rig->instrumentCommands;
    rig->extend("sample1", 60000);
    rig->run();
    const std::int32_t requestMs = rig->status.planTimeMs;
    LONGS_EQUAL(1, rig->count(ev::kExtensionRequested));
    LONGS_EQUAL(commands + 1, rig->instrumentCommands);
    CHECK(rig->lastInstrument.instrument == msg::Instrument::kGrinder);
    CHECK(rig->lastInstrument.action == msg::InstrumentAction::kExtend);
    LONGS_EQUAL(sampleId, rig->lastInstrument.extendsCommandId);
    CHECK(rig->lastInstrument.commandId != sampleId && rig->lastInstrument.commandId != 0);
    LONGS_EQUAL(1, rig->lastInstrument.targetId);
    DOUBLES_EQUAL(60.0, rig->lastInstrument.maxDurationS, 1e-9);
    const std::uint16_t followOn = rig->lastInstrument.commandId;
    // Not committed until the grinder takes it; meanwhile another is busy.
    LONGS_EQUAL(t0 + 120 * 1000, rig->task.dispatcher().network().window(kDone1).earliestMs);
    LONGS_EQUAL(0, rig->status.extensionsAccepted);
    rig->extend("sample1", 10000);
    rig->run();
    LONGS_EQUAL(static_cast<long>(PlanExtensionRefusal::kBusy), static_cast<long>(rig->status.lastExtensionRefusal));
    // Taken: the grinder works on the follow-on.
    rig->instrumentProgress(msg::Instrument::kGrinder, msg::InstrumentState::kBusy, followOn, 57);
    rig->run();
    LONGS_EQUAL(1, rig->count(ev::kExtensionAccepted));
    LONGS_EQUAL(1, rig->status.extensionsAccepted);
    LONGS_EQUAL(1, rig->status.extensionsRefused);  // the busy one
    LONGS_EQUAL(requestMs + 60000, rig->task.dispatcher().network().window(kDone1).earliestMs);
    LONGS_EQUAL(t0 + 300 * 1000, rig->task.dispatcher().network().window(kDone1).latestMs);  // never beyond ub
    LONGS_EQUAL(60000, rig->task.dispatcher().activities().extendedMs[kSample1]);
    CHECK(state(kSample1) == plan_executive::ActivityState::kRunning);
    // The original command's done is not news any more; the follow-on's is.
    rig->runFor(880);
    rig->instrumentProgress(msg::Instrument::kGrinder, msg::InstrumentState::kDone, followOn, 100);
    rig->run();
    CHECK(state(kSample1) == plan_executive::ActivityState::kDone);
    LONGS_EQUAL(1, rig->count(ev::kExtendedCompleted));
    LONGS_EQUAL(0, rig->count(ev::kActivityEarly));
    LONGS_EQUAL(0, rig->count(ev::kActivityLate));
    CHECK(state(kDrive2) == plan_executive::ActivityState::kRunning);
}

TEST(PlanExecutiveExtension, RequestsAreRefusedWithTheirReasonAndThePlanUntouched) {
    refused("drive1", 10000, PlanExtensionRefusal::kNotScience);  // running, a drive
    startSample1();
    refused("nope", 10000, PlanExtensionRefusal::kUnknownActivity);
    refused("sample", 10000, PlanExtensionRefusal::kUnknownActivity);      // a prefix is not the name
    refused("sample1 ", 10000, PlanExtensionRefusal::kUnknownActivity);    // nor a longer text
    refused("drive1", 10000, PlanExtensionRefusal::kNotRunning);     // done
    refused("sample2", 10000, PlanExtensionRefusal::kNotRunning);    // waiting
    rig->extend("image1", 10000);  // not in the selection
    rig->run();
    LONGS_EQUAL(static_cast<long>(PlanExtensionRefusal::kNotRunning),
                static_cast<long>(rig->status.lastExtensionRefusal));
    CHECK(state(kImage1) == plan_executive::ActivityState::kInactive);
    refused("sample1", 0, PlanExtensionRefusal::kInvalid);
    refused("sample1", PlanExecutiveTask::kMaxExtendMs + 1, PlanExtensionRefusal::kInvalid);
    // 20 % after 30 s: 150 s in all; 200 s more passes the ub (300 s).
    grinderAt(30, 20);
    refused("sample1", 200000, PlanExtensionRefusal::kBeyondUb);
    CHECK(state(kSample1) == plan_executive::ActivityState::kRunning);
    LONGS_EQUAL(0, rig->status.activitiesFailed);
}

TEST(PlanExecutiveExtension, TheInstrumentRefusingTheFollowOnLeavesTheActivityAsItWas) {
    startSample1();
    grinderAt(60, 40);
    rig->extend("sample1", 30000);
    rig->run();
    const std::uint16_t followOn = rig->lastInstrument.commandId;
    const plan_executive::Window w = rig->task.dispatcher().network().window(kDone1);
    rig->instrumentProgress(msg::Instrument::kGrinder, msg::InstrumentState::kBusy, sampleId, 41, followOn,
                            msg::InstrumentRefusal::kNoSuchCommand);
    rig->run();
    LONGS_EQUAL(1, rig->count(ev::kExtensionRefused));
    LONGS_EQUAL(static_cast<long>(PlanExtensionRefusal::kInstrument),
                static_cast<long>(rig->status.lastExtensionRefusal));
    LONGS_EQUAL(0, rig->status.extensionsAccepted);
    LONGS_EQUAL(w.earliestMs, rig->task.dispatcher().network().window(kDone1).earliestMs);
    CHECK(state(kSample1) == plan_executive::ActivityState::kRunning);
    LONGS_EQUAL(0, rig->count(ev::kActivityFailed));
    // The original command's done completes it, as if nothing was asked.
    rig->instrumentProgress(msg::Instrument::kGrinder, msg::InstrumentState::kDone, sampleId, 100, followOn,
                            msg::InstrumentRefusal::kNoSuchCommand);
    rig->run();
    CHECK(state(kSample1) == plan_executive::ActivityState::kDone);
    LONGS_EQUAL(0, rig->count(ev::kExtendedCompleted));
}

TEST(PlanExecutiveExtension, AnActivityEndingBeforeTheAnswerOrCancelledDropsTheFollowOn) {
    startSample1();
    grinderAt(140, 93);
    rig->extend("sample1", 30000);
    rig->run();
    // The grinder finished before it read the follow-on.
    rig->instrumentProgress(msg::Instrument::kGrinder, msg::InstrumentState::kDone, sampleId, 100);
    rig->run();
    CHECK(state(kSample1) == plan_executive::ActivityState::kDone);
    LONGS_EQUAL(1, rig->count(ev::kExtensionRefused));
    LONGS_EQUAL(static_cast<long>(PlanExtensionRefusal::kNotRunning),
                static_cast<long>(rig->status.lastExtensionRefusal));
    // drive2 runs; sample2 later: a follow-on pending when the plan is aborted
    // is cancelled with the command it continues (whichever the grinder runs).
    const std::uint32_t drive2 = rig->lastGoal.goals.revision;
    rig->deliberative(msg::DeliberativeState::kExecuting, drive2);
    rig->runFor(600);
    rig->deliberative(msg::DeliberativeState::kComplete, drive2);
    rig->run();
    CHECK(state(kSample2) == plan_executive::ActivityState::kRunning);
    const std::uint16_t sample2Id = rig->lastInstrument.commandId;
    rig->extend("sample2", 30000);
    rig->run();
    const std::uint16_t followOn = rig->lastInstrument.commandId;
    const std::uint32_t commands = rig->instrumentCommands;
    rig->send(msg::PlanCommandKind::kAbort);
    rig->run();
    LONGS_EQUAL(commands + 2, rig->instrumentCommands);
    CHECK(rig->lastInstrument.action == msg::InstrumentAction::kCancel);
    LONGS_EQUAL(followOn, rig->lastInstrument.commandId);
    CHECK(sample2Id != followOn);
    LONGS_EQUAL(2, rig->count(ev::kExtensionRefused));
}

// A report window after the sample: 20 s that must end by 260 s. The sample,
// started at 1 s and expected to end at 151 s, could take 100 s more within
// its own ub (301 s), but its end would pass its latest, 240 s (the deadline
// less the report): refused, the plan untouched; 30 s more fits.
TEST(PlanExecutiveExtension, AnExtensionThatWouldBreakALaterDeadlineIsRefused) {
    rig->uploadAndStart("plan deadline\n"
                        "event at1\n"
                        "event done1\n"
                        "event back\n"
                        "activity go drive start at1 [1, 100] cost 1 at 10 0\n"
                        "activity s sample at1 done1 [120, 300] cost 1 target 1\n"
                        "activity r communicate done1 back [20, 20] cost 1\n"
                        "constraint start back [0, 260]\n"
                        "end\n");
    rig->runFor(5);
    STRCMP_EQUAL("deadline", rig->status.planName);
    rig->deliberative(msg::DeliberativeState::kComplete, rig->lastGoal.goals.revision);
    rig->runFor(10);  // the drive's lb is 1 s
    CHECK(state(1) == plan_executive::ActivityState::kRunning);
    sampleId = rig->lastInstrument.commandId;
    t0 = rig->task.dispatcher().startMs(1);
    LONGS_EQUAL(240 * 1000, rig->task.dispatcher().network().window(kDone1).latestMs);
    grinderAt(30, 20);  // 150 s in all: expected at t0 + 150 s
    LONGS_EQUAL(1000, t0);
    refused("s", 100000, PlanExtensionRefusal::kInconsistent);
    rig->extend("s", 30000);
    rig->run();
    LONGS_EQUAL(1, rig->count(ev::kExtensionRequested));
}

// Lockstep: `rse-ground plan load` end to end. The ground tool's own command
// line (runGroundCli: the ground check, PLAN_LOAD chunks each waiting for its
// acknowledgement, PLAN_START with the length and CRC-32, the wait for the
// executive's verdict) on an in-memory link to the flight software, in
// lockstep with the simulator: the packets rse-ground builds go through
// command ingest, authentication and the plan executive's commands to the
// plan executive, which must accept the plan (event 950) and start dispatching.
// A full 16 KiB upload (82 chunks) must arrive whole: the acknowledgements
// pace it under the executive's pipe of 12 a run.
#include <cstdio>
#include <deque>
#include <fstream>
#include <string>
#include <vector>

#include "fsw/msg/plan_executive_msgs.hpp"
#include "ground/ground_cli.hpp"
#include "ground/ground_link.hpp"
#include "hal/link/memory_packet_link.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;

namespace {

const char* const kTwoTargets = "unit_test/fuzz/corpus/plan/two_targets.plan";

// The ground tool's link into the rig: commands onto the uplink; telemetry
// taken off the downlink every frame. While nothing is waiting, receive(t)
// runs the rig a frame at a time, up to t of rover time.
class RigLink final : public ground::GroundLink {
public:
    RigLink(sim::LockstepRig& rig, hal::MemoryPacketLink& link) : rig_(rig), link_(link) {}

    void send(const std::vector<std::uint8_t>& packet) override {
        if (!core::isOk(link_.groundSend(packet.data(), packet.size()))) {
            throw ground::LinkError("lockstep uplink full");
        }
        ++sent;
    }
    std::optional<std::vector<std::uint8_t>> receive(double timeoutSeconds) override {
        take();
        const core::TimeNs end = rig_.clock().now() + static_cast<core::TimeNs>(timeoutSeconds * 1e9);
        while (queue_.empty() && rig_.clock().now() < end) {
            rig_.runFor(app::kMinorFramePeriod);  // the frame callback takes the downlink
        }
        if (queue_.empty()) {
            return std::nullopt;
        }
        std::vector<std::uint8_t> packet = std::move(queue_.front());
        queue_.pop_front();
        return packet;
    }
    std::string describe() const override { return "lockstep in-memory link"; }

    // Everything downlinked so far into the queue (the oldest dropped past 10 000).
    void take() {
        std::uint8_t buffer[hal::kMemoryLinkMaxPacket];
        std::size_t length = 0;
        while (core::isOk(link_.groundReceive(buffer, sizeof buffer, &length))) {
            queue_.emplace_back(buffer, buffer + length);
            if (queue_.size() > 10000) {
                queue_.pop_front();
            }
        }
    }

    std::uint32_t sent = 0;  // packets sent

private:
    sim::LockstepRig& rig_;
    hal::MemoryPacketLink& link_;
    std::deque<std::vector<std::uint8_t>> queue_;
};

RigLink* g_link = nullptr;
void takeDownlink(sim::LockstepRig&) { g_link->take(); }

}  // namespace

TEST_GROUP(LockstepPlanUplink) {
    sim::LockstepRig* rig = nullptr;
    hal::MemoryPacketLink* packets = nullptr;
    RigLink* link = nullptr;
    test::TempDir* dir = nullptr;

    void setup() override {
        rig = new sim::LockstepRig(sim::loadScenarioFile("sim_stub/scenarios/two_targets.toml"));
        packets = new hal::MemoryPacketLink;
        link = new RigLink(*rig, *packets);
        g_link = link;
        dir = new test::TempDir;
        CHECK(core::isOk(rig->fsw().addGroundLink(packets)));
        CHECK(core::Status::kOk == rig->init());
        rig->setOnFrame(takeDownlink);
        CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 3 * kNsPerSec));
        const test::CliResult mode = ground({"send", "SET_MODE", "mode=AUTONOMOUS"});
        CHECK_TEXT(mode.rc == 0, mode.err.c_str());
        link->sent = 0;  // what the tests send from here
    }
    void teardown() override {
        delete dir;
        delete rig;
        delete link;
        delete packets;
        g_link = nullptr;
    }
    // rse-ground with its state directory, on the rig's link.
    test::CliResult ground(std::vector<std::string> args) {
        args.insert(args.begin(), {"--state-dir", dir->path()});
        return test::cli(args, [this](bool) { return std::make_unique<test::BorrowedLink>(*link); });
    }
    // The executive's command pipe ("plan_exec", PlanExecutiveTask::kPipeDepth deep).
    const core::PipeStats& commandPipe() {
        core::SoftwareBus& bus = rig->fsw().bus();
        for (std::size_t p = 0; p < bus.pipeCount(); ++p) {
            if (std::string(bus.pipeName(static_cast<core::PipeId>(p))) == "plan_exec") {
                return *bus.pipeStats(static_cast<core::PipeId>(p));
            }
        }
        FAIL("no plan_exec pipe");
        return *bus.pipeStats(0);
    }
    bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
    void dumpOnFailure(bool ok, const test::CliResult& r) {
        if (!ok) {
            std::printf("rc %d\nout:\n%s\nerr:\n%s\nconsole:\n%s\n", r.rc, r.out.c_str(), r.err.c_str(),
                        rig->consoleText());
        }
    }
};

TEST(LockstepPlanUplink, TheTwoTargetsPlanLoadedByRseGroundIsAcceptedAndDispatched) {
    const test::CliResult r = ground({"plan", "load", kTwoTargets});
    dumpOnFailure(r.rc == 0, r);
    LONGS_EQUAL(0, r.rc);
    CHECK_TEXT(has(r.out, "the plan executive accepted the plan: EVT 950 INFO plan_exec: plan two_targets "
                          "accepted: 801 B, 5 events, 6 activities, 2 choices, cost 32.50"),
               r.out.c_str());
    LONGS_EQUAL(6, link->sent);  // 5 chunks and the start
    rig->runFor(200 * kNsPerMs);  // the console writes at 10 Hz
    LONGS_EQUAL(1, rig->consoleCount("EVT 950 INFO  plan_exec: plan two_targets accepted"));
    LONGS_EQUAL(0, rig->consoleCount("EVT 952"));
    LONGS_EQUAL(801, rig->fsw().planExecutive().uploadLength());
    STRCMP_EQUAL("two_targets", rig->fsw().planExecutive().plan().name);
    DOUBLES_EQUAL(32.5, rig->fsw().planExecutive().status().cost, 1e-9);
    // Dispatching: drive1 goes to the deliberative layer and the rover drives.
    CHECK_TRUE(rig->runUntil([&] { return rig->consoleCount("plan_exec: drive drive1 started") == 1; },
                             2 * kNsPerSec));
    CHECK_TRUE(rig->fsw().planExecutive().state() == msg::PlanExecutiveState::kDispatching);
}

TEST(LockstepPlanUplink, AFullSixteenKibPlanArrivesWholeInEightyTwoPacedChunks) {
    const std::string path = dir->file("full.plan");
    std::ofstream(path, std::ios::binary) << test::paddedPlan(test::readText(kTwoTargets), 16384);
    const core::TimeNs before = rig->clock().now();
    const test::CliResult r = ground({"plan", "load", path});
    const double seconds = static_cast<double>(rig->clock().now() - before) / 1e9;
    dumpOnFailure(r.rc == 0, r);
    LONGS_EQUAL(0, r.rc);
    CHECK_TRUE(has(r.out, "in 82 PLAN_LOAD chunks"));
    CHECK_TRUE(has(r.out, "EVT 950 INFO plan_exec: plan two_targets accepted: 16384 B"));
    LONGS_EQUAL(83, link->sent);
    LONGS_EQUAL(16384, rig->fsw().planExecutive().uploadLength());
    // Paced by the acknowledgements: one chunk a frame at most (10 ms), ten
    // between two runs of the executive, never more than its pipe holds.
    CHECK(seconds > 0.8);
    const core::PipeStats& pipe = commandPipe();
    LONGS_EQUAL(0, pipe.dropped);
    CHECK(pipe.highWater <= 10);
    rig->runFor(200 * kNsPerMs);
    LONGS_EQUAL(0, rig->consoleCount("EVT 952"));
    std::printf("\n  16 KiB plan: 82 chunks, start and verdict in %.2f s of rover time; executive pipe high water %u of %u\n",
                seconds, static_cast<unsigned>(pipe.highWater), static_cast<unsigned>(pipe.depth));
}

TEST(LockstepPlanUplink, APlanTheRoverRefusesIsNotSentUnlessForcedAndThenItsRefusalIsExitThree) {
    // A drive of at least 60 s to be done within 30 s: no schedule exists.
    const std::string path = dir->file("too_tight.plan");
    std::ofstream(path) << "plan too_tight\n"
                           "event there\n"
                           "activity go drive start there [60, 900] cost 10 at 10 0\n"
                           "constraint start there [0, 30]\n"
                           "end\n";
    test::CliResult r = ground({"plan", "load", path});
    LONGS_EQUAL(2, r.rc);
    CHECK_TRUE(has(r.err, "no valid selection of methods"));
    LONGS_EQUAL(0, link->sent);
    r = ground({"plan", "load", path, "--force"});
    dumpOnFailure(r.rc == 3, r);
    LONGS_EQUAL(3, r.rc);
    CHECK_TEXT(has(r.err, "the plan executive refused the plan: EVT 954 ERROR plan_exec: plan too_tight refused: "
                          "no valid selection"),
               r.err.c_str());
    CHECK_TRUE(rig->fsw().planExecutive().state() == msg::PlanExecutiveState::kIdle);
}

TEST(LockstepPlanUplink, AShortPlanIsAcceptedAndAbortStopsIt) {
    test::CliResult r = ground({"plan", "short", "plan hop; event a; activity go drive start a [0, 600] at 5 0; end"});
    dumpOnFailure(r.rc == 0, r);
    LONGS_EQUAL(0, r.rc);
    CHECK_TRUE(has(r.out, "EVT 950 INFO plan_exec: plan hop accepted"));
    LONGS_EQUAL(0, rig->fsw().planExecutive().uploadLength());  // the upload buffer is not touched
    r = ground({"plan", "abort"});
    LONGS_EQUAL(0, r.rc);
    CHECK_TRUE(rig->runUntil([&] { return rig->consoleCount("EVT 965 WARN  plan_exec: PLAN_ABORT: plan hop") == 1; },
                             kNsPerSec));
    CHECK_TRUE(rig->fsw().planExecutive().state() == msg::PlanExecutiveState::kIdle);
}

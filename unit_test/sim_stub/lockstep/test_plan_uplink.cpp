// A plan mission's uplink (sim_stub/lockstep/plan_uplink.hpp) into the flight
// software in lockstep, on the two-targets scenario: the ground's check first;
// SET_RISK_BOUND; the text in the ground's PLAN_LOAD chunks (ground/
// plan_transfer.hpp), which the plan executive writes one by one at their
// offsets; PLAN_START with the text's length and CRC-32; the executive's
// verdict. The chunks and the CRC are checked by hand (the 801-byte plan is
// 4 x 200 B + 1 B; its CRC-32 from Python's zlib.crc32), and a refused
// upload comes back with the executive's own words.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "fsw/core/byte_codec.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "ground/plan_transfer.hpp"
#include "sim_stub/lockstep/flight_watch.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/memory_ground.hpp"
#include "sim_stub/lockstep/mission_options.hpp"
#include "sim_stub/lockstep/plan_uplink.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;

namespace pe = plan_executive::events;

namespace {

const char* const kScenario = "sim_stub/scenarios/two_targets.toml";
constexpr std::size_t kTwoTargetsBytes = 801;
constexpr std::uint32_t kTwoTargetsCrc = 0xB8750EF2;  // zlib.crc32 of unit_test/fuzz/corpus/plan/two_targets.plan

bool contains(const std::string& text, const char* what) { return text.find(what) != std::string::npos; }

// The two-targets scenario's plan mission as rse-demo takes it.
sim::MissionOptions twoTargetsMission() {
    sim::MissionOptions o;
    std::string error;
    CHECK_TEXT(sim::applyScenarioMission(sim::loadScenarioFile(kScenario), &o, &error), error.c_str());
    return o;
}

}  // namespace

TEST_GROUP(PlanGroundCheck) {
    std::string error;
};

TEST(PlanGroundCheck, TheScenariosPlanPassesAndABrokenOneIsRefusedWithTheReason) {
    sim::MissionOptions o = twoTargetsMission();
    LONGS_EQUAL(kTwoTargetsBytes, o.planText.size());
    CHECK_TEXT(sim::planPassesGroundCheck(o, &error), error.c_str());
    o.planText = "plan bad\nactivity a drive start nowhere [1, 2] cost 1 at 1 1\nend\n";
    CHECK_FALSE(sim::planPassesGroundCheck(o, &error));
    CHECK_TEXT(error.rfind("the plan did not pass the ground check: ", 0) == 0, error.c_str());
    CHECK_TEXT(contains(error, "nowhere"), error.c_str());
    o.planText = std::string(ground::kPlanUploadBytes + 1, '#');  // too long to upload at all
    CHECK_FALSE(sim::planPassesGroundCheck(o, &error));
}

// What the uplink sends is the ground's plan transfer: PLAN_LOAD chunks of
// 200 bytes at most (u16 offset, then the bytes) and PLAN_START (u32 length,
// u32 CRC-32), big-endian.
TEST(PlanGroundCheck, TheChunksAndTheStartAreTheTextsByHand) {
    const sim::MissionOptions o = twoTargetsMission();
    const std::vector<std::vector<std::uint8_t>> chunks = ground::planLoadChunks(o.planText);
    LONGS_EQUAL(5, chunks.size());
    std::string joined;
    for (std::size_t k = 0; k < chunks.size(); ++k) {
        core::BeReader r(chunks[k].data(), chunks[k].size());
        LONGS_EQUAL(200 * k, r.u16());
        LONGS_EQUAL(2 + (k < 4 ? 200 : 1), chunks[k].size());  // the bytes run to the end of the arguments
        joined.append(reinterpret_cast<const char*>(chunks[k].data()) + 2, chunks[k].size() - 2);
    }
    CHECK_TRUE(joined == o.planText);
    const std::vector<std::uint8_t> start = ground::planStartArgs(o.planText);
    core::BeReader r(start.data(), start.size());
    LONGS_EQUAL(kTwoTargetsBytes, r.u32());
    LONGS_EQUAL(kTwoTargetsCrc, r.u32());
    CHECK_TRUE(r.ok());
}

TEST_GROUP(PlanUplink) {
    sim::LockstepRig* rig = nullptr;
    sim::MemoryGround* ground = nullptr;
    sim::FlightWatch* watch = nullptr;
    core::EventLog::Cursor cursor{};
    std::vector<core::Event> seen;  // the plan executive's upload events, as they came
    std::string error;

    void setup() override {
        rig = new sim::LockstepRig(sim::loadScenarioFile(kScenario));
        ground = new sim::MemoryGround;
        CHECK(core::isOk(rig->fsw().addGroundLink(&ground->link())));
        CHECK(core::Status::kOk == rig->init());
        watch = new sim::FlightWatch(rig->fsw().bus(), rig->fsw().events());
        CHECK_TRUE(watch->subscribe());
        CHECK_TRUE(rig->runUntil([&] { service(); return rig->allDrivesOperational(); }, 3 * kNsPerSec));
        CHECK_TRUE(ground->setMode(2));  // AUTONOMOUS
        CHECK_TRUE(rig->runUntil([&] { service(); return watch->modeIs(2); }, kNsPerSec));
        seen.clear();
    }
    void teardown() override {
        delete watch;
        delete ground;
        delete rig;
    }
    // Once a frame, as the mission runner's service: the downlink drained,
    // the watch, and here the flight events kept.
    void service() {
        ground->drainDownlink();
        watch->drain();
        core::Event e;
        while (core::isOk(rig->fsw().events().read(&cursor, &e))) {
            if (e.id == pe::kChunkAccepted || e.id == pe::kUploadRefused || e.id == pe::kPlanAccepted) {
                seen.push_back(e);
            }
        }
    }
    bool uplink(const sim::MissionOptions& o) {
        return sim::uplinkPlan(o, *ground, *rig, *watch, [this] { service(); }, &error);
    }
    std::vector<std::string> textsOf(core::EventId id) const {
        std::vector<std::string> texts;
        for (const core::Event& e : seen) {
            if (e.id == id) {
                texts.emplace_back(e.text);
            }
        }
        return texts;
    }
};

// The 801-byte plan: the executive writes 5 chunks at offsets 0, 200, 400,
// 600 and 800, in order, and accepts the whole text (its length and CRC-32
// matched PLAN_START's); the operator's risk bound is in force.
TEST(PlanUplink, TheScenariosPlanArrivesInItsChunksAndIsAccepted) {
    sim::MissionOptions o = twoTargetsMission();
    o.risk = 2e-3;
    const core::TimeNs before = rig->clock().now();
    CHECK_TEXT(uplink(o), error.c_str());
    // SET_RISK_BOUND and each of the 5 chunks 20 ms apart, then the verdict.
    CHECK(rig->clock().now() - before >= 6 * 20 * kNsPerMs);
    const std::vector<std::string> chunks = textsOf(pe::kChunkAccepted);
    LONGS_EQUAL(5, chunks.size());
    STRCMP_EQUAL("plan_exec: chunk at 0, 200 B: 200 B of plan text", chunks[0].c_str());
    STRCMP_EQUAL("plan_exec: chunk at 200, 200 B: 400 B of plan text", chunks[1].c_str());
    STRCMP_EQUAL("plan_exec: chunk at 400, 200 B: 600 B of plan text", chunks[2].c_str());
    STRCMP_EQUAL("plan_exec: chunk at 600, 200 B: 800 B of plan text", chunks[3].c_str());
    STRCMP_EQUAL("plan_exec: chunk at 800, 1 B: 801 B of plan text", chunks[4].c_str());
    LONGS_EQUAL(0, textsOf(pe::kUploadRefused).size());
    const std::vector<std::string> accepted = textsOf(pe::kPlanAccepted);
    LONGS_EQUAL(1, accepted.size());
    CHECK_TEXT(contains(accepted[0], "plan two_targets accepted: 801 B"), accepted[0].c_str());
    LONGS_EQUAL(kTwoTargetsBytes, rig->fsw().planExecutive().uploadLength());
    LONGS_EQUAL(1, watch->planExec().plansAccepted);
    LONGS_EQUAL(0, watch->planExec().plansRefused);
    CHECK_TRUE(rig->runUntil([&] { service(); return watch->plan().riskBound == 2e-3; }, 2 * kNsPerSec));
}

// A plan the executive's parser refuses: the chunks and the start are taken,
// the text refused (event 953), and the uplink fails with the executive's words.
TEST(PlanUplink, APlanTheExecutiveRefusesFailsWithItsWords) {
    sim::MissionOptions o = twoTargetsMission();
    o.planText = "plan broken\nthis is no statement\nend\n";
    CHECK_FALSE(uplink(o));
    LONGS_EQUAL(1, textsOf(pe::kChunkAccepted).size());
    CHECK_TEXT(error.rfind("the plan executive refused the plan: plan_exec: ", 0) == 0, error.c_str());
    CHECK_TEXT(error.substr(std::strlen("the plan executive refused the plan: ")) == watch->planRefusal(),
               error.c_str());
    LONGS_EQUAL(1, watch->planExec().plansRefused);
    LONGS_EQUAL(0, watch->planExec().plansAccepted);
}

// A text too long to upload has no chunks, and a PLAN_START whose length
// passes the dictionary's range (16384 B) is rejected by the command service
// before the executive sees it: no verdict, and the uplink says so after
// kPlanVerdictSeconds.
TEST(PlanUplink, NoVerdictWithinItsTimeFailsTheUplink) {
    sim::MissionOptions o = twoTargetsMission();
    o.planText.append(ground::kPlanUploadBytes, '#');
    const core::TimeNs before = rig->clock().now();
    CHECK_FALSE(uplink(o));
    STRCMP_EQUAL("no verdict from the plan executive within 3 s", error.c_str());
    CHECK(rig->clock().now() - before >= 3 * kNsPerSec);
    LONGS_EQUAL(0, textsOf(pe::kChunkAccepted).size());
    LONGS_EQUAL(0, watch->planExec().plansRefused);
    LONGS_EQUAL(0, watch->planExec().plansAccepted);
}

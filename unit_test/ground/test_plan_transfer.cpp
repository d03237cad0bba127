// `rse-ground plan load / short / abort` (ground/plan_transfer.hpp): the
// chunks' offsets, lengths and bytes put back together are the file;
// PLAN_START carries its length and CRC-32; each command waits for its
// acknowledgement; the executive's verdict (its events) decides the exit
// code; a plan the ground check refuses, and a file over the rover's buffer,
// are not sent (the link is not even opened).
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/plan_executive/plan_parser.hpp"
#include "ground/ground_session.hpp"
#include "ground/plan_transfer.hpp"
#include "ground/sequence_store.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

const char* const kTwoTargets = "unit_test/fuzz/corpus/plan/two_targets.plan";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

using test::readText;
std::string paddedPlan(std::size_t size) { return test::paddedPlan(test::readText(kTwoTargets), size); }

using Rig = test::SessionRig;

}  // namespace

TEST_GROUP(GroundPlanTransfer){};

TEST(GroundPlanTransfer, ChunksAre200BytesFromOffset0AndPutBackTogetherAreTheText) {
    const std::string plan = readText(kTwoTargets);
    LONGS_EQUAL(801, plan.size());
    const auto chunks = ground::planLoadChunks(plan);
    LONGS_EQUAL(5, chunks.size());
    std::string joined;
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        cmdtlm::PLAN_LOAD_Args a{};
        core::BeReader r(chunks[i].data(), chunks[i].size());
        cmdtlm::decodeArgs(r, &a);
        LONGS_EQUAL(i * 200, a.offset);
        LONGS_EQUAL(i < 4 ? 200 : plan.size() - 800, a.data_length);
        LONGS_EQUAL(2 + a.data_length, chunks[i].size());  // u16 offset, then the bytes
        CHECK_EQUAL(joined.size(), a.offset);
        joined.append(reinterpret_cast<const char*>(a.data), a.data_length);
    }
    CHECK_TRUE(joined == plan);
}

TEST(GroundPlanTransfer, AFullBufferIs82ChunksTheLastEndingAt16384AndOneByteMoreIsNone) {
    const std::string full = paddedPlan(16384);
    LONGS_EQUAL(16384, full.size());
    const auto chunks = ground::planLoadChunks(full);
    LONGS_EQUAL(82, chunks.size());
    cmdtlm::PLAN_LOAD_Args last{};
    core::BeReader r(chunks.back().data(), chunks.back().size());
    cmdtlm::decodeArgs(r, &last);
    LONGS_EQUAL(16200, last.offset);
    LONGS_EQUAL(184, last.data_length);
    CHECK_TRUE(ground::planLoadChunks(full + "\n").empty());
}

TEST(GroundPlanTransfer, PlanStartCarriesTheLengthAndTheCrc32OfTheText) {
    const std::vector<std::uint8_t> args = ground::planStartArgs(readText(kTwoTargets));
    cmdtlm::PLAN_START_Args a{};
    core::BeReader r(args.data(), args.size());
    cmdtlm::decodeArgs(r, &a);
    LONGS_EQUAL(8, args.size());
    LONGS_EQUAL(801, a.length);
    // zlib.crc32 of the file, computed apart from this code (python3 -c
    // "import zlib; print(hex(zlib.crc32(open(PATH, 'rb').read())))").
    UNSIGNED_LONGS_EQUAL(0xb8750ef2U, a.crc32);
}

TEST(GroundPlanTransfer, LoadSendsEveryChunkThenPlanStartAndReportsTheAcceptance) {
    Rig rig;
    const std::string plan = readText(kTwoTargets);
    LONGS_EQUAL(0, ground::loadPlanText(rig.session, plan, 0.5, rig.out, rig.err));
    STRCMP_EQUAL("", rig.err.str().c_str());
    CHECK_TRUE(rig.rover.planTaken == plan);
    const std::vector<std::string> expected = {"PLAN_LOAD", "PLAN_LOAD", "PLAN_LOAD", "PLAN_LOAD", "PLAN_LOAD",
                                               "PLAN_START"};
    CHECK_TRUE(rig.rover.executed == expected);
    // One command at a time: every one acknowledged before the next went.
    LONGS_EQUAL(6, rig.rover.verdicts.size());
    CHECK_TRUE(contains(rig.out.str(), "loading 801 bytes of plan text (CRC-32 0xb8750ef2) in 5 PLAN_LOAD chunks"));
    CHECK_TRUE(contains(rig.out.str(), "PLAN_LOAD 5/5 (offset 800): PLAN_LOAD (0x185/0"));
    CHECK_TRUE(contains(rig.out.str(), "the plan executive accepted the plan: EVT 950 INFO plan_exec: verdict"));
}

TEST(GroundPlanTransfer, AFullSixteenKibPlanGoesUpWhole) {
    Rig rig;
    const std::string full = paddedPlan(16384);
    LONGS_EQUAL(0, ground::loadPlanText(rig.session, full, 0.5, rig.out, rig.err));
    LONGS_EQUAL(83, rig.rover.executed.size());
    CHECK_TRUE(rig.rover.planTaken == full);
}

TEST(GroundPlanTransfer, TheExecutivesRefusalIsExitThreeWithItsEvent) {
    Rig rig;
    rig.rover.planVerdict = 953;
    LONGS_EQUAL(3, ground::loadPlanText(rig.session, readText(kTwoTargets), 0.5, rig.out, rig.err));
    CHECK_TRUE(contains(rig.err.str(), "the plan executive refused the plan: EVT 953 ERROR plan_exec: verdict"));
}

TEST(GroundPlanTransfer, AChunkLostOnBoardStopsTheLoadAtTheExecutivesGapRefusal) {
    Rig rig;
    rig.rover.planLoseChunk = 1;  // acknowledged, then lost (a full pipe): chunk 3 is beyond the text
    LONGS_EQUAL(3, ground::loadPlanText(rig.session, readText(kTwoTargets), 0.5, rig.out, rig.err));
    LONGS_EQUAL(3, rig.rover.executed.size());  // stopped after the refused chunk; no PLAN_START
    CHECK_TRUE(contains(rig.err.str(), "the plan executive refused the upload: EVT 952 ERROR plan_exec: refused (gap)"));
    CHECK_TRUE(rig.rover.planTaken.empty());
}

TEST(GroundPlanTransfer, ARejectedCommandStopsTheLoadWithItsReason) {
    Rig rig;
    rig.rover.mode = cmdtlm::Mode::kSafe;  // PLAN_LOAD goes in any mode, PLAN_START not in SAFE
    LONGS_EQUAL(3, ground::loadPlanText(rig.session, readText(kTwoTargets), 0.5, rig.out, rig.err));
    LONGS_EQUAL(6, rig.rover.verdicts.size());
    CHECK_TRUE(contains(rig.err.str(), "PLAN_START: PLAN_START (0x185/1"));
    CHECK_TRUE(contains(rig.err.str(), "rejected: wrong_mode"));
}

TEST(GroundPlanTransfer, NoAcknowledgementOrNoVerdictIsExitOne) {
    Rig rig;
    rig.rover.answer = false;
    LONGS_EQUAL(1, ground::loadPlanText(rig.session, readText(kTwoTargets), 0.2, rig.out, rig.err));
    CHECK_TRUE(contains(rig.err.str(), "PLAN_LOAD 1/5 (offset 0): no acknowledgement within 0.3 s"));

    Rig quiet;
    quiet.rover.planEvents = false;
    LONGS_EQUAL(1, ground::loadPlanText(quiet.session, readText(kTwoTargets), 0.2, quiet.out, quiet.err));
    CHECK_TRUE(contains(quiet.err.str(), "PLAN_START: accepted, but no verdict from the plan executive within 0.2 s"));
}

TEST(GroundPlanTransfer, TextTooLongForTheBufferOrEmptyIsNeverSent) {
    Rig rig;
    LONGS_EQUAL(2, ground::loadPlanText(rig.session, paddedPlan(16385), 0.2, rig.out, rig.err));
    LONGS_EQUAL(2, ground::loadPlanText(rig.session, "", 0.2, rig.out, rig.err));
    LONGS_EQUAL(2, ground::sendShortPlan(rig.session, std::string(201, ' '), 0.2, rig.out, rig.err));
    CHECK_TRUE(rig.link.sent.empty());
    CHECK_TRUE(contains(rig.err.str(), "plan load: 16385 bytes of plan text; the rover takes 1 to 16384"));
}

TEST(GroundPlanTransfer, TheCheckBeforeSendingIsPlanChecks) {
    std::ostringstream out, err;
    const plan_executive::SelectionInput ok;
    const std::string plan = readText(kTwoTargets);
    LONGS_EQUAL(0, ground::checkPlanForUplink(plan, "p", ground::kPlanUploadBytes, ok, false, out, err));
    CHECK_TRUE(contains(out.str(), "expected cost: 32.500"));
    plan_executive::SelectionInput noInstruments;
    noInstruments.components[static_cast<std::size_t>(plan_executive::Component::kGrinder)] =
        plan_executive::ComponentState::kFailed;
    noInstruments.components[static_cast<std::size_t>(plan_executive::Component::kCamera)] =
        plan_executive::ComponentState::kFailed;
    LONGS_EQUAL(2, ground::checkPlanForUplink(plan, "p", ground::kPlanUploadBytes, noInstruments, false, out, err));
    CHECK_TRUE(contains(err.str(), "p: no valid selection of methods"));
    CHECK_TRUE(contains(err.str(), "p: not sent (--force sends it anyway"));
    LONGS_EQUAL(0, ground::checkPlanForUplink(plan, "p", ground::kPlanUploadBytes, noInstruments, true, out, err));
    // Forced or not, a plan longer than the command can carry is never sent.
    LONGS_EQUAL(2, ground::checkPlanForUplink(plan, "p", ground::kPlanShortBytes, ok, true, out, err));
}

// ---- The command line -------------------------------------------------------

TEST_GROUP(GroundPlanCli){};

TEST(GroundPlanCli, PlanLoadChecksThenUploadsAndExitsZeroOnTheAcceptance) {
    test::CliRig rig;
    const test::CliResult r = rig.run({"plan", "load", kTwoTargets});
    CHECK_TEXT(r.rc == 0, r.err.c_str());
    CHECK_TRUE(rig.rover.planTaken == readText(kTwoTargets));
    CHECK_TRUE(contains(r.out, "plan 'two_targets': 5 events, 6 activities"));  // the ground check's summary
    CHECK_TRUE(contains(r.out, "expected cost: 32.500"));
    CHECK_TRUE(contains(r.out, "the plan executive accepted the plan"));
}

TEST(GroundPlanCli, ARefusedPlanOrAnOversizeFileIsNotSentAndNoLinkIsOpened) {
    test::CliRig rig;
    const std::string bad = rig.dir.file("bad.plan");
    std::ofstream(bad) << "plan bad\nevent a\nactivity x teleport start a [0, 1]\nend\n";
    test::CliResult r = rig.run({"plan", "load", bad});
    LONGS_EQUAL(2, r.rc);
    CHECK_TEXT(contains(r.err, bad + ":3: unknown activity kind at 'teleport' (the rover would refuse this plan)"),
               r.err.c_str());
    CHECK_TRUE(contains(r.err, "not sent"));

    r = rig.run({"plan", "load", kTwoTargets, "--failed", "grinder,camera"});
    LONGS_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "no valid selection of methods"));

    const std::string big = rig.dir.file("big.plan");
    std::ofstream(big, std::ios::binary) << paddedPlan(16385);
    r = rig.run({"plan", "load", big});
    LONGS_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "16385 bytes of plan text; the rover takes 1 to 16384 (its plan upload buffer)"));
    r = rig.run({"plan", "load", big, "--force"});
    LONGS_EQUAL(2, r.rc);

    LONGS_EQUAL(0, rig.linksOpened);
    CHECK_TRUE(rig.link.sent.empty());
    LONGS_EQUAL(1, rig.run({"plan", "load", rig.dir.file("missing.plan")}).rc);
}

TEST(GroundPlanCli, ForceSendsARefusedPlanToSeeTheRoverRefuseIt) {
    test::CliRig rig;
    rig.rover.planVerdict = 954;
    const test::CliResult r = rig.run({"plan", "load", kTwoTargets, "--failed", "grinder,camera", "--force"});
    LONGS_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.err, "sending it anyway (--force)"));
    CHECK_TRUE(contains(r.err, "the plan executive refused the plan: EVT 954"));
}

TEST(GroundPlanCli, ShortSendsTheTextInOnePlanShortAndAbortSendsPlanAbort) {
    test::CliRig rig;
    const std::string text = "plan p; event a; activity go drive start a [0, 600] at 5 5; end";
    test::CliResult r = rig.run({"plan", "short", text});
    CHECK_TEXT(r.rc == 0, r.err.c_str());
    CHECK_TRUE(rig.rover.planTaken == text);
    STRCMP_EQUAL("PLAN_SHORT", rig.rover.executed.back().c_str());

    r = rig.run({"plan", "short", "plan p; event a; end; event b"});
    LONGS_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "plan short:1: text after the end marker"));

    r = rig.run({"plan", "abort"});
    LONGS_EQUAL(0, r.rc);
    STRCMP_EQUAL("PLAN_ABORT", rig.rover.executed.back().c_str());
    CHECK_TRUE(contains(r.out, "PLAN_ABORT (0x185/3"));
}

TEST(GroundPlanCli, UsageErrors) {
    test::CliRig rig;
    LONGS_EQUAL(2, rig.run({"plan", "load"}).rc);
    LONGS_EQUAL(2, rig.run({"plan", "load", kTwoTargets, "extra"}).rc);
    const test::CliResult unknown = rig.run({"plan", "load", kTwoTargets, "--failed", "laser"});
    LONGS_EQUAL(2, unknown.rc);
    CHECK_TRUE(contains(unknown.err, "plan load: unknown component 'laser'"));
    LONGS_EQUAL(2, rig.run({"plan", "load", kTwoTargets, "--degraded"}).rc);
    LONGS_EQUAL(2, rig.run({"plan", "load", kTwoTargets, "--activate"}).rc);
    LONGS_EQUAL(2, rig.run({"plan", "abort", "now"}).rc);
    LONGS_EQUAL(0, rig.linksOpened);
}

// Command scripts: parsing (good and bad lines, with line numbers), wait
// conditions against decoded packets, and whole scripts run against a fake rover
// that checks packets with the flight's validator.
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/command_encoder.hpp"
#include "ground/ground_session.hpp"
#include "ground/script_runner.hpp"
#include "ground/sequence_store.hpp"
#include "ground/telemetry_decoder.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using ground::ScriptStatement;

namespace {

ground::Script parse(const std::string& text) {
    std::istringstream in(text);
    return ground::parseScript(in);
}

std::string conditionError(const std::string& text) {
    try {
        (void)ground::parseCondition(text);
    } catch (const ground::ScriptError& e) {
        return e.what();
    }
    return "";
}

ground::DecodedPacket hkWithMode(std::uint8_t mode) {
    cmdtlm::HK_Tlm hk{};
    hk.mode = mode;
    hk.cmd_rejected_by_reason[10] = 4;
    return ground::decodeTelemetry(test::telemetryPacket(hk));
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

struct Rig : test::SessionRig {
    int run(const std::string& text) {
        ground::ScriptRunner runner(session, out, err);
        return runner.run(parse(text), "test.rsc");
    }
};

}  // namespace

TEST_GROUP(GroundScriptParse){};

TEST(GroundScriptParse, GoodScriptWithCommentsAndBlankLines) {
    const ground::Script s = parse(
        "# set up\n"
        "\n"
        "send SET_MODE mode=1   # to standby\n"
        "send-expect replayed_sequence NOOP --auth-seq 5\n"
        "wait HK.mode == 1 within 5\n"
        "wait DRIVES.state[2]>=4\n"
        "sleep 0.5\n"
        "print step 2 done # a comment\n");
    CHECK_TRUE(s.ok());
    CHECK_EQUAL(6U, s.statements.size());
    CHECK_TRUE(s.statements[0].kind == ScriptStatement::Kind::kSend);
    CHECK_EQUAL(3, s.statements[0].line);
    STRCMP_EQUAL("SET_MODE", s.statements[0].command->name);
    CHECK_EQUAL(1U, s.statements[0].args.size());
    CHECK_EQUAL(1, s.statements[0].args[0]);
    STRCMP_EQUAL("send SET_MODE mode=1", s.statements[0].source.c_str());

    CHECK_TRUE(s.statements[1].kind == ScriptStatement::Kind::kSendExpect);
    CHECK_EQUAL(10U, s.statements[1].expectedReason);
    CHECK_TRUE(s.statements[1].authSequence.has_value());
    CHECK_EQUAL(5U, *s.statements[1].authSequence);

    CHECK_TRUE(s.statements[2].kind == ScriptStatement::Kind::kWait);
    DOUBLES_EQUAL(5.0, s.statements[2].seconds, 0.0);
    STRCMP_EQUAL("HK.mode == 1", s.statements[2].condition.source.c_str());

    CHECK_EQUAL(2U, s.statements[3].condition.index);
    CHECK_TRUE(s.statements[3].condition.op == ground::CompareOp::kGe);
    DOUBLES_EQUAL(ground::kDefaultWaitSeconds, s.statements[3].seconds, 0.0);

    CHECK_TRUE(s.statements[4].kind == ScriptStatement::Kind::kSleep);
    DOUBLES_EQUAL(0.5, s.statements[4].seconds, 0.0);
    CHECK_TRUE(s.statements[5].kind == ScriptStatement::Kind::kPrint);
    STRCMP_EQUAL("step 2 done", s.statements[5].text.c_str());
    CHECK_EQUAL(8, s.statements[5].line);
}

TEST(GroundScriptParse, BadLinesAreReportedWithTheirNumbers) {
    const ground::Script s = parse(
        "send NOOP\n"
        "sned NOOP\n"
        "send GOTO x=1 y=2\n"
        "send FLY\n"
        "wait HK.mode = 1\n"
        "wait HK.nothing == 1\n"
        "send-expect bogus NOOP\n"
        "sleep soon\n"
        "wait HK.mode == 1 within -2\n"
        "send NOOP --auth-seq\n");
    CHECK_FALSE(s.ok());
    CHECK_EQUAL(9U, s.errors.size());
    CHECK_TRUE(s.errors[0].rfind("line 2: unknown statement 'sned'", 0) == 0);
    CHECK_TRUE(s.errors[1].rfind("line 3: GOTO: missing argument 'risk'", 0) == 0);
    CHECK_TRUE(contains(s.errors[1], "usage: GOTO x="));
    CHECK_TRUE(s.errors[2].rfind("line 4: unknown command 'FLY'", 0) == 0);
    CHECK_TRUE(s.errors[3].rfind("line 5: no comparison", 0) == 0);
    CHECK_TRUE(s.errors[4].rfind("line 6: HK has no field 'nothing'", 0) == 0);
    CHECK_TRUE(s.errors[5].rfind("line 7: unknown reason 'bogus'", 0) == 0);
    CHECK_TRUE(contains(s.errors[5], "replayed_sequence"));
    CHECK_TRUE(s.errors[6].rfind("line 8: sleep 'soon'", 0) == 0);
    CHECK_TRUE(s.errors[7].rfind("line 9: within '-2'", 0) == 0);
    CHECK_TRUE(s.errors[8].rfind("line 10: --auth-seq needs a number", 0) == 0);
}

TEST(GroundScriptParse, ConditionErrors) {
    CHECK_TRUE(contains(conditionError("NOPE.x == 1"), "unknown telemetry packet 'NOPE'"));
    CHECK_TRUE(contains(conditionError("HK.cmd_rejected_by_reason == 1"), "is an array of 20: write"));
    CHECK_TRUE(contains(conditionError("HK.cmd_rejected_by_reason[20] == 1"), "index beyond the 20 elements"));
    CHECK_TRUE(contains(conditionError("HK.mode[x] == 1"), "FIELD[i]"));
    CHECK_TRUE(contains(conditionError("EVENT.text < abc"), "only == and != compare it"));
    CHECK_TRUE(contains(conditionError("HK.mode == fast"), "'fast' is not a number"));
    CHECK_TRUE(contains(conditionError("HK.mode =="), "no value"));
    CHECK_TRUE(contains(conditionError("mode == 1"), "is not PACKET.FIELD"));
}

TEST_GROUP(GroundWaitCondition){};

TEST(GroundWaitCondition, ComparesTheNamedFieldOfTheNamedPacket) {
    const ground::WaitCondition c = ground::parseCondition("HK.mode == 1");
    CHECK_TRUE(c.holds(hkWithMode(1)));
    CHECK_FALSE(c.holds(hkWithMode(2)));
    STRCMP_EQUAL("HK.mode = 2", c.observed(hkWithMode(2)).c_str());
    cmdtlm::CMD_ACK_Tlm ack{};
    const ground::DecodedPacket other = ground::decodeTelemetry(test::telemetryPacket(ack));
    CHECK_FALSE(c.appliesTo(other));
    CHECK_FALSE(c.holds(other));
}

TEST(GroundWaitCondition, EveryOperator) {
    const ground::DecodedPacket p = hkWithMode(2);
    CHECK_TRUE(ground::parseCondition("HK.mode != 1").holds(p));
    CHECK_TRUE(ground::parseCondition("HK.mode < 3").holds(p));
    CHECK_FALSE(ground::parseCondition("HK.mode < 2").holds(p));
    CHECK_TRUE(ground::parseCondition("HK.mode <= 2").holds(p));
    CHECK_TRUE(ground::parseCondition("HK.mode > 1.5").holds(p));
    CHECK_FALSE(ground::parseCondition("HK.mode > 2").holds(p));
    CHECK_TRUE(ground::parseCondition("HK.mode >= 2").holds(p));
    CHECK_TRUE(ground::parseCondition("hk.MODE == AUTONOMOUS").holds(p));
}

TEST(GroundWaitCondition, ArrayElementsAndTexts) {
    const ground::DecodedPacket p = hkWithMode(0);
    CHECK_TRUE(ground::parseCondition("HK.cmd_rejected_by_reason[10] == 4").holds(p));
    CHECK_FALSE(ground::parseCondition("HK.cmd_rejected_by_reason[9] == 4").holds(p));
    STRCMP_EQUAL("HK.cmd_rejected_by_reason[10] = 4",
                 ground::parseCondition("HK.cmd_rejected_by_reason[10] > 0").observed(p).c_str());

    cmdtlm::EVENT_Tlm e{};
    std::strncpy(e.text, "table: ROVER_GEOMETRY activated", sizeof e.text);
    const ground::DecodedPacket event = ground::decodeTelemetry(test::telemetryPacket(e));
    CHECK_TRUE(ground::parseCondition("EVENT.text == table: ROVER_GEOMETRY activated").holds(event));
    CHECK_TRUE(ground::parseCondition("EVENT.text == \"table: ROVER_GEOMETRY activated\"").holds(event));
    CHECK_TRUE(ground::parseCondition("EVENT.text != other").holds(event));
}

TEST_GROUP(GroundScriptRun){};

TEST(GroundScriptRun, PassingScriptExitsZero) {
    Rig rig;
    const int rc = rig.run(
        "print start\n"
        "send SET_MODE mode=MANUAL\n"
        "wait HK.mode == 3 within 1\n"
        "send DRIVE v=0.2 omega=0 duration=1\n"
        "send NOOP --auth-seq 500\n"
        "send-expect replayed_sequence NOOP --auth-seq 500\n"
        "send-expect wrong_mode GOTO x=1 y=2 risk=0.01\n"
        "wait CMD_ACK.rejected == 2 within 1\n"
        "sleep 0.05\n");
    STRCMP_EQUAL("", rig.err.str().c_str());
    CHECK_EQUAL(0, rc);
    CHECK_TRUE(contains(rig.out.str(), "start\n"));
    CHECK_TRUE(contains(rig.out.str(), "line 2: SET_MODE (0x180/3, auth seq 1) accepted"));
    CHECK_TRUE(contains(rig.out.str(), "line 3: HK.mode == 3: met"));
    CHECK_TRUE(contains(rig.out.str(), "line 6: NOOP (0x180/0, auth seq 500) rejected: replayed_sequence"));
    CHECK_TRUE(contains(rig.out.str(), "test.rsc: all 9 statements passed"));
    CHECK_TRUE(rig.rover.mode == cmdtlm::Mode::kManual);
    CHECK_EQUAL(3U, rig.rover.executed.size());  // SET_MODE, DRIVE, the first NOOP
    // Numbers after a forced one continue above it: the GOTO after the two 500s got 501.
    CHECK_EQUAL(501U, rig.store.last(1));
    CHECK_EQUAL(501U, rig.rover.verdicts.back().authSequence);
}

TEST(GroundScriptRun, ARejectedSendFailsAtItsLine) {
    Rig rig;
    rig.rover.mode = cmdtlm::Mode::kSafe;
    const int rc = rig.run("print a\nsend GOTO x=1 y=2 risk=0.01\nprint never\n");
    CHECK_EQUAL(1, rc);
    CHECK_TRUE(contains(rig.err.str(), "test.rsc:2: FAILED: send GOTO x=1 y=2 risk=0.01"));
    CHECK_TRUE(contains(rig.err.str(), "expected acceptance, got GOTO (0x181/0, auth seq 1) rejected: wrong_mode"));
    CHECK_TRUE(contains(rig.err.str(), "1 of 3 statements passed, stopped at line 2"));
    CHECK_FALSE(contains(rig.out.str(), "never"));
}

TEST(GroundScriptRun, AnUnmetWaitFailsWithTheLastValueSeen) {
    Rig rig;
    const int rc = rig.run("send SET_MODE mode=2\nwait HK.mode == 3 within 0.2\n");
    CHECK_EQUAL(1, rc);
    CHECK_TRUE(contains(rig.err.str(), "test.rsc:2: FAILED: wait HK.mode == 3 within 0.2"));
    CHECK_TRUE(contains(rig.err.str(), "not met within 0.2 s (last HK.mode = 2)"));
}

TEST(GroundScriptRun, WaitsIgnorePacketsFromBeforeTheLastSend) {
    Rig rig;
    // HK with mode 1 arrives after the first command; the second command makes it 2.
    const int rc = rig.run("send SET_MODE mode=1\nsend SET_MODE mode=2\nwait HK.mode == 1 within 0.2\n");
    CHECK_EQUAL(1, rc);
    CHECK_TRUE(contains(rig.err.str(), "last HK.mode = 2"));
}

TEST(GroundScriptRun, NoAcknowledgementFailsWithTheLinkHint) {
    Rig rig;
    rig.rover.answer = false;
    const int rc = rig.run("send NOOP\n");
    CHECK_EQUAL(1, rc);
    CHECK_TRUE(contains(rig.err.str(), "test.rsc:1: FAILED: send NOOP"));
    CHECK_TRUE(contains(rig.err.str(), "no acknowledgement within 0.3 s: is rse-fsw running and is the link up?"));
}

TEST(GroundScriptRun, ABadLineStopsTheScriptBeforeAnythingIsSent) {
    Rig rig;
    const int rc = rig.run("send NOOP\nsend GOTO x=1 y=2 risk=5\n");
    CHECK_EQUAL(1, rc);
    CHECK_TRUE(contains(rig.err.str(), "test.rsc: line 2: GOTO: risk=5 is out of range 1e-09..0.49"));
    CHECK_TRUE(contains(rig.err.str(), "nothing was sent"));
    CHECK_EQUAL(0U, rig.link.sent.size());
}

TEST(GroundScriptRun, ScriptFileThatCannotBeReadFails) {
    Rig rig;
    CHECK_EQUAL(1, ground::runScriptFile("/nonexistent/script.rsc", rig.session, rig.out, rig.err));
    CHECK_TRUE(contains(rig.err.str(), "cannot read script"));
}

// The plan text parser (plan_parser.hpp): the two-targets example read whole,
// every odd-but-legal input that crashed a fielded executive (comment
// characters inside strings, an empty plan, a plan of only its end marker),
// and each rejection with its reason, line and token; nothing left of a
// refused plan; no heap; never a read past the given length.
#include <cstdio>
#include <cstring>
#include <string>

#include "fsw/plan_executive/plan_parser.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::plan_executive;

namespace {

Tpn plan;  // 49 kB: static, as in flight

ParseResult parse(const std::string& text) { return parsePlan(text.data(), text.size(), &plan); }

// The rejection, its line and its token, in one check with a readable failure.
void refused(const std::string& text, PlanError error, std::uint32_t line, const char* token) {
    const ParseResult r = parse(text);
    const std::string what = std::string("expected '") + toString(error) + "' at line " + std::to_string(line) +
                             " token '" + token + "', got '" + toString(r.error) + "' at line " +
                             std::to_string(r.line) + " token '" + r.token + "'";
    CHECK_TEXT(r.error == error, what.c_str());
    CHECK_TEXT(r.line == line, what.c_str());
    STRCMP_EQUAL(token, r.token);
    // Nothing of a refused plan is left to use.
    LONGS_EQUAL(0, plan.activityCount);
    LONGS_EQUAL(1, plan.eventCount);
    LONGS_EQUAL(0, plan.choiceCount);
}

// The example of docs/plan_executive.md (tpn_builders.hpp).
const char* const kTwoTargets = rse::test::plan::kTwoTargetsText;

}  // namespace

TEST_GROUP(PlanParser){};

TEST(PlanParser, TheTwoTargetsPlanIsReadWhole) {
    const ParseResult r = parse(kTwoTargets);
    CHECK_TEXT(r.error == PlanError::kOk, toString(r.error));
    STRCMP_EQUAL("two_targets", plan.name);
    LONGS_EQUAL(5, plan.eventCount);  // start and four declared
    STRCMP_EQUAL("start", plan.events[0].name);
    LONGS_EQUAL(6, plan.activityCount);
    LONGS_EQUAL(1, plan.constraintCount);
    LONGS_EQUAL(2, plan.choiceCount);
    LONGS_EQUAL(1, plan.variableCount);

    const Activity& drive1 = plan.activities[0];
    CHECK(drive1.kind == ActivityKind::kDrive);
    LONGS_EQUAL(0, drive1.from);
    LONGS_EQUAL(1, drive1.to);
    LONGS_EQUAL(60000, drive1.duration.lbMs);
    LONGS_EQUAL(900000, drive1.duration.ubMs);
    DOUBLES_EQUAL(10.0, drive1.cost, 0.0);
    DOUBLES_EQUAL(10.0, drive1.x, 0.0);
    DOUBLES_EQUAL(0.0, drive1.y, 0.0);
    LONGS_EQUAL(1, drive1.askCount);
    CHECK(!drive1.asks[0].planVariable);
    CHECK(drive1.asks[0].variable == static_cast<std::uint8_t>(Component::kDriveML));
    CHECK(drive1.asks[0].value == static_cast<std::uint8_t>(ComponentState::kFailed));
    CHECK(drive1.asks[0].negated);
    CHECK(!drive1.guard.guarded());

    const Activity& sample1 = plan.activities[1];
    CHECK(sample1.kind == ActivityKind::kSample);
    LONGS_EQUAL(1, sample1.target);
    LONGS_EQUAL(0, sample1.guard.choice);
    LONGS_EQUAL(0, sample1.guard.option);
    LONGS_EQUAL(1, sample1.tellCount);
    CHECK(sample1.tells[0].planVariable);
    LONGS_EQUAL(0, sample1.tells[0].variable);
    LONGS_EQUAL(1, sample1.tells[0].value);  // "yes"

    const Activity& drive2 = plan.activities[3];
    CHECK(drive2.duration.ubMs == kInfiniteMs);
    DOUBLES_EQUAL(12.5, drive2.cost, 0.0);

    const Activity& image2 = plan.activities[5];
    LONGS_EQUAL(1, image2.guard.choice);
    LONGS_EQUAL(1, image2.guard.option);

    STRCMP_EQUAL("image", plan.choices[0].options[1].name);
    DOUBLES_EQUAL(2.0, plan.choices[0].options[1].cost, 0.0);
    DOUBLES_EQUAL(0.0, plan.choices[0].options[0].cost, 0.0);
    LONGS_EQUAL(3600000, plan.constraints[0].bounds.ubMs);
}

TEST(PlanParser, CommentCharactersInsideStringsAreText) {
    const ParseResult r = parse(
        "plan \"sol 12 #2; v2\"  # a comment after it\n"
        "event \"rock #2\"\n"
        "activity \"look # at it\" wait start \"rock #2\" [1, 2]\n"
        "end\n");
    CHECK_TEXT(r.error == PlanError::kOk, toString(r.error));
    STRCMP_EQUAL("sol 12 #2; v2", plan.name);
    STRCMP_EQUAL("rock #2", plan.events[1].name);
    STRCMP_EQUAL("look # at it", plan.activities[0].name);
    LONGS_EQUAL(1, plan.activities[0].to);
}

TEST(PlanParser, AnEmptyPlanIsLegal) {
    const ParseResult r = parse("plan nothing_to_do\nend\n");
    CHECK(r.error == PlanError::kOk);
    STRCMP_EQUAL("nothing_to_do", plan.name);
    LONGS_EQUAL(0, plan.activityCount);
    LONGS_EQUAL(1, plan.eventCount);
}

TEST(PlanParser, APlanOfOnlyItsEndMarkerIsLegalAndEmpty) {
    for (const char* text : {"end", "end\n", "  end  # done\n", "\n\n# only this\nend"}) {
        const ParseResult r = parse(text);
        CHECK_TEXT(r.error == PlanError::kOk, text);
        STRCMP_EQUAL("", plan.name);
        LONGS_EQUAL(0, plan.activityCount);
        LONGS_EQUAL(1, plan.eventCount);
    }
}

TEST(PlanParser, TextWithNoStatementIsRefusedAsEmpty) {
    for (const char* text : {"", "   ", "\n\n", "# only a comment\n", ";;;"}) {
        const ParseResult r = parse(text);
        CHECK_TEXT(r.error == PlanError::kEmptyText, text);
        LONGS_EQUAL(0, r.line);
    }
    // A null pointer reads as no text.
    CHECK(parsePlan(nullptr, 10, &plan).error == PlanError::kEmptyText);
}

TEST(PlanParser, TheShortFormSeparatesLinesWithSemicolons) {
    const ParseResult r = parse("plan short; event a; activity go drive start a [0, 600] at 5 5; end");
    CHECK_TEXT(r.error == PlanError::kOk, toString(r.error));
    LONGS_EQUAL(1, plan.activityCount);
    DOUBLES_EQUAL(5.0, plan.activities[0].y, 0.0);
    // Errors name the physical line: ';' separates statements, not lines.
    refused("plan short; event a;\nactivity go fly start a [0, 1]; end", PlanError::kUnknownActivityKind, 2, "fly");
}

TEST(PlanParser, ATruncatedPlanIsRefused) {
    const std::string full = kTwoTargets;
    refused(full.substr(0, full.size() - 4), PlanError::kNoEndMarker, 0, "");
    // Cut inside the end marker: "en" is no statement.
    refused(full.substr(0, full.size() - 2), PlanError::kUnknownKeyword, 17, "en");
    refused(std::string(kTwoTargets) + "event late\n", PlanError::kTextAfterEnd, 18, "event");
}

TEST(PlanParser, CyclesAreRefused) {
    refused("event a; event b; activity x wait a b [1, 2]; activity y wait b a [1, 2]; end", PlanError::kCycle, 0,
            "a");
    refused("event a; event b; activity x wait start a [0, 1]; activity y wait a b [0, 1]; "
            "constraint b a [0, 5]; end",
            PlanError::kCycle, 0, "a");
    refused("event a; activity x wait a a [1, 2]; end", PlanError::kSelfLoop, 1, "a");
    refused("event a; constraint a a [0, 1]; end", PlanError::kSelfLoop, 1, "a");
}

TEST(PlanParser, UnknownActivitiesEventsAndStatementsAreNamed) {
    refused("event a\nactivity x teleport start a [0, 1]\nend", PlanError::kUnknownActivityKind, 2, "teleport");
    refused("activity x wait start nowhere [0, 1]\nend", PlanError::kUnknownEvent, 1, "nowhere");
    refused("plan p\nfly away\nend", PlanError::kUnknownKeyword, 2, "fly");
    refused("event a when c1.x\nend", PlanError::kUnknownChoice, 1, "c1.x");
    refused("choice c1 p q\nevent a when c1.r\nend", PlanError::kUnknownOption, 2, "c1.r");
}

TEST(PlanParser, BoundsAreCheckedAndReadExactly) {
    refused("event a; activity x wait start a [5, 2]; end", PlanError::kBoundsReversed, 1, "2");
    refused("event a; constraint start a [10.5, 10.499]; end", PlanError::kBoundsReversed, 1, "10.499");
    refused("event a; activity x wait start a [-1, 2]; end", PlanError::kBadNumber, 1, "-1");
    refused("event a; activity x wait start a [inf, inf]; end", PlanError::kBadNumber, 1, "inf");
    refused("event a; activity x wait start a [nan, 2]; end", PlanError::kBadNumber, 1, "nan");
    refused("event a; activity x wait start a [1e3, 2e3]; end", PlanError::kBadNumber, 1, "1e3");
    refused("event a; activity x wait start a [0.0001, 2]; end", PlanError::kBadNumber, 1, "0.0001");
    refused("event a; activity x wait start a [0, 99999999999]; end", PlanError::kBadNumber, 1, "99999999999");
    refused("event a; activity x wait start a [., 1]; end", PlanError::kBadNumber, 1, ".");
    refused("event a; activity x wait start a 1, 2] cost 1; end", PlanError::kMissingField, 1, "1");
    const ParseResult r = parse("event a; activity x wait start a [0.001, 1000000]; end");
    CHECK(r.error == PlanError::kOk);
    LONGS_EQUAL(1, plan.activities[0].duration.lbMs);
    LONGS_EQUAL(1000000000, plan.activities[0].duration.ubMs);
}

TEST(PlanParser, NamesAreIdentifiersOrStringsAndUnique) {
    refused("event 9lives; end", PlanError::kBadName, 1, "9lives");
    refused("event cost; end", PlanError::kBadName, 1, "cost");
    refused("event a-b; end", PlanError::kBadName, 1, "a-b");
    refused("event abcdefghijklmnopqrstuvwxyz; end", PlanError::kBadName, 1, "abcdefghijklmnopqrstuvw");
    refused("event \"\"; end", PlanError::kBadName, 1, "");
    refused("event a; event a; end", PlanError::kDuplicateName, 1, "a");
    refused("event start; end", PlanError::kDuplicateName, 1, "start");
    refused("var grinder on off; end", PlanError::kDuplicateName, 1, "grinder");
    refused("choice c p p; end", PlanError::kDuplicateName, 1, "p");
    refused("choice c only; end", PlanError::kTooManyOptions, 1, "c");
    refused("choice c a b d e f; end", PlanError::kTooManyOptions, 1, "f");
    refused("plan a; plan b; end", PlanError::kMisplacedPlanLine, 1, "plan");
    refused("event a; plan b; end", PlanError::kMisplacedPlanLine, 1, "plan");
}

TEST(PlanParser, ConditionsNameKnownVariablesAndValues) {
    refused("event a; activity x wait start a [0, 1] ask grinder=broken; end", PlanError::kBadCondition, 1,
            "grinder=broken");
    refused("event a; activity x wait start a [0, 1] ask laser=ok; end", PlanError::kBadCondition, 1, "laser=ok");
    refused("event a; activity x wait start a [0, 1] tell grinder=ok; end", PlanError::kBadCondition, 1,
            "grinder=ok");
    refused("var v p q; event a; activity x wait start a [0, 1] tell v!=p; end", PlanError::kBadCondition, 1,
            "v!=p");
    refused("event a; activity x wait start a [0, 1] ask camera!ok; end", PlanError::kBadCondition, 1, "camera!ok");
    refused("event a; activity x wait start a [0, 1] ask =ok; end", PlanError::kBadCondition, 1, "=ok");
    refused("event a; activity x wait start a [0, 1] ask a=b ask c=d ask e=f ask g=h ask i=j; end",
            PlanError::kBadCondition, 1, "a=b");
    refused("event a; activity x wait start a [0, 1] ask camera=ok ask camera=ok ask camera=ok ask camera=ok "
            "ask camera=ok; end",
            PlanError::kTooManyConditions, 1, "camera=ok");
    const ParseResult r = parse("var v p q; event a; activity x wait start a [0, 1] ask v!=q tell v=p; end");
    CHECK(r.error == PlanError::kOk);
    CHECK(plan.activities[0].asks[0].planVariable && plan.activities[0].asks[0].negated);
    LONGS_EQUAL(1, plan.activities[0].asks[0].value);
}

TEST(PlanParser, ConditionsMayBeSpacedAroundTheirOperator) {
    // `grinder = ok`, `drive_ML != failed` (the issue's own spelling) read as the joined forms do.
    const ParseResult r = parse("var v p q; event a; activity x wait start a [0, 1] ask grinder = ok "
                                "ask drive_ML != failed ask v!=q tell v = p cost 2; end");
    CHECK_TEXT(r.error == PlanError::kOk, toString(r.error));
    const Activity& x = plan.activities[0];
    LONGS_EQUAL(3, x.askCount);
    LONGS_EQUAL(1, x.tellCount);
    CHECK(!x.asks[0].planVariable && !x.asks[0].negated);
    LONGS_EQUAL(static_cast<int>(Component::kGrinder), x.asks[0].variable);
    LONGS_EQUAL(static_cast<int>(ComponentState::kOk), x.asks[0].value);
    CHECK(!x.asks[1].planVariable && x.asks[1].negated);
    LONGS_EQUAL(static_cast<int>(Component::kDriveML), x.asks[1].variable);
    LONGS_EQUAL(static_cast<int>(ComponentState::kFailed), x.asks[1].value);
    CHECK(x.tells[0].planVariable && !x.tells[0].negated);
    LONGS_EQUAL(0, x.tells[0].value);
    DOUBLES_EQUAL(2.0, x.cost, 0.0);  // the field after the spaced Tell is still read
    // Spaced but still wrong: each refused at the token that is wrong.
    refused("var v p q; event a; activity x wait start a [0, 1] tell v != p; end", PlanError::kBadCondition, 1, "v");
    refused("event a; activity x wait start a [0, 1] ask grinder = broken; end", PlanError::kBadCondition, 1,
            "grinder");
    refused("event a; activity x wait start a [0, 1] ask grinder = ok=x; end", PlanError::kBadCondition, 1, "ok=x");
    refused("event a; activity x wait start a [0, 1] ask grinder =; end", PlanError::kBadCondition, 1, "grinder");
    refused("event a; activity x wait start a [0, 1] ask \"grinder\" = ok; end", PlanError::kBadCondition, 1,
            "grinder");
}

TEST(PlanParser, EachKindHasItsOwnFields) {
    refused("event a; activity x drive start a [0, 1]; end", PlanError::kMissingField, 1, "drive");
    refused("event a; activity x sample start a [0, 1]; end", PlanError::kMissingField, 1, "sample");
    refused("event a; activity x wait start a [0, 1] target 3; end", PlanError::kUnexpectedToken, 1, "target");
    refused("event a; activity x image start a [0, 1] at 1 2; end", PlanError::kUnexpectedToken, 1, "at");
    refused("event a; activity x image start a [0, 1] target 0; end", PlanError::kBadNumber, 1, "0");
    refused("event a; activity x image start a [0, 1] target 2.5; end", PlanError::kBadNumber, 1, "2.5");
    refused("event a; activity x drive start a [0, 1] at 1; end", PlanError::kUnexpectedToken, 1, "at");
    // A bare number after the point is no radius (a region is `within R`, below).
    refused("event a; activity x drive start a [0, 1] at 1 2 0.8; end", PlanError::kRadiusWithoutWithin, 1, "0.8");
    refused("event a; activity x wait start a [0, 1] cost 1 cost 2; end", PlanError::kUnexpectedToken, 1, "cost");
    refused("event a; activity x wait start a [0, 1] cost; end", PlanError::kMissingField, 1, "cost");
    refused("event a; activity x wait start a [0, 1] fast; end", PlanError::kUnexpectedToken, 1, "fast");
    refused("event a; activity x wait start a; end", PlanError::kMissingField, 1, "a");
    refused("end extra", PlanError::kUnexpectedToken, 1, "extra");
}

// `at X Y within R`: the drive is done anywhere within R m of the point, kept
// in mm (the text's 3 decimals); without `within`, the point (radius 0).
TEST(PlanParser, ADriveMayEndAnywhereWithinARegionOfItsPoint) {
    const ParseResult r = parse(
        "event a; event b; event c; event e\n"
        "activity d1 drive start a [0, 900] cost 10 at 10 0 within 3 ask drive_ML!=failed\n"
        "activity d2 drive a b [0, inf] at 20.5 -5.25 within 0.001\n"
        "activity d3 drive b c [0, inf] at 1 2 within 50.000\n"
        "activity d4 drive c e [0, inf] at 4 4 cost 2\n"
        "end\n");
    CHECK_TEXT(r.error == PlanError::kOk, toString(r.error));
    LONGS_EQUAL(4, plan.activityCount);
    const Activity& d1 = plan.activities[0];
    DOUBLES_EQUAL(10.0, d1.x, 0.0);
    DOUBLES_EQUAL(0.0, d1.y, 0.0);
    LONGS_EQUAL(3000, d1.radiusMm);
    DOUBLES_EQUAL(10.0, d1.cost, 0.0);  // fields before and after `within` are read as usual
    LONGS_EQUAL(1, d1.askCount);
    LONGS_EQUAL(1, plan.activities[1].radiusMm);
    DOUBLES_EQUAL(-5.25, plan.activities[1].y, 0.0);
    LONGS_EQUAL(50000, plan.activities[2].radiusMm);
    LONGS_EQUAL(0, plan.activities[3].radiusMm);  // no `within`: the point
    DOUBLES_EQUAL(2.0, plan.activities[3].cost, 0.0);

    // R must be a plain decimal in [0.001, 50] m with at most 3 decimals.
    const char* const head = "event a; activity x drive start a [0, 1] at 1 2 within ";
    refused(std::string(head) + "0; end", PlanError::kBadNumber, 1, "0");
    refused(std::string(head) + "0.0004; end", PlanError::kBadNumber, 1, "0.0004");
    refused(std::string(head) + "-3; end", PlanError::kBadNumber, 1, "-3");
    refused(std::string(head) + "50.001; end", PlanError::kBadNumber, 1, "50.001");
    refused(std::string(head) + "1e1; end", PlanError::kBadNumber, 1, "1e1");
    refused(std::string(head) + "nan; end", PlanError::kBadNumber, 1, "nan");
    refused(std::string(head) + "inf; end", PlanError::kBadNumber, 1, "inf");
    refused(std::string(head) + "three; end", PlanError::kBadNumber, 1, "three");
    refused(std::string(head) + "cost 3; end", PlanError::kBadNumber, 1, "cost");
    // `within` with no number, twice, before the point, or on another kind.
    refused("event a; activity x drive start a [0, 1] at 1 2 within; end", PlanError::kMissingField, 1, "within");
    refused("event a; activity x drive start a [0, 1] at 1 2 within 3 within 4; end", PlanError::kUnexpectedToken, 1,
            "within");
    refused("event a; activity x drive start a [0, 1] within 3 at 1 2; end", PlanError::kUnexpectedToken, 1,
            "within");
    refused("event a; activity x image start a [0, 1] target 1 within 3; end", PlanError::kUnexpectedToken, 1,
            "within");
    // A bare number after the point: refused with its own reason, whatever it looks like.
    refused("event a; activity x drive start a [0, 1] at 1 2 3; end", PlanError::kRadiusWithoutWithin, 1, "3");
    refused("event a; activity x drive start a [0, 1] at 1 2 -3; end", PlanError::kRadiusWithoutWithin, 1, "-3");
    refused("event a; activity x drive start a [0, 1] at 1 2 .5 cost 1; end", PlanError::kRadiusWithoutWithin, 1,
            ".5");
    // A keyword now: not a name.
    refused("event within; end", PlanError::kBadName, 1, "within");
}

TEST(PlanParser, GuardsMustImplyTheirEvents) {
    // An activity that exists without the option cannot use the option's event.
    refused("choice c p q; event a when c.p; activity x wait start a [0, 1]; end", PlanError::kBadGuard, 1, "a");
    refused("choice c p q; event a when c.p; activity x wait start a [0, 1] when c.q; end", PlanError::kBadGuard, 1,
            "a");
    // A nested choice's option implies its parent's.
    const ParseResult r = parse(
        "choice c p q\n"
        "choice d r s when c.p\n"
        "event a when c.p\n"
        "activity x wait start a [0, 1] when d.s\n"
        "end\n");
    CHECK_TEXT(r.error == PlanError::kOk, toString(r.error));
    LONGS_EQUAL(0, plan.choices[1].guard.choice);
    LONGS_EQUAL(1, plan.activities[0].guard.choice);
    LONGS_EQUAL(1, plan.activities[0].guard.option);
}

TEST(PlanParser, BadBytesAndUnterminatedStringsAreRefused) {
    refused(std::string("event a\x01; end"), PlanError::kBadCharacter, 1, "\x01");
    refused(std::string("event \"a\x7f\"; end"), PlanError::kBadCharacter, 1, "\x7f");
    refused(std::string("plan p\nevent a\xff\nend"), PlanError::kBadCharacter, 2, "\xff");
    refused(std::string("event a\0b; end", 14), PlanError::kBadCharacter, 1, std::string(1, '\0').c_str());
    refused("plan \"never closed\nend\n", PlanError::kUnterminatedString, 1, "never closed");
    refused("plan \"never closed", PlanError::kUnterminatedString, 1, "never closed");
}

TEST(PlanParser, LimitsRefuseRatherThanTruncate) {
    std::string many;
    for (std::size_t i = 0; i < kMaxEvents; ++i) {  // start plus 256 more: one too many
        many += "event e" + std::to_string(i) + "\n";
    }
    refused(many + "end\n", PlanError::kTooManyEvents, static_cast<std::uint32_t>(kMaxEvents), "e255");
    std::string chain;
    for (std::size_t i = 0; i < 200; ++i) {
        chain += "event e" + std::to_string(i) + "\n";
    }
    for (std::size_t i = 0; i <= kMaxActivities; ++i) {  // one too many
        chain += "activity a" + std::to_string(i) + " wait e" + std::to_string(i % 199) + " e" +
                 std::to_string(i % 199 + 1) + " [0, 1]\n";
    }
    CHECK(chain.size() < kMaxPlanText);
    refused(chain + "end\n", PlanError::kTooManyActivities, 200 + kMaxActivities + 1, "a256");
    refused(std::string(kMaxPlanText + 1, ' '), PlanError::kTooLong, 0, "");
    std::string longLine = "event a; activity x wait start a [0, 1]";
    for (int i = 0; i < 20; ++i) {
        longLine += " ask camera=ok";
    }
    refused(longLine + "; end", PlanError::kLineTooLong, 1, "ask");  // token 41
}

TEST(PlanParser, NoByteBeyondTheLengthIsRead) {
    // The buffer goes on past the length with a valid ending; the parser must
    // see only the first part (a plan without its end marker).
    const char text[] = "event a; activity x wait start a [0, 1]; end";
    const std::size_t cut = std::strlen("event a; activity x wait start a [0, 1]; ");
    const ParseResult r = parsePlan(text, cut, &plan);
    CHECK(r.error == PlanError::kNoEndMarker);
    // Cut inside a string: unterminated, not read on.
    const char quoted[] = "plan \"abc\"; end";
    CHECK(parsePlan(quoted, 8, &plan).error == PlanError::kUnterminatedString);
}

TEST(PlanParser, ParsingAllocatesNothing) {
    const std::string good = kTwoTargets;
    const std::string bad = "event a; activity x teleport start a [0, 1]; end";
    rse::test::AllocationWatch watch;
    for (int i = 0; i < 50; ++i) {
        parsePlan(good.data(), good.size(), &plan);
        parsePlan(bad.data(), bad.size(), &plan);
    }
    LONGS_EQUAL(0, watch.count());
}

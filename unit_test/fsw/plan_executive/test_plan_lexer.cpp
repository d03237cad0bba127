// The plan text's tokens (plan_lexer.hpp): statements cut at newlines and
// ';' (lines counted by newlines only), words, strings (with '#' and ';'
// inside) and brackets; comments to the end of a statement; a bad byte, an
// unterminated string and too many tokens stopping it with the token at
// fault; numbers as plain decimals within their range and decimals.
#include <cstdint>
#include <cstring>
#include <string>

#include "fsw/plan_executive/plan_lexer.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::plan_executive;
using namespace rse::plan_executive::plan_text;

namespace {

std::string text(const Token& t) { return std::string(t.text, t.length); }

Token word(const char* s) { return Token{s, std::strlen(s), false}; }

}  // namespace

TEST_GROUP(PlanLexer){};

TEST(PlanLexer, StatementsEndAtNewlinesAndSemicolonsAndLinesCountNewlinesOnly) {
    const std::string t = "plan p; event \"a b;#c\" # comment; not a statement\nactivity x [1, inf]";
    PlanLexer lexer(t.data(), t.size());
    CHECK_TRUE(lexer.next());
    LONGS_EQUAL(2, lexer.count());
    STRCMP_EQUAL("plan", text(lexer.tokens()[0]).c_str());
    LONGS_EQUAL(1, lexer.line());
    CHECK_TRUE(lexer.next());
    LONGS_EQUAL(2, lexer.count());
    CHECK_TRUE(lexer.tokens()[1].quoted);
    STRCMP_EQUAL("a b;#c", text(lexer.tokens()[1]).c_str());
    CHECK_TRUE(lexer.next());  // what followed the comment's ';': a statement of its own
    LONGS_EQUAL(3, lexer.count());
    LONGS_EQUAL(1, lexer.line());
    CHECK_TRUE(lexer.next());
    LONGS_EQUAL(2, lexer.line());
    LONGS_EQUAL(7, lexer.count());  // activity x [ 1 , inf ]
    STRCMP_EQUAL("[", text(lexer.tokens()[2]).c_str());
    STRCMP_EQUAL(",", text(lexer.tokens()[4]).c_str());
    STRCMP_EQUAL("]", text(lexer.tokens()[6]).c_str());
    CHECK_FALSE(lexer.next());
    CHECK(lexer.error() == PlanError::kOk);
    LONGS_EQUAL(2, lexer.line());  // the last statement's, still
}

TEST(PlanLexer, ABadByteAnUnterminatedStringOrTooManyTokensStopIt) {
    const std::string bad = "event a\x01";
    PlanLexer a(bad.data(), bad.size());
    CHECK_FALSE(a.next());
    CHECK(a.error() == PlanError::kBadCharacter);
    STRCMP_EQUAL("\x01", text(a.errorToken()).c_str());
    const std::string open = "ok\nevent \"abc\nend";
    PlanLexer b(open.data(), open.size());
    CHECK_TRUE(b.next());
    CHECK_FALSE(b.next());
    CHECK(b.error() == PlanError::kUnterminatedString);
    STRCMP_EQUAL("abc", text(b.errorToken()).c_str());
    LONGS_EQUAL(2, b.line());
    CHECK_FALSE(b.next());  // stopped
    std::string many;
    for (std::size_t i = 0; i <= kMaxLineTokens; ++i) {
        many += "w ";
    }
    PlanLexer c(many.data(), many.size());
    CHECK_FALSE(c.next());
    CHECK(c.error() == PlanError::kLineTooLong);
}

TEST(PlanLexer, KeywordsAndNamesAndNumbers) {
    CHECK_TRUE(isKeyword(word("within")));
    CHECK_FALSE(isKeyword(word("drive1")));
    CHECK_FALSE(isKeyword(Token{"end", 3, true}));  // a string is never a keyword
    CHECK_TRUE(equalsName(Token{"end", 3, true}, "end"));
    CHECK_TRUE(looksNumeric(word("-3")));
    CHECK_FALSE(looksNumeric(word("x3")));
    double v = 0.0;
    CHECK_TRUE(readDecimal(word("-12.25"), 2, -100.0, 100.0, &v));
    DOUBLES_EQUAL(-12.25, v, 0.0);
    CHECK_FALSE(readDecimal(word("12.255"), 2, -100.0, 100.0, &v));  // too many decimals
    CHECK_FALSE(readDecimal(word("1e3"), 3, 0.0, 1e6, &v));           // no exponent
    CHECK_FALSE(readDecimal(word("nan"), 3, 0.0, 1e6, &v));
    CHECK_FALSE(readDecimal(word("101"), 0, 0.0, 100.0, &v));         // out of range
    CHECK_FALSE(readDecimal(word("."), 3, 0.0, 1.0, &v));
    std::int32_t ms = 0;
    CHECK_TRUE(readMilliseconds(word("1.001"), &ms));
    LONGS_EQUAL(1001, ms);
    CHECK_FALSE(readMilliseconds(word("-1"), &ms));
    CHECK_FALSE(readMilliseconds(word("inf"), &ms));
}

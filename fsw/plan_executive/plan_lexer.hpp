// The plan text's tokens (docs/plan_executive.md "Plan text"): the lexer
// that cuts the text into statements of tokens, and the number readers.
// Internal to the parser (plan_parser.hpp is the interface).
//
// A statement ends at a newline or a ';' (the short form's separator; the
// line count goes by newlines only). '#' starts a comment to the end of the
// statement, except inside a "..." string, where '#' and ';' are text. A
// token is a string (its text without the quotes), one of '[' ']' ',', or a
// word (printable ASCII but '#', '"', '[', ']', ',' and ';'). A control or
// non-ASCII byte (outside or inside a string), a string not closed on its
// line, or more than kMaxLineTokens tokens in a statement is an error: the
// lexer stops there. Numbers are plain decimals read digit by digit (no
// strtod: no locale, no overflow, no "nan" or "inf" spellings).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/plan_executive/plan_parser.hpp"

namespace rse::plan_executive::plan_text {

// The longest statement (a drive with cost, `at X Y within R`, four asks, two
// tells and a guard) has 31 tokens; a line with more is refused rather than cut.
constexpr std::size_t kMaxLineTokens = 40;

struct Token {
    const char* text = nullptr;  // into the plan text (a string's: after its opening quote)
    std::size_t length = 0;
    bool quoted = false;
};

// An unquoted token that is this word (a keyword, an operator).
bool equals(const Token& t, const char* word);
// A token, quoted or not, that is this name.
bool equalsName(const Token& t, const char* name);
// A statement or field keyword (never a name).
bool isKeyword(const Token& t);
// A token that can only be meant as a number (names start with a letter or '_').
bool looksNumeric(const Token& t);

class PlanLexer {
public:
    PlanLexer(const char* text, std::size_t length) : text_(text), length_(length) {}

    // The next statement's tokens (none for an empty one). False at the end
    // of the text, or on an error (error() then says which, errorToken() where).
    bool next();
    const Token* tokens() const { return tokens_; }
    std::size_t count() const { return count_; }
    // The physical line (1-based) the statement last read starts on.
    std::uint32_t line() const { return line_; }
    PlanError error() const { return error_; }
    const Token& errorToken() const { return errorToken_; }

private:
    bool fail(PlanError e, const Token& at);
    // A "..." string from the quote at at_; false on an error.
    bool readString(Token* t);

    const char* text_;
    std::size_t length_;
    std::size_t at_ = 0;              // next byte to read
    std::uint32_t line_ = 0;          // the physical line the statement being read starts on
    std::uint32_t physicalLine_ = 1;  // lines end at '\n' only (';' separates statements)
    Token tokens_[kMaxLineTokens];
    std::size_t count_ = 0;
    PlanError error_ = PlanError::kOk;
    Token errorToken_{};
};

// A decimal without exponent: optional '-', digits, optional '.' and at most
// `decimals` digits; within [lo, hi]. False when it is not (kBadNumber).
bool readDecimal(const Token& t, int decimals, double lo, double hi, double* v);
// Seconds with at most 3 decimals in [0, kMaxBoundMs / 1000], as whole ms.
bool readMilliseconds(const Token& t, std::int32_t* ms);

}  // namespace rse::plan_executive::plan_text

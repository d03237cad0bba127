#include "fsw/plan_executive/plan_lexer.hpp"

#include <cstring>

namespace rse::plan_executive::plan_text {

namespace {

const char* const kKeywords[] = {"plan", "var",  "event", "choice", "activity", "constraint", "end",   "when",
                                 "cost", "at",   "within", "target", "ask",     "tell",       "inf"};

bool isWordChar(char c) {
    const auto u = static_cast<unsigned char>(c);
    return u > 0x20 && u < 0x7F && c != '#' && c != '"' && c != '[' && c != ']' && c != ',' && c != ';';
}

}  // namespace

bool equals(const Token& t, const char* word) {
    const std::size_t n = std::strlen(word);
    return !t.quoted && t.length == n && std::memcmp(t.text, word, n) == 0;
}

bool equalsName(const Token& t, const char* name) {
    const std::size_t n = std::strlen(name);
    return t.length == n && std::memcmp(t.text, name, n) == 0;
}

bool looksNumeric(const Token& t) {
    if (t.quoted || t.length == 0) {
        return false;
    }
    const char c = t.text[0];
    return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+';
}

bool isKeyword(const Token& t) {
    for (const char* k : kKeywords) {
        if (equals(t, k)) {
            return true;
        }
    }
    return false;
}

bool PlanLexer::fail(PlanError e, const Token& at) {
    error_ = e;
    errorToken_ = at;
    return false;
}

bool PlanLexer::readString(Token* t) {
    t->quoted = true;
    t->text = text_ + at_ + 1;
    std::size_t k = at_ + 1;
    while (k < length_ && text_[k] != '"') {
        const auto u = static_cast<unsigned char>(text_[k]);
        if (text_[k] == '\n') {
            break;
        }
        if (u < 0x20 || u >= 0x7F) {
            return fail(PlanError::kBadCharacter, Token{text_ + k, 1, false});
        }
        ++k;
    }
    t->length = k - at_ - 1;
    if (k >= length_ || text_[k] != '"') {
        return fail(PlanError::kUnterminatedString, *t);
    }
    at_ = k + 1;
    return true;
}

bool PlanLexer::next() {
    count_ = 0;
    if (error_ != PlanError::kOk || at_ >= length_) {
        return false;
    }
    line_ = physicalLine_;
    while (at_ < length_) {
        const char c = text_[at_];
        if (c == '\n' || c == ';') {
            physicalLine_ += c == '\n' ? 1U : 0U;
            ++at_;
            return true;
        }
        if (c == ' ' || c == '\t' || c == '\r') {
            ++at_;
            continue;
        }
        if (c == '#') {  // a comment runs to the end of the line (a newline or ';')
            while (at_ < length_ && text_[at_] != '\n' && text_[at_] != ';') {
                ++at_;
            }
            continue;
        }
        Token t;
        t.text = text_ + at_;
        if (c == '"') {
            if (!readString(&t)) {
                return false;
            }
        } else if (c == '[' || c == ']' || c == ',') {
            t.length = 1;
            ++at_;
        } else if (isWordChar(c)) {
            std::size_t k = at_;
            while (k < length_ && isWordChar(text_[k])) {
                ++k;
            }
            t.length = k - at_;
            at_ = k;
        } else {
            return fail(PlanError::kBadCharacter, Token{text_ + at_, 1, false});
        }
        if (count_ == kMaxLineTokens) {
            return fail(PlanError::kLineTooLong, t);
        }
        tokens_[count_++] = t;
    }
    return true;
}

bool readMilliseconds(const Token& t, std::int32_t* ms) {
    double s = 0.0;
    if (!readDecimal(t, 3, 0.0, static_cast<double>(kMaxBoundMs) / 1000.0, &s)) {
        return false;
    }
    // readDecimal() has read at most 3 fractional digits: s * 1000 is an
    // integer up to rounding, so round to nearest.
    *ms = static_cast<std::int32_t>(s * 1000.0 + 0.5);
    return true;
}

bool readDecimal(const Token& t, int decimals, double lo, double hi, double* v) {
    if (t.quoted || t.length == 0 || t.length > 20) {
        return false;
    }
    std::size_t i = 0;
    const bool negative = t.text[0] == '-';
    i += negative ? 1U : 0U;
    std::uint64_t whole = 0;
    std::size_t digits = 0;
    while (i < t.length && t.text[i] >= '0' && t.text[i] <= '9') {
        whole = whole * 10U + static_cast<std::uint64_t>(t.text[i] - '0');
        ++digits;
        ++i;
    }
    std::uint64_t fraction = 0;
    std::uint64_t scale = 1;
    if (i < t.length && t.text[i] == '.') {
        ++i;
        int fd = 0;
        while (i < t.length && t.text[i] >= '0' && t.text[i] <= '9') {
            if (fd == decimals) {
                return false;
            }
            fraction = fraction * 10U + static_cast<std::uint64_t>(t.text[i] - '0');
            scale *= 10U;
            ++fd;
            ++digits;
            ++i;
        }
    }
    if (i != t.length || digits == 0 || whole > 1000000000000ULL) {
        return false;
    }
    double value = static_cast<double>(whole) + static_cast<double>(fraction) / static_cast<double>(scale);
    value = negative ? -value : value;
    if (!(value >= lo && value <= hi)) {
        return false;
    }
    *v = value;
    return true;
}

}  // namespace rse::plan_executive::plan_text

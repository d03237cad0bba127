// The parse's run: statement by statement, each to its reader by its
// keyword; names and event references; numbers; and the whole plan's check
// (no cycle of precedence). The statements are read in plan_statements.cpp
// and plan_activity_line.cpp, guards and conditions in plan_conditions.cpp,
// tokens in plan_lexer.cpp.
#include "fsw/plan_executive/plan_parser.hpp"

#include <cstring>

#include "fsw/plan_executive/plan_text_parser.hpp"

namespace rse::plan_executive {

namespace plan_text {

bool Parser::fail(PlanError e, const Token* at) {
    if (result_.error == PlanError::kOk) {
        result_.error = e;
        result_.line = line_;
        if (at != nullptr && at->text != nullptr) {
            const std::size_t n = at->length < kNameSize - 1 ? at->length : kNameSize - 1;
            std::memcpy(result_.token, at->text, n);
            result_.token[n] = '\0';
        }
    }
    return false;
}

bool Parser::nextLine() {
    const bool read = lexer_.next();
    line_ = lexer_.line();
    tokens_ = lexer_.tokens();
    count_ = lexer_.count();
    if (lexer_.error() != PlanError::kOk) {
        return fail(lexer_.error(), &lexer_.errorToken());
    }
    return read;
}

void Parser::clearPlan() {
    tpn_->name[0] = '\0';
    tpn_->eventCount = 1;
    tpn_->events[0] = PlanEvent{};
    std::memcpy(tpn_->events[0].name, "start", 6);
    tpn_->activityCount = 0;
    tpn_->constraintCount = 0;
    tpn_->choiceCount = 0;
    tpn_->variableCount = 0;
}

ParseResult Parser::run() {
    clearPlan();
    if (length_ > kMaxPlanText) {
        fail(PlanError::kTooLong, nullptr);
    } else {
        while (result_.error == PlanError::kOk && nextLine()) {
            if (count_ > 0 && statement()) {
                sawStatement_ = true;
            }
        }
        if (result_.error == PlanError::kOk) {
            if (!sawStatement_) {
                line_ = 0;
                fail(PlanError::kEmptyText, nullptr);
            } else if (!sawEnd_) {
                line_ = 0;
                fail(PlanError::kNoEndMarker, nullptr);
            } else {
                checkCycles();
            }
        }
    }
    if (result_.error != PlanError::kOk) {  // nothing half-parsed is left to use
        clearPlan();
    }
    return result_;
}

bool Parser::statement() {
    const Token& k = tokens_[0];
    if (sawEnd_) {
        return fail(PlanError::kTextAfterEnd, &k);
    }
    if (equals(k, "plan")) {
        return planLine();
    }
    if (equals(k, "var")) {
        return varLine();
    }
    if (equals(k, "event")) {
        return eventLine();
    }
    if (equals(k, "choice")) {
        return choiceLine();
    }
    if (equals(k, "activity")) {
        return activityLine();
    }
    if (equals(k, "constraint")) {
        return constraintLine();
    }
    if (equals(k, "end")) {
        if (count_ > 1) {
            return fail(PlanError::kUnexpectedToken, &tokens_[1]);
        }
        sawEnd_ = true;
        return true;
    }
    return fail(PlanError::kUnknownKeyword, &k);
}

bool Parser::name(const Token& t, char* dst, bool allowQuoted) {
    if (t.length == 0 || t.length >= kNameSize) {
        return fail(PlanError::kBadName, &t);
    }
    if (t.quoted) {
        if (!allowQuoted) {
            return fail(PlanError::kBadName, &t);
        }
    } else {
        const char c0 = t.text[0];
        const bool letter = (c0 >= 'A' && c0 <= 'Z') || (c0 >= 'a' && c0 <= 'z') || c0 == '_';
        if (!letter || isKeyword(t)) {
            return fail(PlanError::kBadName, &t);
        }
        for (std::size_t i = 1; i < t.length; ++i) {
            const char c = t.text[i];
            const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
            if (!ok) {
                return fail(PlanError::kBadName, &t);
            }
        }
    }
    std::memcpy(dst, t.text, t.length);
    dst[t.length] = '\0';
    return true;
}

bool Parser::eventRef(const Token& t, std::uint16_t* index) {
    for (std::uint16_t i = 0; i < tpn_->eventCount; ++i) {
        if (equalsName(t, tpn_->events[i].name)) {
            *index = i;
            return true;
        }
    }
    return fail(PlanError::kUnknownEvent, &t);
}

bool Parser::decimal(const Token& t, int decimals, double lo, double hi, double* v) {
    return readDecimal(t, decimals, lo, hi, v) || fail(PlanError::kBadNumber, &t);
}

bool Parser::milliseconds(const Token& t, std::int32_t* ms) {
    return readMilliseconds(t, ms) || fail(PlanError::kBadNumber, &t);
}

// Kahn's algorithm over the precedence edges (activities and constraints, all
// options together): O(events x edges), no storage beyond two small arrays.
bool Parser::checkCycles() {
    std::uint16_t indegree[kMaxEvents] = {};
    bool done[kMaxEvents] = {};
    const std::size_t n = tpn_->eventCount;
    for (std::size_t i = 0; i < tpn_->activityCount; ++i) {
        ++indegree[tpn_->activities[i].to];
    }
    for (std::size_t i = 0; i < tpn_->constraintCount; ++i) {
        ++indegree[tpn_->constraints[i].to];
    }
    for (std::size_t round = 0; round < n; ++round) {
        std::size_t e = n;
        for (std::size_t i = 0; i < n; ++i) {
            if (!done[i] && indegree[i] == 0) {
                e = i;
                break;
            }
        }
        if (e == n) {
            for (std::size_t i = 0; i < n; ++i) {
                if (!done[i]) {
                    line_ = 0;
                    Token t{tpn_->events[i].name, std::strlen(tpn_->events[i].name), false};
                    return fail(PlanError::kCycle, &t);
                }
            }
        }
        done[e] = true;
        for (std::size_t i = 0; i < tpn_->activityCount; ++i) {
            if (tpn_->activities[i].from == e) {
                --indegree[tpn_->activities[i].to];
            }
        }
        for (std::size_t i = 0; i < tpn_->constraintCount; ++i) {
            if (tpn_->constraints[i].from == e) {
                --indegree[tpn_->constraints[i].to];
            }
        }
    }
    return true;
}

}  // namespace plan_text

const char* toString(PlanError e) {
    static const char* const kNames[kPlanErrorCount] = {
        "ok",
        "empty plan text",
        "plan text too long",
        "bad character",
        "unterminated string",
        "too many tokens on a line",
        "no end marker",
        "text after the end marker",
        "unknown statement",
        "plan line not first or repeated",
        "bad name",
        "duplicate name",
        "unknown event",
        "unknown choice",
        "unknown option",
        "unknown activity kind",
        "bad number",
        "lower bound above upper bound",
        "missing field",
        "unexpected token",
        "bad condition",
        "too many events",
        "too many activities",
        "too many constraints",
        "too many choices",
        "options per choice not 2..4",
        "too many plan variables or values",
        "too many asks or tells",
        "from and to are the same event",
        "event guarded by an option the element does not imply",
        "cycle of precedence",
        "number after a drive's point (a region is written within R)",
    };
    const auto i = static_cast<std::size_t>(e);
    return i < kPlanErrorCount ? kNames[i] : "?";
}

ParseResult parsePlan(const char* text, std::size_t length, Tpn* out) {
    if (out == nullptr) {
        ParseResult r;
        r.error = PlanError::kEmptyText;
        return r;
    }
    if (text == nullptr) {
        length = 0;
    }
    plan_text::Parser p(text, length, out);
    return p.run();
}

}  // namespace rse::plan_executive

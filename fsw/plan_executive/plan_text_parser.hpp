// One parse of a plan text (parsePlan, plan_parser.hpp, is the interface):
// the statements read from the lexer's tokens into the Tpn. Internal to the
// parser; its members are in the files of what they read:
//   plan_parser.cpp        the run, the statement keywords, names, the cycle check
//   plan_statements.cpp    plan, var, event, choice and constraint lines, bounds
//   plan_activity_line.cpp activity lines and their fields
//   plan_conditions.cpp    guards (`when C.O`) and conditions (Ask / Tell)
// Every reader consumes tokens of the current statement and returns false on
// the first problem, which fail() records (reason, line, token) once.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/plan_executive/plan_lexer.hpp"
#include "fsw/plan_executive/plan_parser.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive::plan_text {

constexpr double kMaxCost = 1000000.0;  // an activity's or an option's

class Parser {
public:
    Parser(const char* text, std::size_t length, Tpn* out) : lexer_(text, length), length_(length), tpn_(out) {}

    ParseResult run();

private:
    // The next statement's tokens into tokens_ / count_; false at the end of
    // the text or on the lexer's error (recorded).
    bool nextLine();
    bool fail(PlanError e, const Token* at);
    // The empty plan: no name, only the start event (event 0).
    void clearPlan();
    bool statement();
    bool planLine();
    bool varLine();
    bool eventLine();
    bool choiceLine();
    bool activityLine();
    bool activityHead(Activity* a);
    bool activityFields(Activity* a);
    bool driveAt(std::size_t* k, Activity* a);
    bool conditionField(std::size_t* k, Activity* a);
    bool constraintLine();
    bool checkCycles();

    // Field readers: each reads tokens of the current statement, false on an error.
    bool name(const Token& t, char* dst, bool allowQuoted);
    bool eventRef(const Token& t, std::uint16_t* index);
    // `[ LB , UB ]` at tokens k .. k + 4 (UB may be inf).
    bool boundsAt(std::size_t k, Bounds* b);
    bool guardAt(std::size_t k, Guard* g);
    bool guardImplies(const Guard& element, const Guard& event) const;
    bool guardValid(const Guard& element, std::uint16_t from, std::uint16_t to);
    // A condition at tokens_[k]: `VAR=VALUE` / `VAR!=VALUE` in one token, or
    // spaced, `VAR = VALUE` / `VAR != VALUE` in three; *used says how many.
    bool conditionAt(std::size_t k, bool tell, Condition* c, std::size_t* used);
    bool condition(const Token& at, const Token& variable, bool negated, const Token& value, bool tell,
                   Condition* c);
    bool decimal(const Token& t, int decimals, double lo, double hi, double* v);
    bool milliseconds(const Token& t, std::int32_t* ms);

    PlanLexer lexer_;
    std::size_t length_;
    std::uint32_t line_ = 0;  // the physical line the statement being read starts on
    Tpn* tpn_;
    const Token* tokens_ = nullptr;
    std::size_t count_ = 0;
    bool sawStatement_ = false;
    bool sawEnd_ = false;
    ParseResult result_;
};

}  // namespace rse::plan_executive::plan_text

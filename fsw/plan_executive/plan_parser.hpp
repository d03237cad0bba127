// The plan text format (docs/plan_executive.md "Plan text") to a Tpn.
//
// Plans arrive from the ground (a file uplinked in chunks, or the short form
// in one command, where ';' separates lines): hostile until checked. The parser
// reads at most kMaxPlanText bytes, never reads past the length it is given
// (no NUL is needed), allocates nothing, and either fills the whole Tpn or
// reports the first problem: a PlanError, the line it is on (1-based) and the
// offending token, so the operator sees what to mend. A plan larger than a
// limit of tpn.hpp is refused (kTooMany...), never truncated.
//
// What it checks beyond the grammar: names unique per kind and declared before
// use, bounds lb <= ub, each activity kind's own fields, conditions on known
// variables and values, guards (an element's events exist whenever it does),
// no activity or constraint from an event to itself, and no cycle of
// precedence (activities and constraints run forwards in time, so a cycle
// could only hold with every duration 0: always a mistake). Temporal
// consistency (upper bounds) is the Simple Temporal Network's check
// (stn.hpp), run for each selection of methods.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

enum class PlanError : std::uint8_t {
    kOk = 0,
    kEmptyText = 1,          // nothing but whitespace and comments
    kTooLong = 2,            // more than kMaxPlanText bytes
    kBadCharacter = 3,       // a control or non-ASCII byte outside a string
    kUnterminatedString = 4, // a '"' string not closed on its line
    kLineTooLong = 5,        // more tokens on a line than any statement has
    kNoEndMarker = 6,        // the text ends without "end": truncated?
    kTextAfterEnd = 7,       // a statement after "end"
    kUnknownKeyword = 8,     // a line that starts with no known statement
    kMisplacedPlanLine = 9,  // "plan" not first, or twice
    kBadName = 10,           // not an identifier, too long, or a reserved word
    kDuplicateName = 11,     // a second event / activity / choice / variable of that name
    kUnknownEvent = 12,
    kUnknownChoice = 13,     // in a guard "when C.O"
    kUnknownOption = 14,
    kUnknownActivityKind = 15,
    kBadNumber = 16,         // not a finite decimal in range
    kBoundsReversed = 17,    // lb > ub
    kMissingField = 18,      // a statement without a field it needs (which: the token)
    kUnexpectedToken = 19,   // a field the statement does not take, or given twice
    kBadCondition = 20,      // not VAR=VALUE / VAR!=VALUE, or an unknown variable or value; a Tell with !=
    kTooManyEvents = 21,
    kTooManyActivities = 22,
    kTooManyConstraints = 23,
    kTooManyChoices = 24,
    kTooManyOptions = 25,    // or fewer than 2
    kTooManyVariables = 26,  // or values (fewer than 1)
    kTooManyConditions = 27, // asks or tells on one activity
    kSelfLoop = 28,          // from == to
    kBadGuard = 29,          // an element's event is guarded by an option the element does not imply
    kCycle = 30,             // a cycle of precedence through the named event
    kRadiusWithoutWithin = 31, // a number after a drive's point: a region is `at X Y within R`
};
constexpr std::size_t kPlanErrorCount = 32;

const char* toString(PlanError e);

struct ParseResult {
    PlanError error = PlanError::kOk;
    std::uint32_t line = 0;   // 1-based line of the problem (0: the whole text)
    char token[kNameSize] = {};  // the offending token (truncated), or empty
};

// Parses text[0 .. length) into *out (cleared first). On an error *out holds
// an empty plan, so no half-parsed plan can be used by mistake.
ParseResult parsePlan(const char* text, std::size_t length, Tpn* out);

}  // namespace rse::plan_executive

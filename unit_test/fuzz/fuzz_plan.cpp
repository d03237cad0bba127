// libFuzzer target: the plan text parser (fsw/plan_executive/plan_parser.hpp),
// the onboard reader of every plan uplinked from the ground. An input is one
// plan text, exactly as `rse-ground` would send it (file or short form).
//
// Invariants (a violation is __builtin_trap(), which libFuzzer reports as a
// crash like any sanitizer finding):
//   - the verdict is a PlanError the parser can give, with a NUL-terminated token;
//   - a refused plan leaves nothing to use (no activity, choice, constraint or
//     variable; only the start event);
//   - an accepted plan is well formed: counts within the limits, every name
//     NUL-terminated, every activity and constraint between two distinct known
//     events with lb <= ub and finite lb, a drive's region within 50 m and
//     none on another kind, guards naming existing options,
//     conditions naming existing variables and values, no Tell with !=;
//   - parsing is deterministic: the same text gives the same verdict twice.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fsw/plan_executive/plan_parser.hpp"

using namespace rse::plan_executive;

namespace {

Tpn plan;
Tpn again;

void require(bool ok) {
    if (!ok) {
        __builtin_trap();
    }
}

bool terminated(const char* s) { return std::memchr(s, '\0', kNameSize) != nullptr; }

bool guardOk(const Tpn& p, const Guard& g) {
    return !g.guarded() || (g.choice < p.choiceCount && g.option < p.choices[g.choice].optionCount);
}

bool conditionOk(const Tpn& p, const Condition& c) {
    if (c.planVariable) {
        return c.variable < p.variableCount && c.value < p.variables[c.variable].valueCount;
    }
    return c.variable < kComponentCount && c.value < kComponentStateCount;
}

void checkAccepted(const Tpn& p) {
    require(p.eventCount >= 1 && p.eventCount <= kMaxEvents);
    require(p.activityCount <= kMaxActivities && p.constraintCount <= kMaxConstraints);
    require(p.choiceCount <= kMaxChoices && p.variableCount <= kMaxPlanVariables);
    require(terminated(p.name));
    for (std::size_t i = 0; i < p.eventCount; ++i) {
        require(terminated(p.events[i].name) && p.events[i].name[0] != '\0');
        require(guardOk(p, p.events[i].guard));
    }
    for (std::size_t i = 0; i < p.activityCount; ++i) {
        const Activity& a = p.activities[i];
        require(terminated(a.name));
        require(a.from < p.eventCount && a.to < p.eventCount && a.from != a.to);
        require(a.duration.lbMs >= 0 && a.duration.lbMs <= a.duration.ubMs && a.duration.lbMs <= kMaxBoundMs);
        require(static_cast<std::size_t>(a.kind) < kActivityKindCount);
        require(a.askCount <= kMaxAsks && a.tellCount <= kMaxTells);
        require(guardOk(p, a.guard));
        require(a.cost >= 0.0 && a.cost == a.cost);
        // A region only on a drive, and within the bus goal's limit (50 m, in mm).
        require(a.radiusMm <= 50000 && (a.kind == ActivityKind::kDrive || a.radiusMm == 0));
        for (std::size_t k = 0; k < a.askCount; ++k) {
            require(conditionOk(p, a.asks[k]));
        }
        for (std::size_t k = 0; k < a.tellCount; ++k) {
            require(conditionOk(p, a.tells[k]) && a.tells[k].planVariable && !a.tells[k].negated);
        }
    }
    for (std::size_t i = 0; i < p.constraintCount; ++i) {
        const TemporalConstraint& c = p.constraints[i];
        require(c.from < p.eventCount && c.to < p.eventCount && c.from != c.to);
        require(c.bounds.lbMs >= 0 && c.bounds.lbMs <= c.bounds.ubMs);
        require(guardOk(p, c.guard));
    }
    for (std::size_t i = 0; i < p.choiceCount; ++i) {
        require(terminated(p.choices[i].name));
        require(p.choices[i].optionCount >= 2 && p.choices[i].optionCount <= kMaxOptions);
        // A choice nests only under an earlier one.
        require(!p.choices[i].guard.guarded() || p.choices[i].guard.choice < i);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > kMaxPlanText + 16) {
        return -1;  // not added to the corpus (the parser refuses it at once)
    }
    const char* text = reinterpret_cast<const char*>(data);
    const ParseResult r = parsePlan(text, size, &plan);
    require(static_cast<std::size_t>(r.error) < kPlanErrorCount);
    require(terminated(r.token));
    if (r.error == PlanError::kOk) {
        checkAccepted(plan);
    } else {
        require(plan.activityCount == 0 && plan.constraintCount == 0 && plan.choiceCount == 0 &&
                plan.variableCount == 0 && plan.eventCount == 1 && plan.name[0] == '\0');
    }
    const ParseResult r2 = parsePlan(text, size, &again);
    require(r2.error == r.error && r2.line == r.line && std::strcmp(r2.token, r.token) == 0);
    require(again.activityCount == plan.activityCount && again.eventCount == plan.eventCount);
    return 0;
}

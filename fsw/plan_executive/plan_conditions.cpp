// Guards and conditions (plan_text_parser.hpp): `when C.O` (an element that
// exists only when option O of choice C is chosen) and whether an element's
// guard implies its events' (each of its events exists whenever it does);
// Ask and Tell conditions on a component or a plan variable, in one token
// (`grinder=ok`, `drive_ML!=failed`) or three (`grinder = ok`).
#include <cstring>

#include "fsw/plan_executive/plan_text_parser.hpp"

namespace rse::plan_executive::plan_text {

// "when C.O" at tokens k, k + 1 (k < count_ and tokens_[k] is "when").
bool Parser::guardAt(std::size_t k, Guard* g) {
    if (k + 1 >= count_) {
        return fail(PlanError::kMissingField, &tokens_[k]);
    }
    const Token& t = tokens_[k + 1];
    std::size_t dot = 0;
    while (dot < t.length && t.text[dot] != '.') {
        ++dot;
    }
    if (t.quoted || dot == 0 || dot + 1 >= t.length) {
        return fail(PlanError::kUnknownChoice, &t);
    }
    const Token choice{t.text, dot, false};
    const Token option{t.text + dot + 1, t.length - dot - 1, false};
    for (std::uint8_t c = 0; c < tpn_->choiceCount; ++c) {
        if (equalsName(choice, tpn_->choices[c].name)) {
            for (std::uint8_t o = 0; o < tpn_->choices[c].optionCount; ++o) {
                if (equalsName(option, tpn_->choices[c].options[o].name)) {
                    g->choice = c;
                    g->option = o;
                    return true;
                }
            }
            return fail(PlanError::kUnknownOption, &t);
        }
    }
    return fail(PlanError::kUnknownChoice, &t);
}

// True when every selection in which `element` holds also has `event`: the
// event is unguarded, or guarded by the element's own option or by an option
// its choice is nested under. Choices nest only under earlier choices, so the
// walk up is bounded by the choice count.
bool Parser::guardImplies(const Guard& element, const Guard& event) const {
    if (!event.guarded()) {
        return true;
    }
    Guard g = element;
    for (std::size_t depth = 0; g.guarded() && depth <= kMaxChoices; ++depth) {
        if (g.choice == event.choice && g.option == event.option) {
            return true;
        }
        g = tpn_->choices[g.choice].guard;
    }
    return false;
}

bool Parser::guardValid(const Guard& element, std::uint16_t from, std::uint16_t to) {
    if (!guardImplies(element, tpn_->events[from].guard)) {
        Token t{tpn_->events[from].name, std::strlen(tpn_->events[from].name), false};
        return fail(PlanError::kBadGuard, &t);
    }
    if (!guardImplies(element, tpn_->events[to].guard)) {
        Token t{tpn_->events[to].name, std::strlen(tpn_->events[to].name), false};
        return fail(PlanError::kBadGuard, &t);
    }
    return true;
}

bool Parser::conditionAt(std::size_t k, bool tell, Condition* c, std::size_t* used) {
    const Token& t = tokens_[k];
    const bool spaced = k + 2 < count_ && (equals(tokens_[k + 1], "=") || equals(tokens_[k + 1], "!="));
    if (spaced) {
        const Token& value = tokens_[k + 2];
        for (std::size_t i = 0; i < t.length; ++i) {
            if (t.text[i] == '=' || t.text[i] == '!') {
                return fail(PlanError::kBadCondition, &t);
            }
        }
        for (std::size_t i = 0; i < value.length; ++i) {
            if (value.text[i] == '=' || value.text[i] == '!') {
                return fail(PlanError::kBadCondition, &value);
            }
        }
        if (t.quoted || value.quoted) {
            return fail(PlanError::kBadCondition, t.quoted ? &t : &value);
        }
        *used = 3;
        return condition(t, t, equals(tokens_[k + 1], "!="), value, tell, c);
    }
    std::size_t op = 0;
    while (op < t.length && t.text[op] != '=' && t.text[op] != '!') {
        ++op;
    }
    if (t.quoted || op == 0 || op >= t.length) {
        return fail(PlanError::kBadCondition, &t);
    }
    const bool negated = t.text[op] == '!';
    if (negated && (op + 1 >= t.length || t.text[op + 1] != '=')) {
        return fail(PlanError::kBadCondition, &t);
    }
    const std::size_t valueAt = op + (negated ? 2U : 1U);
    if (valueAt >= t.length) {
        return fail(PlanError::kBadCondition, &t);
    }
    *used = 1;
    return condition(t, Token{t.text, op, false}, negated, Token{t.text + valueAt, t.length - valueAt, false}, tell,
                     c);
}

bool Parser::condition(const Token& t, const Token& variable, bool negated, const Token& value, bool tell,
                       Condition* c) {
    if (tell && negated) {  // a Tell sets a value; "not this value" sets none
        return fail(PlanError::kBadCondition, &t);
    }
    *c = Condition{};
    c->negated = negated;
    for (std::uint8_t k = 0; k < kComponentCount; ++k) {
        if (equalsName(variable, toString(static_cast<Component>(k)))) {
            if (tell) {  // a component's state is mode estimation's to tell
                return fail(PlanError::kBadCondition, &t);
            }
            for (std::uint8_t s = 0; s < kComponentStateCount; ++s) {
                if (equalsName(value, toString(static_cast<ComponentState>(s)))) {
                    c->variable = k;
                    c->value = s;
                    return true;
                }
            }
            return fail(PlanError::kBadCondition, &t);
        }
    }
    for (std::uint8_t k = 0; k < tpn_->variableCount; ++k) {
        const PlanVariable& pv = tpn_->variables[k];
        if (equalsName(variable, pv.name)) {
            for (std::uint8_t s = 0; s < pv.valueCount; ++s) {
                if (equalsName(value, pv.values[s])) {
                    c->planVariable = true;
                    c->variable = k;
                    c->value = s;
                    return true;
                }
            }
            return fail(PlanError::kBadCondition, &t);
        }
    }
    return fail(PlanError::kBadCondition, &t);
}

}  // namespace rse::plan_executive::plan_text

// The plan text's statements but activities (plan_text_parser.hpp): `plan
// NAME`, `var NAME VALUE...`, `event NAME [when C.O]`, `choice NAME OPTION
// [cost C]... [when C.O]`, `constraint FROM TO [LB, UB] [when C.O]`, and the
// bounds `[LB, UB]` an activity shares.
#include <cstring>

#include "fsw/plan_executive/plan_text_parser.hpp"

namespace rse::plan_executive::plan_text {

bool Parser::planLine() {
    if (sawStatement_ || tpn_->name[0] != '\0') {
        return fail(PlanError::kMisplacedPlanLine, &tokens_[0]);
    }
    if (count_ < 2) {
        return fail(PlanError::kMissingField, &tokens_[0]);
    }
    if (count_ > 2) {
        return fail(PlanError::kUnexpectedToken, &tokens_[2]);
    }
    return name(tokens_[1], tpn_->name, true);
}

bool Parser::varLine() {
    if (count_ < 3) {
        return fail(PlanError::kMissingField, &tokens_[count_ - 1]);
    }
    if (tpn_->variableCount == kMaxPlanVariables) {
        return fail(PlanError::kTooManyVariables, &tokens_[1]);
    }
    PlanVariable& v = tpn_->variables[tpn_->variableCount];
    v = PlanVariable{};
    if (!name(tokens_[1], v.name, false)) {
        return false;
    }
    for (std::uint8_t c = 0; c < kComponentCount; ++c) {
        if (equalsName(tokens_[1], toString(static_cast<Component>(c)))) {
            return fail(PlanError::kDuplicateName, &tokens_[1]);
        }
    }
    for (std::size_t i = 0; i < tpn_->variableCount; ++i) {
        if (equalsName(tokens_[1], tpn_->variables[i].name)) {
            return fail(PlanError::kDuplicateName, &tokens_[1]);
        }
    }
    for (std::size_t k = 2; k < count_; ++k) {
        if (v.valueCount == kMaxVariableValues) {
            return fail(PlanError::kTooManyVariables, &tokens_[k]);
        }
        char* dst = v.values[v.valueCount];
        if (!name(tokens_[k], dst, false)) {
            return false;
        }
        for (std::size_t i = 0; i < v.valueCount; ++i) {
            if (std::strcmp(v.values[i], dst) == 0) {
                return fail(PlanError::kDuplicateName, &tokens_[k]);
            }
        }
        ++v.valueCount;
    }
    ++tpn_->variableCount;
    return true;
}

bool Parser::eventLine() {
    if (count_ < 2) {
        return fail(PlanError::kMissingField, &tokens_[0]);
    }
    if (tpn_->eventCount == kMaxEvents) {
        return fail(PlanError::kTooManyEvents, &tokens_[1]);
    }
    PlanEvent& e = tpn_->events[tpn_->eventCount];
    e = PlanEvent{};
    if (!name(tokens_[1], e.name, true)) {
        return false;
    }
    for (std::uint16_t i = 0; i < tpn_->eventCount; ++i) {
        if (std::strcmp(tpn_->events[i].name, e.name) == 0) {
            return fail(PlanError::kDuplicateName, &tokens_[1]);
        }
    }
    if (count_ > 2) {
        if (!equals(tokens_[2], "when")) {
            return fail(PlanError::kUnexpectedToken, &tokens_[2]);
        }
        if (!guardAt(2, &e.guard)) {
            return false;
        }
        if (count_ > 4) {
            return fail(PlanError::kUnexpectedToken, &tokens_[4]);
        }
    }
    ++tpn_->eventCount;
    return true;
}

bool Parser::choiceLine() {
    if (count_ < 2) {
        return fail(PlanError::kMissingField, &tokens_[0]);
    }
    if (tpn_->choiceCount == kMaxChoices) {
        return fail(PlanError::kTooManyChoices, &tokens_[1]);
    }
    Choice& c = tpn_->choices[tpn_->choiceCount];
    c = Choice{};
    if (!name(tokens_[1], c.name, false)) {
        return false;
    }
    for (std::uint8_t i = 0; i < tpn_->choiceCount; ++i) {
        if (std::strcmp(tpn_->choices[i].name, c.name) == 0) {
            return fail(PlanError::kDuplicateName, &tokens_[1]);
        }
    }
    std::size_t k = 2;
    while (k < count_) {
        const Token& t = tokens_[k];
        if (equals(t, "cost")) {
            if (c.optionCount == 0 || k + 1 >= count_) {
                return fail(PlanError::kMissingField, &t);
            }
            if (!decimal(tokens_[k + 1], 6, 0.0, kMaxCost, &c.options[c.optionCount - 1].cost)) {
                return false;
            }
            k += 2;
        } else if (equals(t, "when")) {
            if (!guardAt(k, &c.guard)) {
                return false;
            }
            k += 2;
            if (k < count_) {
                return fail(PlanError::kUnexpectedToken, &tokens_[k]);
            }
        } else {
            if (c.optionCount == kMaxOptions) {
                return fail(PlanError::kTooManyOptions, &t);
            }
            ChoiceOption& o = c.options[c.optionCount];
            o = ChoiceOption{};
            if (!name(t, o.name, false)) {
                return false;
            }
            for (std::uint8_t i = 0; i < c.optionCount; ++i) {
                if (std::strcmp(c.options[i].name, o.name) == 0) {
                    return fail(PlanError::kDuplicateName, &t);
                }
            }
            ++c.optionCount;
            ++k;
        }
    }
    if (c.optionCount < 2) {
        return fail(PlanError::kTooManyOptions, &tokens_[1]);
    }
    ++tpn_->choiceCount;
    return true;
}

bool Parser::constraintLine() {
    // constraint FROM TO [ LB , UB ] [when C.O]
    if (count_ < 8) {
        return fail(PlanError::kMissingField, &tokens_[count_ - 1]);
    }
    if (tpn_->constraintCount == kMaxConstraints) {
        return fail(PlanError::kTooManyConstraints, &tokens_[1]);
    }
    TemporalConstraint& c = tpn_->constraints[tpn_->constraintCount];
    c = TemporalConstraint{};
    if (!eventRef(tokens_[1], &c.from) || !eventRef(tokens_[2], &c.to)) {
        return false;
    }
    if (c.from == c.to) {
        return fail(PlanError::kSelfLoop, &tokens_[2]);
    }
    if (!boundsAt(3, &c.bounds)) {
        return false;
    }
    if (count_ > 8) {
        if (!equals(tokens_[8], "when")) {
            return fail(PlanError::kUnexpectedToken, &tokens_[8]);
        }
        if (!guardAt(8, &c.guard)) {
            return false;
        }
        if (count_ > 10) {
            return fail(PlanError::kUnexpectedToken, &tokens_[10]);
        }
    }
    if (!guardValid(c.guard, c.from, c.to)) {
        return false;
    }
    ++tpn_->constraintCount;
    return true;
}

// `[ LB , UB ]` at tokens k .. k + 4: seconds, 0 <= LB <= UB, UB may be inf.
bool Parser::boundsAt(std::size_t k, Bounds* b) {
    if (!equals(tokens_[k], "[") || !equals(tokens_[k + 2], ",") || !equals(tokens_[k + 4], "]")) {
        return fail(PlanError::kMissingField, &tokens_[k]);
    }
    if (!milliseconds(tokens_[k + 1], &b->lbMs)) {
        return false;
    }
    if (equals(tokens_[k + 3], "inf")) {
        b->ubMs = kInfiniteMs;
    } else if (!milliseconds(tokens_[k + 3], &b->ubMs)) {
        return false;
    }
    if (b->lbMs > b->ubMs) {
        return fail(PlanError::kBoundsReversed, &tokens_[k + 3]);
    }
    return true;
}

}  // namespace rse::plan_executive::plan_text

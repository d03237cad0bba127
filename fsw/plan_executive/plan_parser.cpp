#include "fsw/plan_executive/plan_parser.hpp"

#include <cstring>

#include "fsw/msg/goal_msgs.hpp"

namespace rse::plan_executive {

namespace {

// The longest statement (a drive with cost, `at X Y within R`, four asks, two
// tells and a guard) has 31 tokens; a line with more is refused rather than cut.
constexpr std::size_t kMaxTokens = 40;
constexpr double kMaxCoordinateM = 100000.0;
constexpr double kMaxCost = 1000000.0;
// A drive's region, `within R`: at least 1 mm (the text's resolution; R = 0
// would be the point, written without `within`), at most the bus goal's limit.
constexpr double kMinRadiusM = 0.001;
constexpr double kMaxRadiusM = static_cast<double>(msg::kMaxGoalRadiusM);
static_assert(kMaxRadiusM * 1000.0 <= 65535.0, "Activity::radiusMm holds the largest radius in mm");

struct Token {
    const char* text = nullptr;
    std::size_t length = 0;
    bool quoted = false;
};

bool isWordChar(char c) {
    const auto u = static_cast<unsigned char>(c);
    return u > 0x20 && u < 0x7F && c != '#' && c != '"' && c != '[' && c != ']' && c != ',' && c != ';';
}

bool equals(const Token& t, const char* word) {
    const std::size_t n = std::strlen(word);
    return !t.quoted && t.length == n && std::memcmp(t.text, word, n) == 0;
}

bool equalsName(const Token& t, const char* name) {
    const std::size_t n = std::strlen(name);
    return t.length == n && std::memcmp(t.text, name, n) == 0;
}

const char* const kKeywords[] = {"plan", "var",  "event", "choice", "activity", "constraint", "end",   "when",
                                 "cost", "at",   "within", "target", "ask",     "tell",       "inf"};

// A token that can only be meant as a number (names start with a letter or '_').
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


// One parse: the text, the line being read and its tokens, and the result.
class Parser {
public:
    Parser(const char* text, std::size_t length, Tpn* out) : text_(text), length_(length), tpn_(out) {}

    ParseResult run();

private:
    // Fills tokens_ with the next line's tokens; false at the end of the text
    // or on an error (result_ set).
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
    bool constraintLine();
    bool checkCycles();

    // Field readers: each consumes tokens from pos_, false on an error.
    bool name(const Token& t, char* dst, bool allowQuoted);
    bool eventRef(const Token& t, std::uint16_t* index);
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

    const char* text_;
    std::size_t length_;
    std::size_t at_ = 0;  // next byte to read
    std::uint32_t line_ = 0;          // the physical line the statement being read starts on
    std::uint32_t physicalLine_ = 1;  // lines end at '\n' only (';' separates statements)
    Tpn* tpn_;
    Token tokens_[kMaxTokens];
    std::size_t count_ = 0;
    bool sawStatement_ = false;
    bool sawEnd_ = false;
    ParseResult result_;
};

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
    count_ = 0;
    if (at_ >= length_) {
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
            t.quoted = true;
            t.text = text_ + at_ + 1;
            std::size_t k = at_ + 1;
            while (k < length_ && text_[k] != '"') {
                const auto u = static_cast<unsigned char>(text_[k]);
                if (text_[k] == '\n') {
                    break;
                }
                if (u < 0x20 || u >= 0x7F) {
                    Token bad{text_ + k, 1, false};
                    return fail(PlanError::kBadCharacter, &bad);
                }
                ++k;
            }
            t.length = k - at_ - 1;
            if (k >= length_ || text_[k] != '"') {
                return fail(PlanError::kUnterminatedString, &t);
            }
            at_ = k + 1;
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
            Token bad{text_ + at_, 1, false};
            return fail(PlanError::kBadCharacter, &bad);
        }
        if (count_ == kMaxTokens) {
            return fail(PlanError::kLineTooLong, &t);
        }
        tokens_[count_++] = t;
    }
    return true;
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

bool Parser::eventRef(const Token& t, std::uint16_t* index) {
    for (std::uint16_t i = 0; i < tpn_->eventCount; ++i) {
        if (equalsName(t, tpn_->events[i].name)) {
            *index = i;
            return true;
        }
    }
    return fail(PlanError::kUnknownEvent, &t);
}

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

bool Parser::milliseconds(const Token& t, std::int32_t* ms) {
    double s = 0.0;
    if (!decimal(t, 3, 0.0, static_cast<double>(kMaxBoundMs) / 1000.0, &s)) {
        return false;
    }
    // decimal() has read at most 3 fractional digits: s * 1000 is an integer
    // up to rounding, so round to nearest.
    *ms = static_cast<std::int32_t>(s * 1000.0 + 0.5);
    return true;
}

// A decimal without exponent: optional '-', digits, optional '.' and at most
// `decimals` digits; within [lo, hi]. Read digit by digit (no strtod: no
// locale, no overflow, no "nan" or "inf" spellings).
bool Parser::decimal(const Token& t, int decimals, double lo, double hi, double* v) {
    if (t.quoted || t.length == 0 || t.length > 20) {
        return fail(PlanError::kBadNumber, &t);
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
                return fail(PlanError::kBadNumber, &t);
            }
            fraction = fraction * 10U + static_cast<std::uint64_t>(t.text[i] - '0');
            scale *= 10U;
            ++fd;
            ++digits;
            ++i;
        }
    }
    if (i != t.length || digits == 0 || whole > 1000000000000ULL) {
        return fail(PlanError::kBadNumber, &t);
    }
    double value = static_cast<double>(whole) + static_cast<double>(fraction) / static_cast<double>(scale);
    value = negative ? -value : value;
    if (!(value >= lo && value <= hi)) {
        return fail(PlanError::kBadNumber, &t);
    }
    *v = value;
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

bool Parser::activityLine() {
    // activity NAME KIND FROM TO [ LB , UB ] fields...
    if (count_ < 10) {
        return fail(PlanError::kMissingField, &tokens_[count_ - 1]);
    }
    if (tpn_->activityCount == kMaxActivities) {
        return fail(PlanError::kTooManyActivities, &tokens_[1]);
    }
    Activity& a = tpn_->activities[tpn_->activityCount];
    a = Activity{};
    if (!name(tokens_[1], a.name, true)) {
        return false;
    }
    for (std::uint16_t i = 0; i < tpn_->activityCount; ++i) {
        if (std::strcmp(tpn_->activities[i].name, a.name) == 0) {
            return fail(PlanError::kDuplicateName, &tokens_[1]);
        }
    }
    bool known = false;
    for (std::uint8_t k = 0; k < kActivityKindCount; ++k) {
        if (equals(tokens_[2], toString(static_cast<ActivityKind>(k)))) {
            a.kind = static_cast<ActivityKind>(k);
            known = true;
        }
    }
    if (!known) {
        return fail(PlanError::kUnknownActivityKind, &tokens_[2]);
    }
    if (!eventRef(tokens_[3], &a.from) || !eventRef(tokens_[4], &a.to)) {
        return false;
    }
    if (a.from == a.to) {
        return fail(PlanError::kSelfLoop, &tokens_[4]);
    }
    if (!equals(tokens_[5], "[") || !equals(tokens_[7], ",") || !equals(tokens_[9], "]")) {
        return fail(PlanError::kMissingField, &tokens_[5]);
    }
    if (!milliseconds(tokens_[6], &a.duration.lbMs)) {
        return false;
    }
    if (equals(tokens_[8], "inf")) {
        a.duration.ubMs = kInfiniteMs;
    } else if (!milliseconds(tokens_[8], &a.duration.ubMs)) {
        return false;
    }
    if (a.duration.lbMs > a.duration.ubMs) {
        return fail(PlanError::kBoundsReversed, &tokens_[8]);
    }
    bool sawCost = false, sawAt = false, sawTarget = false, sawWhen = false;
    std::size_t k = 10;
    while (k < count_) {
        const Token& t = tokens_[k];
        const bool hasNext = k + 1 < count_;
        if (equals(t, "cost") && !sawCost && hasNext) {
            if (!decimal(tokens_[k + 1], 6, 0.0, kMaxCost, &a.cost)) {
                return false;
            }
            sawCost = true;
            k += 2;
        } else if (equals(t, "at") && !sawAt && a.kind == ActivityKind::kDrive && k + 2 < count_) {
            if (!decimal(tokens_[k + 1], 3, -kMaxCoordinateM, kMaxCoordinateM, &a.x) ||
                !decimal(tokens_[k + 2], 3, -kMaxCoordinateM, kMaxCoordinateM, &a.y)) {
                return false;
            }
            k += 3;
            // `within R`: the drive is done anywhere within R m of the point
            // (the deliberative and habitual layers stop on the way in). A
            // bare number after the point is refused, not read as a radius:
            // it was one once, with nothing to keep it.
            if (k < count_ && equals(tokens_[k], "within")) {
                double radiusM = 0.0;
                if (k + 1 >= count_) {
                    return fail(PlanError::kMissingField, &tokens_[k]);
                }
                if (!decimal(tokens_[k + 1], 3, kMinRadiusM, kMaxRadiusM, &radiusM)) {
                    return false;
                }
                // decimal() read at most 3 fractional digits: whole mm up to rounding.
                a.radiusMm = static_cast<std::uint16_t>(radiusM * 1000.0 + 0.5);
                k += 2;
            } else if (k < count_ && looksNumeric(tokens_[k])) {
                return fail(PlanError::kRadiusWithoutWithin, &tokens_[k]);
            }
            sawAt = true;
        } else if (equals(t, "target") && !sawTarget && hasNext &&
                   (a.kind == ActivityKind::kSample || a.kind == ActivityKind::kImage || a.kind == ActivityKind::kDig)) {
            double id = 0.0;
            if (!decimal(tokens_[k + 1], 0, 1.0, 255.0, &id)) {
                return false;
            }
            a.target = static_cast<std::uint8_t>(id);
            sawTarget = true;
            k += 2;
        } else if (equals(t, "ask") && hasNext) {
            if (a.askCount == kMaxAsks) {
                return fail(PlanError::kTooManyConditions, &tokens_[k + 1]);
            }
            std::size_t used = 0;
            if (!conditionAt(k + 1, false, &a.asks[a.askCount], &used)) {
                return false;
            }
            ++a.askCount;
            k += 1 + used;
        } else if (equals(t, "tell") && hasNext) {
            if (a.tellCount == kMaxTells) {
                return fail(PlanError::kTooManyConditions, &tokens_[k + 1]);
            }
            std::size_t used = 0;
            if (!conditionAt(k + 1, true, &a.tells[a.tellCount], &used)) {
                return false;
            }
            ++a.tellCount;
            k += 1 + used;
        } else if (equals(t, "when") && !sawWhen) {
            if (!guardAt(k, &a.guard)) {
                return false;
            }
            sawWhen = true;
            k += 2;
        } else {
            return fail(hasNext || !(equals(t, "cost") || equals(t, "at") || equals(t, "target") ||
                                     equals(t, "ask") || equals(t, "tell") || equals(t, "when"))
                            ? PlanError::kUnexpectedToken
                            : PlanError::kMissingField,
                        &t);
        }
    }
    if (a.kind == ActivityKind::kDrive && !sawAt) {
        return fail(PlanError::kMissingField, &tokens_[2]);
    }
    if ((a.kind == ActivityKind::kSample || a.kind == ActivityKind::kImage || a.kind == ActivityKind::kDig) &&
        !sawTarget) {
        return fail(PlanError::kMissingField, &tokens_[2]);
    }
    if (!guardValid(a.guard, a.from, a.to)) {
        return false;
    }
    ++tpn_->activityCount;
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
    if (!equals(tokens_[3], "[") || !equals(tokens_[5], ",") || !equals(tokens_[7], "]")) {
        return fail(PlanError::kMissingField, &tokens_[3]);
    }
    if (!milliseconds(tokens_[4], &c.bounds.lbMs)) {
        return false;
    }
    if (equals(tokens_[6], "inf")) {
        c.bounds.ubMs = kInfiniteMs;
    } else if (!milliseconds(tokens_[6], &c.bounds.ubMs)) {
        return false;
    }
    if (c.bounds.lbMs > c.bounds.ubMs) {
        return fail(PlanError::kBoundsReversed, &tokens_[6]);
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

}  // namespace

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
    Parser p(text, length, out);
    return p.run();
}

}  // namespace rse::plan_executive

#include "ground/script_runner.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>

#include "fsw/cmdtlm/command_validator.hpp"
#include "ground/command_encoder.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

constexpr std::size_t kRecentLimit = 4096;  // packets kept for waits

std::string trim(const std::string& text) {
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) {
        return "";
    }
    const std::size_t last = text.find_last_not_of(" \t\r\n");
    return text.substr(first, last - first + 1);
}

// Removes a comment: '#' at the start or after white space.
std::string stripComment(const std::string& line) {
    for (std::size_t i = 0; i < line.size(); ++i) {
        if (line[i] == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) {
            return line.substr(0, i);
        }
    }
    return line;
}

std::vector<std::string> splitWords(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> words;
    std::string word;
    while (in >> word) {
        words.push_back(word);
    }
    return words;
}

double parseSeconds(const std::string& text, const std::string& what) {
    double value = 0.0;
    if (!parseDouble(text, &value) || !std::isfinite(value) || value < 0.0 || value > 86400.0) {
        throw ScriptError(what + " '" + text + "' is not a number of seconds (0..86400)");
    }
    return value;
}

std::uint32_t parseAuthSequence(const std::string& text) {
    long long value = 0;
    if (!parseInteger(text, &value) || value < 0 || value > 0xFFFFFFFFLL) {
        throw ScriptError("--auth-seq '" + text + "' is not a number 0..4294967295");
    }
    return static_cast<std::uint32_t>(value);
}

// send / send-expect: NAME args... [--auth-seq N]
void parseSend(const std::vector<std::string>& words, std::size_t first, ScriptStatement* s) {
    if (first >= words.size()) {
        throw ScriptError(words[0] + " needs a command name");
    }
    s->command = lookupCommand(words[first]);
    if (s->command == nullptr) {
        throw ScriptError("unknown command '" + words[first] + "' (rse-ground dict --markdown lists them)");
    }
    std::vector<std::string> assignments;
    for (std::size_t i = first + 1; i < words.size(); ++i) {
        if (words[i] == "--auth-seq") {
            if (i + 1 >= words.size()) {
                throw ScriptError("--auth-seq needs a number");
            }
            s->authSequence = parseAuthSequence(words[++i]);
        } else {
            assignments.push_back(words[i]);
        }
    }
    try {
        s->args = encodeArguments(*s->command, assignments);
    } catch (const CommandError& e) {
        throw ScriptError(e.what());
    }
}

bool compare(double a, CompareOp op, double b) {
    switch (op) {
        case CompareOp::kEq: return a == b;
        case CompareOp::kNe: return a != b;
        case CompareOp::kLt: return a < b;
        case CompareOp::kLe: return a <= b;
        case CompareOp::kGt: return a > b;
        case CompareOp::kGe: return a >= b;
    }
    return false;
}

std::string conditionValueText(const WaitCondition& c, const DecodedField& f) {
    if (c.isText) {
        return "\"" + f.text + "\"";
    }
    if (c.index >= f.values.size()) {
        return "?";
    }
    if (f.desc->type == cmdtlm::FieldType::f32) {
        return formatFloat(static_cast<float>(f.values[c.index]));
    }
    return formatNumber(f.values[c.index]);
}

}  // namespace

const char* toString(CompareOp op) {
    switch (op) {
        case CompareOp::kEq: return "==";
        case CompareOp::kNe: return "!=";
        case CompareOp::kLt: return "<";
        case CompareOp::kLe: return "<=";
        case CompareOp::kGt: return ">";
        case CompareOp::kGe: return ">=";
    }
    return "?";
}

bool WaitCondition::appliesTo(const DecodedPacket& decoded) const {
    return decoded.ok && packet != nullptr && decoded.desc == packet;
}

bool WaitCondition::holds(const DecodedPacket& decoded) const {
    if (!appliesTo(decoded)) {
        return false;
    }
    const DecodedField* f = decoded.field(field->name);
    if (f == nullptr) {
        return false;
    }
    if (isText) {
        return (f->text == text) == (op == CompareOp::kEq);
    }
    return index < f->values.size() && compare(f->values[index], op, number);
}

std::string WaitCondition::observed(const DecodedPacket& decoded) const {
    const DecodedField* f = decoded.field(field->name);
    std::string name = std::string(packet->name) + "." + field->name;
    if (field->count > 1 && !isText) {
        name += "[" + std::to_string(index) + "]";
    }
    return name + " = " + (f != nullptr ? conditionValueText(*this, *f) : std::string("?"));
}

namespace {

constexpr const char* kConditionUsage = " (expected PACKET.FIELD OP VALUE, OP one of == != < <= > >=)";

// The first comparison operator in text, the two-character ones first at each
// place: its position and its operator; false when there is none.
bool findComparison(const std::string& text, std::size_t* at, CompareOp* op, std::size_t* opLength) {
    static const char* const kOps[] = {"==", "!=", "<=", ">=", "<", ">"};
    static const CompareOp kOpCodes[] = {CompareOp::kEq, CompareOp::kNe, CompareOp::kLe,
                                         CompareOp::kGe, CompareOp::kLt, CompareOp::kGt};
    for (std::size_t i = 0; i < text.size(); ++i) {
        for (std::size_t k = 0; k < 6; ++k) {
            if (text.compare(i, std::char_traits<char>::length(kOps[k]), kOps[k]) == 0) {
                *at = i;
                *op = kOpCodes[k];
                *opLength = std::char_traits<char>::length(kOps[k]);
                return true;
            }
        }
    }
    return false;
}

const cmdtlm::TelemetryDesc* conditionPacket(const std::string& packetName) {
    const cmdtlm::TelemetryDesc* packet = cmdtlm::findTelemetry(packetName.c_str());
    if (packet == nullptr) {
        std::string known;
        std::size_t count = 0;
        const cmdtlm::TelemetryDesc* all = cmdtlm::telemetryDescs(&count);
        for (std::size_t i = 0; i < count; ++i) {
            known += std::string(i > 0 ? ", " : "") + all[i].name;
        }
        throw ScriptError("unknown telemetry packet '" + packetName + "' (known: " + known + ")");
    }
    return packet;
}

// FIELD or FIELD[i] of c.packet (left is the whole PACKET.FIELD, for messages):
// sets c->field and c->index; true when an element was named.
bool conditionField(const std::string& left, std::string fieldName, WaitCondition* c) {
    bool indexed = false;
    const std::size_t bracket = fieldName.find('[');
    if (bracket != std::string::npos) {
        long long index = 0;
        if (fieldName.back() != ']' ||
            !parseInteger(fieldName.substr(bracket + 1, fieldName.size() - bracket - 2), &index) || index < 0) {
            throw ScriptError("'" + left + "': an element is written FIELD[i], i a number from 0");
        }
        c->index = static_cast<std::size_t>(index);
        indexed = true;
        fieldName = fieldName.substr(0, bracket);
    }
    for (std::size_t i = 0; i < c->packet->fieldCount; ++i) {
        if (fieldName == c->packet->fields[i].name) {
            c->field = &c->packet->fields[i];
        }
    }
    if (c->field == nullptr) {
        std::string known;
        for (std::size_t i = 0; i < c->packet->fieldCount; ++i) {
            known += std::string(i > 0 ? ", " : "") + c->packet->fields[i].name;
        }
        throw ScriptError(std::string(c->packet->name) + " has no field '" + fieldName + "' (fields: " + known + ")");
    }
    return indexed;
}

// A text field: compared whole, == or != only, the value without its quotes.
void textConditionValue(const std::string& qualified, const std::string& right, bool indexed, WaitCondition* c) {
    if (indexed) {
        throw ScriptError(qualified + " is a text: compare it whole, without [i]");
    }
    if (c->op != CompareOp::kEq && c->op != CompareOp::kNe) {
        throw ScriptError(qualified + " is a text: only == and != compare it");
    }
    c->isText = true;
    c->text = right;
    if (c->text.size() >= 2 && c->text.front() == '"' && c->text.back() == '"') {
        c->text = c->text.substr(1, c->text.size() - 2);
    }
}

// A number field (one element of an array): the value a number, or a mode's name for `mode`.
void numberConditionValue(const std::string& qualified, const std::string& right, bool indexed, WaitCondition* c) {
    if (c->field->count > 1 && !indexed) {
        throw ScriptError(qualified + " is an array of " + std::to_string(c->field->count) + ": write " +
                          c->field->name + "[i], i 0.." + std::to_string(c->field->count - 1));
    }
    if (indexed && c->index >= c->field->count) {
        throw ScriptError(qualified + "[" + std::to_string(c->index) + "]: index beyond the " +
                          std::to_string(c->field->count) + " elements");
    }
    bool symbolic = false;
    if (std::string(c->field->name) == "mode") {
        for (std::size_t m = 0; m < cmdtlm::kModeCount; ++m) {
            if (toUpper(right) == cmdtlm::toString(static_cast<cmdtlm::Mode>(m))) {
                c->number = static_cast<double>(m);
                symbolic = true;
            }
        }
    }
    if (!symbolic && (!parseDouble(right, &c->number) || std::isnan(c->number))) {
        throw ScriptError("'" + right + "' is not a number to compare " + qualified + " with");
    }
}

}  // namespace

WaitCondition parseCondition(const std::string& text) {
    std::size_t at = 0;
    std::size_t opLength = 0;
    WaitCondition c;
    if (!findComparison(text, &at, &c.op, &opLength)) {
        throw ScriptError("no comparison in '" + text + "'" + kConditionUsage);
    }
    const std::string left = trim(text.substr(0, at));
    const std::string right = trim(text.substr(at + opLength));
    const std::size_t dot = left.find('.');
    if (left.empty() || dot == std::string::npos || dot == 0 || dot + 1 >= left.size()) {
        throw ScriptError("'" + left + "' is not PACKET.FIELD" + kConditionUsage);
    }
    c.packet = conditionPacket(toUpper(left.substr(0, dot)));
    const bool indexed = conditionField(left, toLower(left.substr(dot + 1)), &c);
    const std::string qualified = std::string(c.packet->name) + "." + c.field->name;
    if (right.empty()) {
        throw ScriptError("no value to compare " + qualified + " with" + kConditionUsage);
    }
    if (c.field->type == cmdtlm::FieldType::chr) {
        textConditionValue(qualified, right, indexed, &c);
    } else {
        numberConditionValue(qualified, right, indexed, &c);
    }
    c.source = qualified + (indexed ? "[" + std::to_string(c.index) + "]" : std::string()) + " " +
               toString(c.op) + " " + right;
    return c;
}

std::optional<ScriptStatement> parseStatement(const std::string& rawLine, int lineNumber) {
    const std::string line = trim(stripComment(rawLine));
    if (line.empty()) {
        return std::nullopt;
    }
    ScriptStatement s;
    s.line = lineNumber;
    s.source = line;
    const std::vector<std::string> words = splitWords(line);
    const std::string keyword = toLower(words[0]);
    if (keyword == "send") {
        s.kind = ScriptStatement::Kind::kSend;
        parseSend(words, 1, &s);
    } else if (keyword == "send-expect") {
        s.kind = ScriptStatement::Kind::kSendExpect;
        if (words.size() < 3) {
            throw ScriptError("usage: send-expect REASON NAME [arg=value ...]");
        }
        const int reason = rejectReasonCode(words[1]);
        if (reason < 0) {
            std::string known;
            for (unsigned i = 0; i < cmdtlm::kRejectReasonCount; ++i) {
                known += (i > 0 ? ", " : "") + rejectReasonName(i);
            }
            throw ScriptError("unknown reason '" + words[1] + "' (known: " + known + ")");
        }
        s.expectedReason = static_cast<unsigned>(reason);
        parseSend(words, 2, &s);
    } else if (keyword == "wait") {
        s.kind = ScriptStatement::Kind::kWait;
        std::vector<std::string> rest(words.begin() + 1, words.end());
        s.seconds = kDefaultWaitSeconds;
        if (rest.size() >= 2 && toLower(rest[rest.size() - 2]) == "within") {
            s.seconds = parseSeconds(rest.back(), "within");
            rest.resize(rest.size() - 2);
        }
        std::string condition;
        for (const std::string& w : rest) {
            condition += (condition.empty() ? "" : " ") + w;
        }
        if (condition.empty()) {
            throw ScriptError("usage: wait PACKET.FIELD OP VALUE [within SECONDS]");
        }
        s.condition = parseCondition(condition);
    } else if (keyword == "sleep") {
        s.kind = ScriptStatement::Kind::kSleep;
        if (words.size() != 2) {
            throw ScriptError("usage: sleep SECONDS");
        }
        s.seconds = parseSeconds(words[1], "sleep");
    } else if (keyword == "print") {
        s.kind = ScriptStatement::Kind::kPrint;
        s.text = trim(line.substr(words[0].size()));
    } else {
        throw ScriptError("unknown statement '" + words[0] + "' (send, send-expect, wait, sleep, print)");
    }
    return s;
}

Script parseScript(std::istream& in) {
    Script script;
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        try {
            if (std::optional<ScriptStatement> s = parseStatement(line, number)) {
                script.statements.push_back(std::move(*s));
            }
        } catch (const ScriptError& e) {
            std::string why = e.what();
            // Multi-line messages (a usage line) are indented under the line number.
            for (std::size_t at = why.find('\n'); at != std::string::npos; at = why.find('\n', at + 2)) {
                why.replace(at, 1, "\n    ");
            }
            script.errors.push_back("line " + std::to_string(number) + ": " + why);
        }
    }
    return script;
}

ScriptRunner::ScriptRunner(GroundSession& session, std::ostream& out, std::ostream& err, bool verbose)
    : session_(session), out_(out), err_(err), verbose_(verbose) {
    session_.setObserver([this](const DecodedPacket& packet) {
        if (verbose_) {
            out_ << "  tlm " << renderPacket(packet) << "\n";
        }
        recent_.emplace_back(session_.receivedCount(), packet);
        while (recent_.size() > kRecentLimit) {
            recent_.pop_front();
        }
    });
}

ScriptRunner::~ScriptRunner() { session_.setObserver(nullptr); }

bool ScriptRunner::runSend(const ScriptStatement& s, std::string* why) {
    const AckResult result = session_.sendCommand(*s.command, s.args, s.authSequence, true);
    // Packets from before this command can no longer meet a wait.
    while (!recent_.empty() && recent_.front().first <= session_.receivedAtLastSend()) {
        recent_.pop_front();
    }
    if (result.outcome == AckOutcome::kNoAck) {
        *why = result.summary;
        return false;
    }
    out_ << "line " << s.line << ": " << result.summary << "\n";
    if (result.reason != s.expectedReason) {
        *why = "expected " + (s.expectedReason == 0 ? std::string("acceptance") : rejectReasonName(s.expectedReason)) +
               ", got " + result.summary;
        return false;
    }
    return true;
}

bool ScriptRunner::runWait(const ScriptStatement& s, std::string* why) {
    const WaitCondition& c = s.condition;
    const DecodedPacket* last = nullptr;
    for (const auto& entry : recent_) {
        if (c.appliesTo(entry.second)) {
            last = &entry.second;
            if (c.holds(entry.second)) {
                out_ << "line " << s.line << ": " << c.source << ": met (" << c.observed(entry.second) << ")\n";
                return true;
            }
        }
    }
    std::optional<DecodedPacket> lastSeen;
    if (last != nullptr) {
        lastSeen = *last;
    }
    const double start = monotonicSeconds();
    const double deadline = start + s.seconds;
    std::size_t others = 0;
    for (;;) {
        const double left = deadline - monotonicSeconds();
        if (left <= 0.0) {
            break;
        }
        std::optional<DecodedPacket> packet = session_.receive(left);
        if (!packet) {
            continue;
        }
        if (!c.appliesTo(*packet)) {
            ++others;
            continue;
        }
        if (c.holds(*packet)) {
            char elapsed[32];
            std::snprintf(elapsed, sizeof elapsed, "%.1f", monotonicSeconds() - start);
            out_ << "line " << s.line << ": " << c.source << ": met after " << elapsed << " s ("
                 << c.observed(*packet) << ")\n";
            return true;
        }
        lastSeen = std::move(packet);
    }
    *why = "wait " + c.source + ": not met within " + formatNumber(s.seconds) + " s (" +
           (lastSeen ? "last " + c.observed(*lastSeen)
                     : "no " + std::string(c.packet->name) + " packet received" +
                           (others > 0 ? " (" + std::to_string(others) + " other packets were)"
                                       : std::string(": is the link up?"))) +
           ")";
    return false;
}

void ScriptRunner::runSleep(double seconds) {
    const double deadline = monotonicSeconds() + seconds;
    for (double left = seconds; left > 0.0; left = deadline - monotonicSeconds()) {
        (void)session_.receive(left);  // keeps the packets for later waits
    }
}

bool ScriptRunner::execute(const ScriptStatement& s, std::string* why) {
    try {
        switch (s.kind) {
            case ScriptStatement::Kind::kSend:
            case ScriptStatement::Kind::kSendExpect:
                return runSend(s, why);
            case ScriptStatement::Kind::kWait:
                return runWait(s, why);
            case ScriptStatement::Kind::kSleep:
                runSleep(s.seconds);
                return true;
            case ScriptStatement::Kind::kPrint:
                out_ << s.text << "\n";
                return true;
        }
    } catch (const std::exception& e) {  // link, state or packet errors
        *why = e.what();
        return false;
    }
    *why = "unknown statement";
    return false;
}

int ScriptRunner::run(const Script& script, const std::string& name) {
    if (!script.ok()) {
        for (const std::string& e : script.errors) {
            err_ << name << ": " << e << "\n";
        }
        err_ << name << ": " << script.errors.size() << " bad line(s); nothing was sent\n";
        return 1;
    }
    std::size_t passed = 0;
    for (const ScriptStatement& s : script.statements) {
        std::string why;
        if (!execute(s, &why)) {
            err_ << name << ":" << s.line << ": FAILED: " << s.source << "\n    " << why << "\n";
            err_ << name << ": " << passed << " of " << script.statements.size()
                 << " statements passed, stopped at line " << s.line << "\n";
            out_.flush();
            return 1;
        }
        ++passed;
        out_.flush();
    }
    out_ << name << ": all " << passed << " statements passed\n";
    return 0;
}

int runScriptFile(const std::string& path, GroundSession& session, std::ostream& out, std::ostream& err,
                  bool verbose) {
    std::ifstream in(path);
    if (!in) {
        err << "cannot read script '" << path << "'\n";
        return 1;
    }
    const Script script = parseScript(in);
    ScriptRunner runner(session, out, err, verbose);
    return runner.run(script, path);
}

}  // namespace rse::ground

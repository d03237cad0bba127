// rse-ground command scripts: one statement a line, '#' starts a comment (at the
// start of a line or after white space), blank lines ignored.
//
//   send NAME [arg=value ...] [--auth-seq N]        fails unless the rover accepts it
//   send-expect REASON NAME [arg=value ...] [--auth-seq N]
//                                                   fails unless the rover answers with that
//                                                   CMD_ACK reason (snake_case name, e.g.
//                                                   replayed_sequence, or accepted)
//   wait PACKET.FIELD OP VALUE [within SECONDS]     OP: == != < <= > >=; FIELD[i] for array
//                                                   elements; default 10 s; VALUE a number (a
//                                                   mode name for mode fields, a text for chr
//                                                   fields with == and !=)
//   sleep SECONDS
//   print TEXT
//
// A wait is met by a telemetry packet received after the last send was sent (so
// a packet that came with the command's acknowledgement counts), or one that
// arrives within the time. The whole script is parsed, and every command's
// arguments checked, before the first statement runs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/ground_session.hpp"
#include "ground/telemetry_decoder.hpp"

namespace rse::ground {

constexpr double kDefaultWaitSeconds = 10.0;

class ScriptError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

enum class CompareOp { kEq, kNe, kLt, kLe, kGt, kGe };
const char* toString(CompareOp op);

struct WaitCondition {
    const cmdtlm::TelemetryDesc* packet = nullptr;
    const cmdtlm::FieldDesc* field = nullptr;
    std::size_t index = 0;
    CompareOp op = CompareOp::kEq;
    bool isText = false;  // chr field: compares text
    double number = 0.0;
    std::string text;
    std::string source;  // "HK.mode == 1", as written (normalised spacing)

    // True when the packet is this condition's packet and the condition holds.
    bool holds(const DecodedPacket& decoded) const;
    bool appliesTo(const DecodedPacket& decoded) const;
    // "HK.mode = 0" for a packet the condition applies to.
    std::string observed(const DecodedPacket& decoded) const;
};

// "HK.mode == 1", "DRIVES.state[2] >= 4", "EVENT.text == mode changed". Throws ScriptError.
WaitCondition parseCondition(const std::string& text);

struct ScriptStatement {
    enum class Kind { kSend, kSendExpect, kWait, kSleep, kPrint };
    Kind kind = Kind::kPrint;
    int line = 0;
    std::string source;  // the statement as written, comment removed
    // send, send-expect
    const cmdtlm::CommandDesc* command = nullptr;
    std::vector<std::uint8_t> args;  // already checked and encoded
    std::optional<std::uint32_t> authSequence;
    unsigned expectedReason = 0;  // 0 = accepted
    // wait
    WaitCondition condition;
    double seconds = 0.0;  // wait: within; sleep: duration
    // print
    std::string text;
};

struct Script {
    std::vector<ScriptStatement> statements;
    std::vector<std::string> errors;  // "line 3: ..." per bad line
    bool ok() const { return errors.empty(); }
};

// Parses one line (without its newline); nullopt for a blank or comment line.
// Throws ScriptError with the reason (no line number).
std::optional<ScriptStatement> parseStatement(const std::string& line, int lineNumber);
Script parseScript(std::istream& in);

class ScriptRunner {
public:
    // Takes over the session's observer. verbose: print every packet received.
    ScriptRunner(GroundSession& session, std::ostream& out, std::ostream& err, bool verbose = false);
    ~ScriptRunner();
    ScriptRunner(const ScriptRunner&) = delete;
    ScriptRunner& operator=(const ScriptRunner&) = delete;

    // Runs the statements in order, stops at the first failure. Reports
    // "NAME:LINE: FAILED: ..." on err. Returns 0 when all passed, else 1.
    int run(const Script& script, const std::string& name);
    // One statement; false with *why when it failed.
    bool execute(const ScriptStatement& statement, std::string* why);

private:
    bool runSend(const ScriptStatement& statement, std::string* why);
    bool runWait(const ScriptStatement& statement, std::string* why);
    void runSleep(double seconds);

    GroundSession& session_;
    std::ostream& out_;
    std::ostream& err_;
    bool verbose_;
    std::deque<std::pair<std::uint64_t, DecodedPacket>> recent_;  // (receive number, packet)
};

// Reads, parses and runs a script file: 0 all passed, 1 a line failed (or did
// not parse, or the file cannot be read).
int runScriptFile(const std::string& path, GroundSession& session, std::ostream& out, std::ostream& err,
                  bool verbose = false);

}  // namespace rse::ground

#include "ground/ground_cli.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/command_encoder.hpp"
#include "ground/dictionary_export.hpp"
#include "ground/ground_link.hpp"
#include "ground/ground_session.hpp"
#include "ground/key_file.hpp"
#include "fsw/geometry/rover_footprint.hpp"
#include "ground/mission_from_telemetry.hpp"
#include "ground/mission_points.hpp"
#include "ground/mission_report.hpp"
#include "ground/mission_telemetry.hpp"
#include "ground/plan_tool.hpp"
#include "ground/plan_transfer.hpp"
#include "ground/script_runner.hpp"
#include "ground/session_recording.hpp"
#include "ground/sequence_store.hpp"
#include "ground/table_compiler.hpp"
#include "ground/table_tool.hpp"
#include "ground/table_transfer.hpp"
#include "ground/telemetry_decoder.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

// words[0] names a dictionary command, the rest are its arg=value assignments:
// the command and its checked argument bytes (CommandError on anything wrong).
const cmdtlm::CommandDesc* namedCommand(const std::vector<std::string>& words, std::vector<std::uint8_t>* encoded) {
    const cmdtlm::CommandDesc* command = lookupCommand(words[0]);
    if (command == nullptr) {
        throw CommandError("unknown command '" + words[0] + "' (rse-ground dict --markdown lists them)");
    }
    *encoded = encodeArguments(*command, std::vector<std::string>(words.begin() + 1, words.end()));
    return command;
}

constexpr const char* kUsage =
    "usage: rse-ground [global options] COMMAND ...\n"
    "commands:\n"
    "  send NAME [arg=value ...] [--auth-seq N] [--no-wait]   send a command, print its CMD_ACK\n"
    "  watch [--count N] [--seconds S] [--only NAME,...]     print telemetry and events as they come\n"
    "  record FILE [--seconds S] [--until-outcome] [--tail S] [--quiet]\n"
    "                                                        record every packet received, with its time\n"
    "  summary FILE [--facts] [--no-events]                  the mission a recording's telemetry shows\n"
    "  report FILE [--map MAP] [--tables DIR] [--out DIR] [--name TEXT]\n"
    "                                                        the ten points, report.md and map.svg from a recording\n"
    "  resync [--auth-seq N]                                 AUTH_RESYNC with the nonce of the rover's next HK\n"
    "  run SCRIPT [--verbose]                                run a command script (docs/ground.md)\n"
    "  table load IMAGE.tbl [--activate] [--force]           upload, validate (and activate) a table\n"
    "  table dump ID|NAME [--inactive] [-o FILE]             download a table image and print it\n"
    "  table build|show|check|list ...                       table images on this machine\n"
    "  dict --markdown|--json [-o FILE]                      export the command/telemetry dictionary\n"
    "  plan check FILE [--failed C,...] [--degraded C,...]   check a mission plan with the flight code\n"
    "  plan load FILE [--failed C,...] [--degraded C,...] [--force]\n"
    "                                                        check, upload (PLAN_LOAD chunks, PLAN_START), verdict\n"
    "  plan short TEXT [--failed C,...] [--degraded C,...] [--force]\n"
    "                                                        the same for a plan in one PLAN_SHORT (';' lines)\n"
    "  plan abort                                            stop the plan running (PLAN_ABORT)\n"
    "  encode NAME [arg=value ...] [--auth-seq N] [-o FILE]  write a command packet (hex without -o)\n"
    "  serve [--http [ADDR:]PORT] [--archive FILE] [--web DIR] [--tables DIR] [--seconds S]\n"
    "                                                        mission control: telemetry archived and served to\n"
    "                                                        Open MCT over HTTP and WebSocket (default\n"
    "                                                        127.0.0.1:8090; docs/mission_control.md)\n"
    "global options:\n"
    "  --udp HOST[:PORT]        commands to HOST:PORT over UDP (default 127.0.0.1:1234)\n"
    "  --tlm-port [ADDR:]PORT   receive telemetry on ADDR:PORT (default 0.0.0.0:1235)\n"
    "  --can IFACE              ISO-TP on a SocketCAN interface instead of UDP\n"
    "  --can-tx ID --can-rx ID  ISO-TP ids in hex (default 6C0 and 6C1); --pad pads frames to 8 bytes\n"
    "  --key-file FILE          command keys, one ID:64hex a line (default: the built-in lab key, id 1)\n"
    "  --key-id N               which key of the file (default: its first)\n"
    "  --no-auth                unauthenticated commands (key id 0): only a lab-setting rover takes them\n"
    "  --state-dir DIR          anti-replay sequence state (default $RSE_GROUND_STATE or ~/.rse-ground)\n"
    "  --timeout S              how long to wait for an acknowledgement (default 2)\n"
    "exit: 0 ok/accepted, 1 link error/no acknowledgement/script failed, 2 usage or bad argument,\n"
    "      3 rejected by the rover\n";

constexpr double kDefaultRecordTailS = 5.0;  // record --until-outcome: seconds recorded after the outcome

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct GlobalOptions {
    std::string udp = "127.0.0.1";
    std::string tlm = "0.0.0.0:1235";
    std::string can;
    std::uint32_t canTx = kGroundIsoTpTxId;
    std::uint32_t canRx = kGroundIsoTpRxId;
    bool pad = false;
    std::string keyFile;
    std::optional<std::uint16_t> keyId;
    bool noAuth = false;
    std::string stateDir;
    double timeout = kDefaultAckTimeout;
};

double parsePositiveSeconds(const std::string& option, const std::string& text) {
    double value = 0.0;
    if (!parseDouble(text, &value) || !std::isfinite(value) || value <= 0.0 || value > 86400.0) {
        throw UsageError(option + " '" + text + "': expected seconds, a number > 0");
    }
    return value;
}

long long parseCount(const std::string& option, const std::string& text, long long min, long long max) {
    long long value = 0;
    if (!parseInteger(text, &value) || value < min || value > max) {
        throw UsageError(option + " '" + text + "': expected a whole number " + std::to_string(min) + ".." +
                         std::to_string(max));
    }
    return value;
}

std::uint32_t parseCanId(const std::string& option, const std::string& text) {
    long long value = 0;
    const std::string hex = text.rfind("0x", 0) == 0 || text.rfind("0X", 0) == 0 ? text : "0x" + text;
    if (!parseInteger(hex, &value) || value < 0 || value > 0x7FF) {
        throw UsageError(option + " '" + text + "': expected an 11-bit CAN id in hex (000..7FF)");
    }
    return static_cast<std::uint32_t>(value);
}

// Splits the global options out of args (everything after the program name).
// Stops at "table build|show|check|list" and "plan check": those arguments
// belong to the table and plan tools.
std::vector<std::string> takeGlobalOptions(const std::vector<std::string>& args, GlobalOptions* g) {
    std::vector<std::string> rest;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (rest.size() == 1 && ((rest[0] == "table" && (a == "build" || a == "show" || a == "check" || a == "list")) ||
                                 (rest[0] == "plan" && a == "check"))) {
            rest.insert(rest.end(), args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
            return rest;
        }
        auto value = [&]() -> std::string {
            if (i + 1 >= args.size()) {
                throw UsageError(a + " needs a value");
            }
            return args[++i];
        };
        if (a == "--udp") {
            g->udp = value();
        } else if (a == "--tlm-port") {
            g->tlm = value();
        } else if (a == "--can") {
            g->can = value();
        } else if (a == "--can-tx") {
            g->canTx = parseCanId(a, value());
        } else if (a == "--can-rx") {
            g->canRx = parseCanId(a, value());
        } else if (a == "--pad") {
            g->pad = true;
        } else if (a == "--key-file") {
            g->keyFile = value();
        } else if (a == "--key-id") {
            g->keyId = static_cast<std::uint16_t>(parseCount(a, value(), 1, 65535));
        } else if (a == "--no-auth") {
            g->noAuth = true;
        } else if (a == "--state-dir") {
            g->stateDir = value();
        } else if (a == "--timeout") {
            g->timeout = parsePositiveSeconds(a, value());
        } else {
            rest.push_back(a);
        }
    }
    return rest;
}

class Cli {
public:
    Cli(GlobalOptions options, std::ostream& out, std::ostream& err, const LinkFactory& linkFactory,
        const ServeCommand& serveCommand)
        : g_(std::move(options)), out_(out), err_(err), linkFactory_(linkFactory), serveCommand_(serveCommand) {}

    int send(const std::vector<std::string>& args);
    int resync(const std::vector<std::string>& args);
    int watch(const std::vector<std::string>& args);
    int record(const std::vector<std::string>& args);
    int summary(const std::vector<std::string>& args);
    int report(const std::vector<std::string>& args);
    bool readRecordingFile(const char* command, const std::string& path, SessionRecording* recording);
    int run(const std::vector<std::string>& args);
    int table(const std::vector<std::string>& args);
    int plan(const std::vector<std::string>& args);
    int encode(const std::vector<std::string>& args);
    int dict(const std::vector<std::string>& args);
    int serve(const std::vector<std::string>& args);

private:
    PacketAuth auth() {
        if (g_.noAuth) {
            if (!g_.keyFile.empty() || g_.keyId) {
                throw UsageError("--no-auth cannot be combined with --key-file or --key-id");
            }
            return PacketAuth{};
        }
        PacketAuth a = loadPacketAuth(g_.keyFile, g_.keyId);
        if (g_.keyFile.empty()) {
            err_ << "rse-ground: signing with the built-in lab key (id 1): lab rovers only, never flight\n";
        } else {
            if (a.key.size() == cmdtlm::kKeySize && cmdtlm::isLabKey(a.key.data())) {
                // The lab key's bytes under any key id are still the public lab key.
                err_ << "rse-ground: key id " << a.keyId << " of " << g_.keyFile
                     << " is the public lab key: lab rovers only, never flight\n";
            }
            if (keyFileTooOpen(g_.keyFile)) {
                err_ << "rse-ground: warning: " << g_.keyFile << " is readable by others (chmod 600 it)\n";
            }
        }
        return a;
    }
    SequenceStore& store() {
        if (!store_) {
            store_ = std::make_unique<SequenceStore>(g_.stateDir.empty() ? SequenceStore::defaultDirectory()
                                                                         : g_.stateDir);
        }
        return *store_;
    }
    std::unique_ptr<GroundLink> openLink(bool listen) {
        if (linkFactory_) {
            return linkFactory_(listen);
        }
        if (!g_.can.empty()) {
            return std::make_unique<IsoTpGroundLink>(g_.can, g_.canTx, g_.canRx, g_.pad);
        }
        const HostPort remote = parseHostPort(g_.udp, "127.0.0.1", kDefaultCommandPort);
        const HostPort local = parseHostPort(g_.tlm, "0.0.0.0", kDefaultTelemetryPort);
        return std::make_unique<UdpGroundLink>(remote, local, listen);
    }
    // Splits "--auth-seq N" out of a command's words.
    std::optional<std::uint32_t> takeAuthSeq(std::vector<std::string>* words) {
        std::optional<std::uint32_t> seq;
        for (std::size_t i = 0; i < words->size();) {
            if ((*words)[i] == "--auth-seq") {
                if (i + 1 >= words->size()) {
                    throw UsageError("--auth-seq needs a number");
                }
                seq = static_cast<std::uint32_t>(parseCount("--auth-seq", (*words)[i + 1], 0, 0xFFFFFFFFLL));
                words->erase(words->begin() + static_cast<std::ptrdiff_t>(i),
                             words->begin() + static_cast<std::ptrdiff_t>(i + 2));
            } else {
                ++i;
            }
        }
        return seq;
    }
    bool takeFlag(std::vector<std::string>* words, const std::string& flag) {
        for (std::size_t i = 0; i < words->size(); ++i) {
            if ((*words)[i] == flag) {
                words->erase(words->begin() + static_cast<std::ptrdiff_t>(i));
                return true;
            }
        }
        return false;
    }
    std::optional<std::string> takeValue(std::vector<std::string>* words, const std::string& option) {
        for (std::size_t i = 0; i < words->size(); ++i) {
            if ((*words)[i] == option) {
                if (i + 1 >= words->size()) {
                    throw UsageError(option + " needs a value");
                }
                std::string v = (*words)[i + 1];
                words->erase(words->begin() + static_cast<std::ptrdiff_t>(i),
                             words->begin() + static_cast<std::ptrdiff_t>(i + 2));
                return v;
            }
        }
        return std::nullopt;
    }
    void rejectOptions(const std::vector<std::string>& words, const std::string& where) {
        for (const std::string& w : words) {
            if (w.rfind("--", 0) == 0 || w == "-o") {
                throw UsageError(where + ": unknown option " + w);
            }
        }
    }
    // A command's acknowledgement, printed, and the exit code it means.
    int report(const AckResult& result) {
        switch (result.outcome) {
            case AckOutcome::kAccepted:
            case AckOutcome::kNotWaited:
                out_ << result.summary << "\n";
                return kExitOk;
            case AckOutcome::kRejected:
                out_ << result.summary << "\n";
                hint(result);
                return kExitRejected;
            case AckOutcome::kNoAck:
                break;
        }
        err_ << "rse-ground: " << result.summary << "\n";
        return kExitLink;
    }
    void hint(const AckResult& result) {
        using cmdtlm::CommandReject;
        switch (static_cast<CommandReject>(result.reason)) {
            case CommandReject::kStaleSequence:
            case CommandReject::kReplayedSequence: {
                const std::uint16_t key = g_.noAuth ? 0 : (g_.keyId ? *g_.keyId : 1);
                err_ << "hint: the rover has seen this anti-replay number (or newer ones) for key " << key
                     << "; numbers come from " << store().directory()
                     << " (another ground station, or a reset state directory?); --auth-seq N jumps ahead\n";
                const std::uint64_t after = std::uint64_t{store().last(key)} + cmdtlm::kReserveBlock + 1;
                if (after <= cmdtlm::kMaxUsableSequence) {
                    err_ << "hint: after a rover restart every number up to its stored reservation is refused, at most "
                         << cmdtlm::kReserveBlock << " above the last one it accepted: --auth-seq " << after << "\n";
                }
                break;
            }
            case CommandReject::kSequenceUnsynchronised:
                if (result.detail == 4 || result.detail == 6) {
                    err_ << (result.detail == 4
                                 ? "hint: not the rover's current nonce (it changes at every restart and after each "
                                   "AUTH_RESYNC accepted): rse-ground resync reads the current one\n"
                                 : "hint: the rover has no nonce (no random source at start-up): AUTH_RESYNC cannot "
                                   "succeed until it restarts with one\n");
                    break;
                }
                err_ << "hint: the rover does not know this key's anti-replay state (store missing or corrupt, or key "
                        "new to it): rse-ground resync (it reads the nonce from HK, auth_challenge_high/low, and "
                        "sends AUTH_RESYNC challenge_high=H challenge_low=L; docs/ground.md)\n";
                break;
            case CommandReject::kSequenceExhausted:
                err_ << "hint: this key's anti-replay numbers are used up (above " << cmdtlm::kMaxUsableSequence
                     << "): load a new key on the rover and use it (docs/ground.md)\n";
                break;
            case CommandReject::kSequenceStoreFailed:
                err_ << "hint: the rover could not write its anti-replay store, so it did not act on the command "
                        "(HK.auth_store_write_failures, event 545); send it again once the store is writable\n";
                break;
            case CommandReject::kMacMissing:
                err_ << "hint: the rover requires authenticated commands: drop --no-auth\n";
                break;
            case CommandReject::kUnknownKey:
            case CommandReject::kBadMac:
                err_ << "hint: the rover does not have this key, or has another key under this id (the rover does not "
                        "say which): check --key-file/--key-id against rse-fsw --key-file\n";
                break;
            default:
                break;
        }
    }

    GlobalOptions g_;
    std::ostream& out_;
    std::ostream& err_;
    std::unique_ptr<SequenceStore> store_;
    const LinkFactory& linkFactory_;
    const ServeCommand& serveCommand_;
};

int Cli::send(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    const bool noWait = takeFlag(&words, "--no-wait");
    const std::optional<std::uint32_t> forced = takeAuthSeq(&words);
    if (words.empty()) {
        throw UsageError("send: which command? (rse-ground dict --markdown lists them)");
    }
    rejectOptions(words, "send");
    // Every argument is checked before the link is even opened.
    std::vector<std::uint8_t> encoded;
    const cmdtlm::CommandDesc* command = namedCommand(words, &encoded);
    const PacketAuth packetAuth = auth();
    std::unique_ptr<GroundLink> link = openLink(!noWait);
    GroundSession session(*link, store(), packetAuth, g_.timeout);
    return report(session.sendCommand(*command, encoded, forced, !noWait));
}

// The two steps of docs/ground.md's re-synchronisation in one: the nonce from
// the rover's next HK (1 Hz), then AUTH_RESYNC carrying it, signed with this
// ground's next number (above every number it has used, which the rover takes
// as the key's new floor). Nothing is sent before the nonce is known.
int Cli::resync(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    const std::optional<std::uint32_t> forced = takeAuthSeq(&words);
    rejectOptions(words, "resync");
    if (!words.empty()) {
        throw UsageError("resync: unexpected '" + words[0] + "'");
    }
    if (g_.noAuth) {
        throw UsageError("resync: AUTH_RESYNC re-synchronises a key: it cannot be sent with --no-auth");
    }
    const PacketAuth packetAuth = auth();
    std::unique_ptr<GroundLink> link = openLink(true);
    const double wait = std::max(g_.timeout, 3.0);  // HK comes once a second
    const double deadline = monotonicSeconds() + wait;
    std::optional<DecodedPacket> hk;
    while (!hk) {
        const double left = deadline - monotonicSeconds();
        if (left <= 0.0) {
            err_ << "rse-ground: resync: no HK within " << formatNumber(wait) << " s on " << link->describe()
                 << ": is rse-fsw running and sending telemetry here?\n";
            return kExitLink;
        }
        std::optional<std::vector<std::uint8_t>> bytes = link->receive(left);
        if (bytes) {
            DecodedPacket packet = decodeTelemetry(*bytes);
            if (packet.ok && std::string(packet.name()) == "HK") {
                hk = std::move(packet);
            }
        }
    }
    const std::optional<double> highField = hk->value("auth_challenge_high");
    const std::optional<double> lowField = hk->value("auth_challenge_low");
    if (!highField || !lowField) {
        err_ << "rse-ground: resync: the rover's HK has no auth_challenge_high/low (a rover without AUTH_RESYNC?): "
                "nothing sent\n";
        return kExitLink;
    }
    const auto high = static_cast<std::uint32_t>(*highField);
    const auto low = static_cast<std::uint32_t>(*lowField);
    out_ << "rover nonce " << high << ":" << low << " (auth_store_state "
         << formatNumber(hk->value("auth_store_state").value_or(-1)) << ", keys unsynchronised "
         << formatNumber(hk->value("auth_keys_unsynced").value_or(-1)) << ")\n";
    std::vector<std::uint8_t> encoded;
    const cmdtlm::CommandDesc* command = namedCommand(
        {"AUTH_RESYNC", "challenge_high=" + std::to_string(high), "challenge_low=" + std::to_string(low)}, &encoded);
    GroundSession session(*link, store(), packetAuth, g_.timeout);
    return report(session.sendCommand(*command, encoded, forced, true));
}

int Cli::watch(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    long long count = 0;
    double seconds = 0.0;
    std::set<std::string> only;
    if (auto v = takeValue(&words, "--count")) {
        count = parseCount("--count", *v, 1, 1LL << 40);
    }
    if (auto v = takeValue(&words, "--seconds")) {
        seconds = parsePositiveSeconds("--seconds", *v);
    }
    if (auto v = takeValue(&words, "--only")) {
        std::string list = *v + ",";
        for (std::size_t start = 0, comma = list.find(','); comma != std::string::npos;
             start = comma + 1, comma = list.find(',', start)) {
            const std::string name = toUpper(list.substr(start, comma - start));
            if (name.empty()) {
                continue;
            }
            if (cmdtlm::findTelemetry(name.c_str()) == nullptr) {
                throw UsageError("watch --only: unknown telemetry packet '" + name + "'");
            }
            only.insert(name);
        }
    }
    if (!words.empty()) {
        throw UsageError("watch: unexpected '" + words[0] + "'");
    }
    std::unique_ptr<GroundLink> link = openLink(true);
    out_ << "watching " << link->describe() << (seconds > 0 ? " for " + formatNumber(seconds) + " s" : "") << "\n"
         << std::flush;
    const double start = monotonicSeconds();
    const double deadline = seconds > 0 ? start + seconds : 0.0;
    long long shown = 0;
    bool anything = false;
    bool warned = false;
    for (;;) {
        const double now = monotonicSeconds();
        if (seconds > 0 && now >= deadline) {
            break;
        }
        const double slice = seconds > 0 ? deadline - now : 1.0;
        std::optional<std::vector<std::uint8_t>> bytes = link->receive(slice < 1.0 ? slice : 1.0);
        if (!bytes) {
            if (!anything && !warned && monotonicSeconds() - start >= 5.0) {
                err_ << "watch: nothing received in 5 s on " << link->describe()
                     << ": is rse-fsw running and sending telemetry here?\n";
                warned = true;
            }
            continue;
        }
        anything = true;
        const DecodedPacket packet = decodeTelemetry(*bytes);
        if (!only.empty() && (!packet.ok || only.count(packet.name()) == 0)) {
            continue;
        }
        out_ << renderPacket(packet) << std::endl;
        if (count > 0 && ++shown >= count) {
            return kExitOk;
        }
    }
    if (count > 0) {
        err_ << "watch: " << shown << " of " << count << " packets within " << formatNumber(seconds) << " s\n";
        return kExitLink;
    }
    if (!anything) {
        err_ << "watch: no telemetry within " << formatNumber(seconds) << " s on " << link->describe()
             << ": is rse-fsw running and is the link up?\n";
        return kExitLink;
    }
    return kExitOk;
}

// A session recorder: every packet received goes to the file as it comes
// (ground/session_recording.hpp). --until-outcome stops once the telemetry
// shows the mission's outcome (ground/mission_telemetry.hpp), --tail seconds
// later so the events that follow it arrive; --seconds bounds the whole
// recording.
int Cli::record(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    const bool untilOutcome = takeFlag(&words, "--until-outcome");
    const bool quiet = takeFlag(&words, "--quiet");
    double seconds = 0.0;
    double tail = kDefaultRecordTailS;
    if (auto v = takeValue(&words, "--seconds")) {
        seconds = parsePositiveSeconds("--seconds", *v);
    }
    if (auto v = takeValue(&words, "--tail")) {
        tail = parsePositiveSeconds("--tail", *v);
    }
    rejectOptions(words, "record");
    if (words.size() != 1) {
        throw UsageError("usage: rse-ground record FILE [--seconds S] [--until-outcome] [--tail S] [--quiet]");
    }
    if (!untilOutcome && seconds <= 0.0) {
        throw UsageError("record: give --seconds S, --until-outcome or both (it would never stop)");
    }
    std::ofstream file(words[0], std::ios::trunc);
    if (!file) {
        err_ << "record: cannot write '" << words[0] << "'\n";
        return kExitLink;
    }
    std::unique_ptr<GroundLink> link = openLink(true);
    timespec utc{};
    clock_gettime(CLOCK_REALTIME, &utc);
    SessionRecorder recorder(file, link->describe(), static_cast<double>(utc.tv_sec) + 1e-9 * static_cast<double>(utc.tv_nsec));
    out_ << "recording " << link->describe() << " to " << words[0]
         << (seconds > 0 ? " for at most " + formatNumber(seconds) + " s" : "")
         << (untilOutcome ? " until the mission's outcome" : "") << "\n"
         << std::flush;
    MissionTelemetryReader reader;
    const double start = monotonicSeconds();
    double stopAt = seconds > 0 ? start + seconds : 0.0;
    bool outcomeSeen = false;
    for (;;) {
        const double now = monotonicSeconds();
        if (stopAt > 0 && now >= stopAt) {
            break;
        }
        const double left = stopAt > 0 ? stopAt - now : 1.0;
        std::optional<std::vector<std::uint8_t>> bytes = link->receive(std::min(left, 1.0));
        if (!bytes) {
            continue;
        }
        const double at = monotonicSeconds() - start;
        recorder.record(at, *bytes);
        if (!recorder.ok()) {
            err_ << "record: writing '" << words[0] << "' failed after " << recorder.packets() << " packets\n";
            return kExitLink;
        }
        const DecodedPacket packet = decodeTelemetry(*bytes);
        if (!quiet) {
            out_ << renderPacket(packet) << std::endl;
        }
        reader.add(at, packet);
        if (untilOutcome && !outcomeSeen && reader.ended()) {
            outcomeSeen = true;
            const double tailEnd = monotonicSeconds() + tail;
            stopAt = stopAt > 0 ? std::min(stopAt, tailEnd) : tailEnd;
            out_ << "outcome: " << toString(reader.mission().outcome) << ": recording " << formatNumber(tail)
                 << " s more\n"
                 << std::flush;
        }
    }
    out_ << "recorded " << recorder.packets() << " packets in " << formatNumber(monotonicSeconds() - start)
         << " s to " << words[0] << "\n";
    if (recorder.packets() == 0) {
        err_ << "record: no telemetry on " << link->describe()
             << ": is rse-fsw running, and has it heard this ground (over CAN it sends only after a command)?\n";
        return kExitLink;
    }
    if (untilOutcome && !outcomeSeen) {
        err_ << "record: no outcome within " << formatNumber(seconds) << " s\n";
        return kExitLink;
    }
    return kExitOk;
}

// A recording file for `command`: false (said on stderr) when it cannot be
// opened; its bad lines are named on stderr and skipped.
bool Cli::readRecordingFile(const char* command, const std::string& path, SessionRecording* recording) {
    std::ifstream in(path);
    if (!in) {
        err_ << command << ": cannot read '" << path << "'\n";
        return false;
    }
    *recording = readSessionRecording(in);
    for (const std::string& e : recording->errors) {
        err_ << path << ": " << e << "\n";
    }
    return true;
}

int Cli::summary(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    const bool facts = takeFlag(&words, "--facts");
    const bool noEvents = takeFlag(&words, "--no-events");
    rejectOptions(words, "summary");
    if (words.size() != 1) {
        throw UsageError("usage: rse-ground summary FILE [--facts] [--no-events]");
    }
    SessionRecording recording;
    if (!readRecordingFile("summary", words[0], &recording) ||
        (recording.packets.empty() && !recording.errors.empty())) {
        return kExitLink;
    }
    const MissionTelemetry mission = readMissionTelemetry(recording);
    if (facts) {
        printMissionFacts(mission, out_);
    } else {
        printMissionTelemetry(mission, out_, !noEvents);
    }
    return kExitOk;
}

// The mission from a recording as rse-demo shows it: the ten points (printed as
// the tracker saw them, then the verdict), build/mission-style report.md and
// map.svg. The coarse map is the one the rover flew: --map (an uploaded image,
// or its .toml source), else DIR/coarse_map.toml of --tables (default
// "tables", the rover's defaults); the footprint from DIR/rover_geometry.toml.
// Exit 0 when the ten points were all seen in order, 3 when not.
int Cli::report(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    const std::string tablesDir = takeValue(&words, "--tables").value_or("tables");
    const std::string mapPath = takeValue(&words, "--map").value_or(tablesDir + "/coarse_map.toml");
    const std::string outDir = takeValue(&words, "--out").value_or("build/mission_telemetry");
    std::optional<std::string> name = takeValue(&words, "--name");
    rejectOptions(words, "report");
    if (words.size() != 1) {
        throw UsageError("usage: rse-ground report FILE [--map MAP] [--tables DIR] [--out DIR] [--name TEXT]");
    }
    SessionRecording recording;
    if (!readRecordingFile("report", words[0], &recording)) {
        return kExitLink;
    }
    if (recording.packets.empty()) {
        err_ << "report: '" << words[0] << "' holds no packet\n";
        return kExitLink;
    }
    // The tables, compiled and checked with the flight code (a bad one is a
    // usage error that names the file and the field).
    tables::CoarseMapTable map{};
    tables::RoverGeometryTable geometry{};
    try {
        const std::vector<std::uint8_t> mapImage = readTableFile(mapPath);
        const tables::TableCheck mapCheck = tables::decodeTable(mapImage.data(), mapImage.size(), &map);
        if (!mapCheck.ok()) {
            throw UsageError("report: " + mapPath + " is not a good COARSE_MAP image: " +
                             describeCheck(mapImage.data(), mapImage.size()));
        }
        const std::string geometryPath = tablesDir + "/rover_geometry.toml";
        const std::vector<std::uint8_t> geometryImage = readTableFile(geometryPath);
        if (!tables::decodeTable(geometryImage.data(), geometryImage.size(), &geometry).ok()) {
            throw UsageError("report: " + geometryPath + " is not a good ROVER_GEOMETRY image: " +
                             describeCheck(geometryImage.data(), geometryImage.size()));
        }
    } catch (const TableSourceError& e) {
        throw UsageError(std::string("report: ") + e.what());
    }
    const MissionTelemetry mission = readMissionTelemetry(recording);
    const TelemetryMissionRecord result = missionRecordFromTelemetry(
        recording, mission, map, geometry::clearanceRadiusM(geometry),
        name.value_or(words[0] + " (telemetry received on " + recording.link + ")"));
    for (const MissionPoint& p : result.pointsInOrder) {
        out_ << TenPointTracker::formatPoint(p) << "\n";
    }
    out_ << "outcome:    " << result.record.outcome << "\n";
    out_ << "plans:      " << result.plansDrawn << " drawn from PLAN_PATH (" << mission.plansMade
         << " made, events 902)\n";
    out_ << "points:     " << result.record.verdict << "\n";
    std::string reportPath;
    std::string mapFile;
    std::string error;
    if (!writeMissionFiles(result.record, outDir, &reportPath, &mapFile, &error)) {
        err_ << "report: " << error << "\n";
        return kExitLink;
    }
    out_ << "mission report: " << reportPath << "\nmission map:    " << mapFile << "\n";
    return result.record.allInOrder ? kExitOk : kExitRejected;
}

int Cli::run(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    const bool verbose = takeFlag(&words, "--verbose");
    if (words.size() != 1) {
        throw UsageError("usage: rse-ground run SCRIPT [--verbose]");
    }
    std::ifstream in(words[0]);
    if (!in) {
        throw UsageError("run: cannot read script '" + words[0] + "'");
    }
    const Script script = parseScript(in);
    if (!script.ok()) {
        for (const std::string& e : script.errors) {
            err_ << words[0] << ": " << e << "\n";
        }
        err_ << words[0] << ": " << script.errors.size() << " bad line(s); nothing was sent\n";
        return kExitLink;
    }
    const PacketAuth packetAuth = auth();
    std::unique_ptr<GroundLink> link = openLink(true);
    GroundSession session(*link, store(), packetAuth, g_.timeout);
    ScriptRunner runner(session, out_, err_, verbose);
    return runner.run(script, words[0]);
}

int Cli::table(const std::vector<std::string>& args) {
    if (args.empty()) {
        throw UsageError("table: load, dump, build, show, check or list");
    }
    std::vector<std::string> words(args.begin() + 1, args.end());
    if (args[0] == "load") {
        const bool activate = takeFlag(&words, "--activate");
        const bool force = takeFlag(&words, "--force");
        rejectOptions(words, "table load");
        if (words.size() != 1) {
            throw UsageError("usage: rse-ground table load IMAGE.tbl [--activate] [--force]");
        }
        std::vector<std::uint8_t> image;
        try {
            image = readTableImageFile(words[0]);
        } catch (const std::exception& e) {
            err_ << "table load: " << e.what() << "\n";
            return kExitLink;
        }
        const PacketAuth packetAuth = auth();
        std::unique_ptr<GroundLink> link = openLink(true);
        GroundSession session(*link, store(), packetAuth, g_.timeout);
        return loadTableImage(session, image, activate, force, out_, err_);
    }
    if (args[0] == "dump") {
        const bool inactive = takeFlag(&words, "--inactive");
        const std::string output = takeValue(&words, "-o").value_or("");
        rejectOptions(words, "table dump");
        if (words.size() != 1) {
            throw UsageError("usage: rse-ground table dump ID|NAME [--inactive] [-o FILE]");
        }
        const tables::TableDesc* table = lookupTable(words[0]);
        if (table == nullptr) {
            std::size_t n = 0;
            const tables::TableDesc* all = tables::tableDescs(&n);
            std::string known;
            for (std::size_t i = 0; i < n; ++i) {
                known += (i > 0 ? ", " : "") + std::to_string(static_cast<unsigned>(all[i].id)) + " " + all[i].name;
            }
            throw UsageError("table dump: no table '" + words[0] + "' (tables: " + known + ")");
        }
        const PacketAuth packetAuth = auth();
        std::unique_ptr<GroundLink> link = openLink(true);
        GroundSession session(*link, store(), packetAuth, g_.timeout);
        return dumpTableImage(session, *table, inactive, output, out_, err_);
    }
    // build, show, check, list: the table tool's, with its own argv ("table" first).
    std::vector<std::string> storage(args);
    storage.insert(storage.begin(), "table");
    std::vector<char*> argv;
    for (std::string& s : storage) {
        argv.push_back(s.data());
    }
    argv.push_back(nullptr);
    return runTableCommand(static_cast<int>(storage.size()), argv.data(), out_, err_);
}

// plan load / short / abort over the link; plan check (and usage) is the plan
// tool's. The plan is checked as `plan check` does before the link is opened.
int Cli::plan(const std::vector<std::string>& args) {
    const std::string sub = args.empty() ? std::string() : args[0];
    if (sub != "load" && sub != "short" && sub != "abort") {
        return runPlanCommand(args, out_, err_);
    }
    std::vector<std::string> words(args.begin() + 1, args.end());
    if (sub == "abort") {
        rejectOptions(words, "plan abort");
        if (!words.empty()) {
            throw UsageError("usage: rse-ground plan abort");
        }
        const PacketAuth packetAuth = auth();
        std::unique_ptr<GroundLink> link = openLink(true);
        GroundSession session(*link, store(), packetAuth, g_.timeout);
        return report(session.sendCommand(cmdtlm::describe(cmdtlm::CommandCode::PLAN_ABORT), {}));
    }
    const bool force = takeFlag(&words, "--force");
    plan_executive::SelectionInput components;
    if (const std::optional<std::string> why = takeComponentStates(&words, &components)) {
        throw UsageError("plan " + sub + ": " + *why);
    }
    rejectOptions(words, "plan " + sub);
    if (words.size() != 1) {
        throw UsageError("usage: rse-ground plan " + sub + (sub == "load" ? " FILE" : " TEXT") +
                         " [--failed C,...] [--degraded C,...] [--force]");
    }
    std::string text = words[0];
    if (sub == "load") {
        std::ifstream file(words[0], std::ios::binary);
        if (!file) {
            err_ << "plan load: cannot read '" << words[0] << "'\n";
            return kExitLink;
        }
        text.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    }
    const std::string where = sub == "load" ? words[0] : "plan short";
    if (const int rc = checkPlanForUplink(text, where, sub == "load" ? kPlanUploadBytes : kPlanShortBytes,
                                          components, force, out_, err_)) {
        return rc;
    }
    const PacketAuth packetAuth = auth();
    std::unique_ptr<GroundLink> link = openLink(true);
    GroundSession session(*link, store(), packetAuth, g_.timeout);
    const double verdictSeconds = std::max(g_.timeout, kPlanVerdictSeconds);
    return sub == "load" ? loadPlanText(session, text, verdictSeconds, out_, err_)
                         : sendShortPlan(session, text, verdictSeconds, out_, err_);
}

int Cli::encode(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    const std::optional<std::uint32_t> forced = takeAuthSeq(&words);
    const std::optional<std::string> output = takeValue(&words, "-o");
    if (words.empty()) {
        throw UsageError("usage: rse-ground encode NAME [arg=value ...] [--auth-seq N] [-o FILE]");
    }
    rejectOptions(words, "encode");
    std::vector<std::uint8_t> encoded;
    const cmdtlm::CommandDesc* command = namedCommand(words, &encoded);
    const PacketAuth packetAuth = auth();
    std::uint32_t sequence = 0;
    if (forced) {
        sequence = *forced;
    } else {
        sequence = store().next(packetAuth.keyId);
    }
    const std::vector<std::uint8_t> packet = buildCommandPacket(*command, encoded, packetAuth, sequence);
    if (!output) {
        out_ << hexBytes(packet.data(), packet.size()) << "\n";
        return kExitOk;
    }
    std::ofstream file(*output, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(packet.data()), static_cast<std::streamsize>(packet.size()));
    file.close();
    if (!file) {
        err_ << "encode: cannot write '" << *output << "'\n";
        return kExitLink;
    }
    out_ << "wrote " << *output << ": " << command->name << ", " << packet.size() << " bytes, key id "
         << packetAuth.keyId << ", auth seq " << sequence << "\n";
    return kExitOk;
}

int Cli::dict(const std::vector<std::string>& args) {
    std::vector<std::string> words = args;
    const std::optional<std::string> output = takeValue(&words, "-o");
    if (words.size() != 1 || (words[0] != "--markdown" && words[0] != "--json")) {
        throw UsageError("usage: rse-ground dict --markdown|--json [-o FILE]");
    }
    const std::string text = words[0] == "--markdown" ? exportDictionaryMarkdown() : exportDictionaryJson();
    if (!output) {
        out_ << text;
        return kExitOk;
    }
    std::ofstream file(*output, std::ios::binary | std::ios::trunc);
    file << text;
    file.close();
    if (!file) {
        err_ << "dict: cannot write '" << *output << "'\n";
        return kExitLink;
    }
    return kExitOk;
}

// The mission control server (ground/mission_control/serve_command.hpp) on the
// link `watch` and `record` use.
int Cli::serve(const std::vector<std::string>& args) {
    if (!serveCommand_) {
        throw UsageError("serve is not built into this program (rse-ground has it)");
    }
    return serveCommand_(args, [this] { return openLink(true); }, out_, err_);
}

}  // namespace

int runGroundCli(int argc, char** argv, std::ostream& out, std::ostream& err) {
    return runGroundCli(argc, argv, out, err, LinkFactory(), ServeCommand());
}

int runGroundCli(int argc, char** argv, std::ostream& out, std::ostream& err, const LinkFactory& linkFactory) {
    return runGroundCli(argc, argv, out, err, linkFactory, ServeCommand());
}

int runGroundCli(int argc, char** argv, std::ostream& out, std::ostream& err, const LinkFactory& linkFactory,
                 const ServeCommand& serveCommand) {
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        args.emplace_back(argv[i] != nullptr ? argv[i] : "");
    }
    try {
        GlobalOptions options;
        std::vector<std::string> rest = takeGlobalOptions(args, &options);
        if (rest.empty()) {
            err << kUsage;
            return kExitUsage;
        }
        const std::string command = rest[0];
        const std::vector<std::string> commandArgs(rest.begin() + 1, rest.end());
        if (command == "help" || command == "--help" || command == "-h") {
            out << kUsage;
            return kExitOk;
        }
        Cli cli(options, out, err, linkFactory, serveCommand);
        if (command == "send") {
            return cli.send(commandArgs);
        }
        if (command == "resync") {
            return cli.resync(commandArgs);
        }
        if (command == "watch") {
            return cli.watch(commandArgs);
        }
        if (command == "run") {
            return cli.run(commandArgs);
        }
        if (command == "record") {
            return cli.record(commandArgs);
        }
        if (command == "summary") {
            return cli.summary(commandArgs);
        }
        if (command == "report") {
            return cli.report(commandArgs);
        }
        if (command == "table") {
            return cli.table(commandArgs);
        }
        if (command == "encode") {
            return cli.encode(commandArgs);
        }
        if (command == "dict") {
            return cli.dict(commandArgs);
        }
        if (command == "plan") {
            return cli.plan(commandArgs);
        }
        if (command == "serve") {
            return cli.serve(commandArgs);
        }
        err << "rse-ground: unknown command '" << command << "'\n" << kUsage;
        return kExitUsage;
    } catch (const UsageError& e) {
        err << "rse-ground: " << e.what() << "\n";
        return kExitUsage;
    } catch (const CommandError& e) {
        err << "rse-ground: " << e.what() << "\n";
        return kExitUsage;
    } catch (const KeyFileError& e) {
        err << "rse-ground: " << e.what() << "\n";
        return kExitUsage;
    } catch (const LinkError& e) {
        err << "rse-ground: " << e.what() << "\n";
        return kExitLink;
    } catch (const StateError& e) {
        err << "rse-ground: " << e.what() << "\n";
        return kExitLink;
    } catch (const std::exception& e) {
        err << "rse-ground: " << e.what() << "\n";
        return kExitLink;
    }
}

}  // namespace rse::ground

// rse-ground watch and record: the telemetry of the link of the global options
// as it comes, printed (watch) or written to a session recording with each
// packet's receive time (record; ground/session_recording.hpp).
#include <algorithm>
#include <ctime>
#include <fstream>
#include <optional>
#include <ostream>
#include <set>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/cli_subcommands.hpp"
#include "ground/mission_telemetry.hpp"
#include "ground/session_recording.hpp"
#include "ground/telemetry_decoder.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

constexpr double kSilenceWarningS = 5.0;    // watch: says so once when nothing came in this long
constexpr double kReceiveSliceS = 1.0;      // the longest one wait on the link lasts
constexpr double kDefaultRecordTailS = 5.0;  // record --until-outcome: seconds recorded after the outcome

struct WatchOptions {
    long long count = 0;    // > 0: stop after this many packets shown
    double seconds = 0.0;   // > 0: stop after this long
    std::set<std::string> only;  // packet names shown (empty: all)
};

// --only NAME,...: telemetry packet names, each checked against the dictionary.
std::set<std::string> packetNames(const std::string& list) {
    std::set<std::string> names;
    const std::string text = list + ",";
    for (std::size_t start = 0, comma = text.find(','); comma != std::string::npos;
         start = comma + 1, comma = text.find(',', start)) {
        const std::string name = toUpper(text.substr(start, comma - start));
        if (name.empty()) {
            continue;
        }
        if (cmdtlm::findTelemetry(name.c_str()) == nullptr) {
            throw UsageError("watch --only: unknown telemetry packet '" + name + "'");
        }
        names.insert(name);
    }
    return names;
}

WatchOptions watchOptions(const Words& words) {
    const ParsedOptions parsed =
        parseCliOptions("watch", words, {{"count", 0, true}, {"seconds", 0, true}, {"only", 0, true}});
    WatchOptions w;
    if (const std::optional<std::string> v = parsed.value("--count")) {
        w.count = parseCount("--count", *v, 1, 1LL << 40);
    }
    if (const std::optional<std::string> v = parsed.value("--seconds")) {
        w.seconds = parsePositiveSeconds("--seconds", *v);
    }
    if (const std::optional<std::string> v = parsed.value("--only")) {
        w.only = packetNames(*v);
    }
    if (!parsed.operands.empty()) {
        throw UsageError("watch: unexpected '" + parsed.operands[0] + "'");
    }
    return w;
}

// What watch says when it stopped on time: short of its count, or nothing heard.
int watchEnded(CliContext& cli, const WatchOptions& w, long long shown, bool anything, const GroundLink& link) {
    if (w.count > 0) {
        cli.err() << "watch: " << shown << " of " << w.count << " packets within " << formatNumber(w.seconds)
                  << " s\n";
        return kExitLink;
    }
    if (!anything) {
        cli.err() << "watch: no telemetry within " << formatNumber(w.seconds) << " s on " << link.describe()
                  << ": is rse-fsw running and is the link up?\n";
        return kExitLink;
    }
    return kExitOk;
}

struct RecordOptions {
    std::string path;
    double seconds = 0.0;  // > 0: the longest the recording lasts
    double tail = kDefaultRecordTailS;
    bool untilOutcome = false;
    bool quiet = false;
};

RecordOptions recordOptions(const Words& words) {
    const ParsedOptions parsed = parseCliOptions(
        "record", words,
        {{"seconds", 0, true}, {"until-outcome", 0, false}, {"tail", 0, true}, {"quiet", 0, false}});
    RecordOptions r;
    r.untilOutcome = parsed.has("--until-outcome");
    r.quiet = parsed.has("--quiet");
    if (const std::optional<std::string> v = parsed.value("--seconds")) {
        r.seconds = parsePositiveSeconds("--seconds", *v);
    }
    if (const std::optional<std::string> v = parsed.value("--tail")) {
        r.tail = parsePositiveSeconds("--tail", *v);
    }
    expectOperands(parsed, 1, "record",
                   "usage: rse-ground record FILE [--seconds S] [--until-outcome] [--tail S] [--quiet]");
    if (!r.untilOutcome && r.seconds <= 0.0) {
        throw UsageError("record: give --seconds S, --until-outcome or both (it would never stop)");
    }
    r.path = parsed.operands[0];
    return r;
}

double utcNowSeconds() {
    timespec utc{};
    clock_gettime(CLOCK_REALTIME, &utc);
    return static_cast<double>(utc.tv_sec) + 1e-9 * static_cast<double>(utc.tv_nsec);
}

// One recording: its packets written as they come until the time is up or,
// with --until-outcome, the tail after the mission's outcome has passed.
class Recording {
public:
    Recording(CliContext& cli, const RecordOptions& options, GroundLink& link, std::ostream& file)
        : cli_(cli), options_(options), link_(link), recorder_(file, link.describe(), utcNowSeconds()) {}

    // False (said on err) when writing the file failed.
    bool run() {
        start_ = monotonicSeconds();
        stopAt_ = options_.seconds > 0 ? start_ + options_.seconds : 0.0;
        for (double now = start_; stopAt_ <= 0 || now < stopAt_; now = monotonicSeconds()) {
            const double left = stopAt_ > 0 ? stopAt_ - now : kReceiveSliceS;
            const std::optional<std::vector<std::uint8_t>> bytes = link_.receive(std::min(left, kReceiveSliceS));
            if (bytes && !take(*bytes)) {
                return false;
            }
        }
        return true;
    }
    double start() const { return start_; }
    std::size_t packets() const { return recorder_.packets(); }
    bool outcomeSeen() const { return outcomeSeen_; }

private:
    bool take(const std::vector<std::uint8_t>& bytes) {
        const double at = monotonicSeconds() - start_;
        recorder_.record(at, bytes);
        if (!recorder_.ok()) {
            cli_.err() << "record: writing '" << options_.path << "' failed after " << recorder_.packets()
                       << " packets\n";
            return false;
        }
        const DecodedPacket packet = decodeTelemetry(bytes);
        if (!options_.quiet) {
            cli_.out() << renderPacket(packet) << std::endl;
        }
        reader_.add(at, packet);
        if (options_.untilOutcome && !outcomeSeen_ && reader_.ended()) {
            outcomeSeen_ = true;
            const double tailEnd = monotonicSeconds() + options_.tail;
            stopAt_ = stopAt_ > 0 ? std::min(stopAt_, tailEnd) : tailEnd;
            cli_.out() << "outcome: " << toString(reader_.mission().outcome) << ": recording "
                       << formatNumber(options_.tail) << " s more\n"
                       << std::flush;
        }
        return true;
    }

    CliContext& cli_;
    const RecordOptions& options_;
    GroundLink& link_;
    SessionRecorder recorder_;
    MissionTelemetryReader reader_;
    double start_ = 0.0;
    double stopAt_ = 0.0;  // 0: not yet known (--until-outcome without --seconds)
    bool outcomeSeen_ = false;
};

}  // namespace

int runWatch(CliContext& cli, const Words& words) {
    const WatchOptions w = watchOptions(words);
    std::unique_ptr<GroundLink> link = cli.openLink(true);
    cli.out() << "watching " << link->describe()
              << (w.seconds > 0 ? " for " + formatNumber(w.seconds) + " s" : "") << "\n"
              << std::flush;
    const double start = monotonicSeconds();
    const double deadline = w.seconds > 0 ? start + w.seconds : 0.0;
    long long shown = 0;
    bool anything = false;
    bool warned = false;
    // Without --seconds it watches until stopped (Ctrl-C) or --count is reached.
    for (double now = start; w.seconds <= 0 || now < deadline; now = monotonicSeconds()) {
        const double slice = w.seconds > 0 ? deadline - now : kReceiveSliceS;
        const std::optional<std::vector<std::uint8_t>> bytes = link->receive(std::min(slice, kReceiveSliceS));
        if (!bytes) {
            if (!anything && !warned && monotonicSeconds() - start >= kSilenceWarningS) {
                cli.err() << "watch: nothing received in 5 s on " << link->describe()
                          << ": is rse-fsw running and sending telemetry here?\n";
                warned = true;
            }
            continue;
        }
        anything = true;
        const DecodedPacket packet = decodeTelemetry(*bytes);
        if (!w.only.empty() && (!packet.ok || w.only.count(packet.name()) == 0)) {
            continue;
        }
        cli.out() << renderPacket(packet) << std::endl;
        if (w.count > 0 && ++shown >= w.count) {
            return kExitOk;
        }
    }
    return watchEnded(cli, w, shown, anything, *link);
}

// A session recorder: every packet received goes to the file as it comes
// (ground/session_recording.hpp). --until-outcome stops once the telemetry
// shows the mission's outcome (ground/mission_telemetry.hpp), --tail seconds
// later so the events that follow it arrive; --seconds bounds the whole
// recording.
int runRecord(CliContext& cli, const Words& words) {
    const RecordOptions options = recordOptions(words);
    std::ofstream file(options.path, std::ios::trunc);
    if (!file) {
        cli.err() << "record: cannot write '" << options.path << "'\n";
        return kExitLink;
    }
    std::unique_ptr<GroundLink> link = cli.openLink(true);
    Recording recording(cli, options, *link, file);
    cli.out() << "recording " << link->describe() << " to " << options.path
              << (options.seconds > 0 ? " for at most " + formatNumber(options.seconds) + " s" : "")
              << (options.untilOutcome ? " until the mission's outcome" : "") << "\n"
              << std::flush;
    if (!recording.run()) {
        return kExitLink;
    }
    cli.out() << "recorded " << recording.packets() << " packets in "
              << formatNumber(monotonicSeconds() - recording.start()) << " s to " << options.path << "\n";
    if (recording.packets() == 0) {
        cli.err() << "record: no telemetry on " << link->describe()
                  << ": is rse-fsw running, and has it heard this ground (over CAN it sends only after a command)?\n";
        return kExitLink;
    }
    if (options.untilOutcome && !recording.outcomeSeen()) {
        cli.err() << "record: no outcome within " << formatNumber(options.seconds) << " s\n";
        return kExitLink;
    }
    return kExitOk;
}

}  // namespace rse::ground

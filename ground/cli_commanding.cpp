// rse-ground send, resync, run, encode and dict: commands by their dictionary
// names, signed with the key of the global options; every argument checked
// before the link is opened (docs/ground.md).
#include <algorithm>
#include <fstream>
#include <optional>
#include <ostream>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/cli_subcommands.hpp"
#include "ground/command_encoder.hpp"
#include "ground/dictionary_export.hpp"
#include "ground/script_runner.hpp"
#include "ground/telemetry_decoder.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

constexpr double kHkWaitSeconds = 3.0;  // resync waits at least this long for an HK (it comes once a second)

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

// --auth-seq N: the anti-replay number to use instead of the store's next.
std::optional<std::uint32_t> forcedSequence(const ParsedOptions& parsed) {
    const std::optional<std::string> text = parsed.value("--auth-seq");
    if (!text) {
        return std::nullopt;
    }
    return static_cast<std::uint32_t>(parseCount("--auth-seq", *text, 0, 0xFFFFFFFFLL));
}

// The rover's next HK on link, waited for until seconds have passed.
std::optional<DecodedPacket> nextHousekeeping(GroundLink& link, double seconds) {
    const double deadline = monotonicSeconds() + seconds;
    for (double left = seconds; left > 0.0; left = deadline - monotonicSeconds()) {
        std::optional<std::vector<std::uint8_t>> bytes = link.receive(left);
        if (bytes) {
            DecodedPacket packet = decodeTelemetry(*bytes);
            if (packet.ok && std::string(packet.name()) == "HK") {
                return packet;
            }
        }
    }
    return std::nullopt;
}

bool writeFile(const std::string& path, const char* data, std::size_t size) {
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    file.write(data, static_cast<std::streamsize>(size));
    file.close();
    return static_cast<bool>(file);
}

}  // namespace

int runSend(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("send", words, {{"auth-seq", 0, true}, {"no-wait", 0, false}});
    const bool noWait = parsed.has("--no-wait");
    const std::optional<std::uint32_t> forced = forcedSequence(parsed);
    if (parsed.operands.empty()) {
        throw UsageError("send: which command? (rse-ground dict --markdown lists them)");
    }
    // Every argument is checked before the link is even opened.
    std::vector<std::uint8_t> encoded;
    const cmdtlm::CommandDesc* command = namedCommand(parsed.operands, &encoded);
    const PacketAuth packetAuth = cli.auth();
    std::unique_ptr<GroundLink> link = cli.openLink(!noWait);
    GroundSession session(*link, cli.store(), packetAuth, cli.options().timeout);
    return cli.reportAck(session.sendCommand(*command, encoded, forced, !noWait));
}

// The two steps of docs/ground.md's re-synchronisation in one: the nonce from
// the rover's next HK (1 Hz), then AUTH_RESYNC carrying it, signed with this
// ground's next number (above every number it has used, which the rover takes
// as the key's new floor). Nothing is sent before the nonce is known.
int runResync(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("resync", words, {{"auth-seq", 0, true}});
    const std::optional<std::uint32_t> forced = forcedSequence(parsed);
    expectOperands(parsed, 0, "resync", "usage: rse-ground resync [--auth-seq N]");
    if (cli.options().noAuth) {
        throw UsageError("resync: AUTH_RESYNC re-synchronises a key: it cannot be sent with --no-auth");
    }
    const PacketAuth packetAuth = cli.auth();
    std::unique_ptr<GroundLink> link = cli.openLink(true);
    const double wait = std::max(cli.options().timeout, kHkWaitSeconds);
    const std::optional<DecodedPacket> hk = nextHousekeeping(*link, wait);
    if (!hk) {
        cli.err() << "rse-ground: resync: no HK within " << formatNumber(wait) << " s on " << link->describe()
                  << ": is rse-fsw running and sending telemetry here?\n";
        return kExitLink;
    }
    const std::optional<double> highField = hk->value("auth_challenge_high");
    const std::optional<double> lowField = hk->value("auth_challenge_low");
    if (!highField || !lowField) {
        cli.err() << "rse-ground: resync: the rover's HK has no auth_challenge_high/low (a rover without "
                     "AUTH_RESYNC?): nothing sent\n";
        return kExitLink;
    }
    const auto high = static_cast<std::uint32_t>(*highField);
    const auto low = static_cast<std::uint32_t>(*lowField);
    cli.out() << "rover nonce " << high << ":" << low << " (auth_store_state "
              << formatNumber(hk->value("auth_store_state").value_or(-1)) << ", keys unsynchronised "
              << formatNumber(hk->value("auth_keys_unsynced").value_or(-1)) << ")\n";
    std::vector<std::uint8_t> encoded;
    const cmdtlm::CommandDesc* command = namedCommand(
        {"AUTH_RESYNC", "challenge_high=" + std::to_string(high), "challenge_low=" + std::to_string(low)}, &encoded);
    GroundSession session(*link, cli.store(), packetAuth, cli.options().timeout);
    return cli.reportAck(session.sendCommand(*command, encoded, forced, true));
}

// A command script (docs/ground.md): checked whole before anything is sent.
int runScript(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("run", words, {{"verbose", 0, false}});
    expectOperands(parsed, 1, "run", "usage: rse-ground run SCRIPT [--verbose]");
    const std::string& path = parsed.operands[0];
    std::ifstream in(path);
    if (!in) {
        throw UsageError("run: cannot read script '" + path + "'");
    }
    const Script script = parseScript(in);
    if (!script.ok()) {
        for (const std::string& e : script.errors) {
            cli.err() << path << ": " << e << "\n";
        }
        cli.err() << path << ": " << script.errors.size() << " bad line(s); nothing was sent\n";
        return kExitLink;
    }
    CliContext::Session s = cli.openSession();
    ScriptRunner runner(*s.session, cli.out(), cli.err(), parsed.has("--verbose"));
    return runner.run(script, path);
}

// A command packet to a file (or as hex), signed with the next number of the
// store unless --auth-seq says which.
int runEncode(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("encode", words, {{"auth-seq", 0, true}, {nullptr, 'o', true}});
    const std::optional<std::uint32_t> forced = forcedSequence(parsed);
    const std::optional<std::string> output = parsed.value("-o");
    if (parsed.operands.empty()) {
        throw UsageError("encode: which command? (usage: rse-ground encode NAME [arg=value ...] [--auth-seq N] "
                         "[-o FILE])");
    }
    std::vector<std::uint8_t> encoded;
    const cmdtlm::CommandDesc* command = namedCommand(parsed.operands, &encoded);
    const PacketAuth packetAuth = cli.auth();
    const std::uint32_t sequence = forced ? *forced : cli.store().next(packetAuth.keyId);
    const std::vector<std::uint8_t> packet = buildCommandPacket(*command, encoded, packetAuth, sequence);
    if (!output) {
        cli.out() << hexBytes(packet.data(), packet.size()) << "\n";
        return kExitOk;
    }
    if (!writeFile(*output, reinterpret_cast<const char*>(packet.data()), packet.size())) {
        cli.err() << "encode: cannot write '" << *output << "'\n";
        return kExitLink;
    }
    cli.out() << "wrote " << *output << ": " << command->name << ", " << packet.size() << " bytes, key id "
              << packetAuth.keyId << ", auth seq " << sequence << "\n";
    return kExitOk;
}

// The command and telemetry dictionary as Markdown or JSON (docs/dictionary.md, .json).
int runDict(CliContext& cli, const Words& words) {
    const ParsedOptions parsed =
        parseCliOptions("dict", words, {{"markdown", 0, false}, {"json", 0, false}, {nullptr, 'o', true}});
    const std::string usage = "usage: rse-ground dict --markdown|--json [-o FILE]";
    expectOperands(parsed, 0, "dict", usage);
    const bool markdown = parsed.has("--markdown");
    if (markdown == parsed.has("--json")) {
        throw UsageError(markdown ? "dict: --markdown or --json, not both" : "dict: --markdown or --json? (" + usage + ")");
    }
    const std::string text = markdown ? exportDictionaryMarkdown() : exportDictionaryJson();
    const std::optional<std::string> output = parsed.value("-o");
    if (!output) {
        cli.out() << text;
        return kExitOk;
    }
    if (!writeFile(*output, text.data(), text.size())) {
        cli.err() << "dict: cannot write '" << *output << "'\n";
        return kExitLink;
    }
    return kExitOk;
}

}  // namespace rse::ground

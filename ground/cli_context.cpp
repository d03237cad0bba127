#include "ground/cli_context.hpp"

#include <ostream>

#include "fsw/cmdtlm/anti_replay_state.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "ground/key_file.hpp"

namespace rse::ground {

GlobalOptions globalOptionsFrom(const ParsedOptions& parsed) {
    GlobalOptions g;
    for (const auto& [option, value] : parsed.given) {
        if (option == "--udp") {
            g.udp = value;
        } else if (option == "--tlm-port") {
            g.tlm = value;
        } else if (option == "--can") {
            g.can = value;
        } else if (option == "--can-tx") {
            g.canTx = parseCanId(option, value);
        } else if (option == "--can-rx") {
            g.canRx = parseCanId(option, value);
        } else if (option == "--pad") {
            g.pad = true;
        } else if (option == "--key-file") {
            g.keyFile = value;
        } else if (option == "--key-id") {
            g.keyId = static_cast<std::uint16_t>(parseCount(option, value, 1, 65535));
        } else if (option == "--no-auth") {
            g.noAuth = true;
        } else if (option == "--state-dir") {
            g.stateDir = value;
        } else if (option == "--timeout") {
            g.timeout = parsePositiveSeconds(option, value);
        }
    }
    return g;
}

CliContext::CliContext(GlobalOptions options, std::ostream& out, std::ostream& err, const LinkFactory& linkFactory,
                       const ServeCommand& serveCommand)
    : g_(std::move(options)), out_(out), err_(err), linkFactory_(linkFactory), serveCommand_(serveCommand) {}

PacketAuth CliContext::auth() {
    if (g_.noAuth) {
        if (!g_.keyFile.empty() || g_.keyId) {
            throw UsageError("--no-auth cannot be combined with --key-file or --key-id");
        }
        return PacketAuth{};
    }
    PacketAuth a = loadPacketAuth(g_.keyFile, g_.keyId);
    if (g_.keyFile.empty()) {
        err_ << "rse-ground: signing with the built-in lab key (id 1): lab rovers only, never flight\n";
        return a;
    }
    if (a.key.size() == cmdtlm::kKeySize && cmdtlm::isLabKey(a.key.data())) {
        // The lab key's bytes under any key id are still the public lab key.
        err_ << "rse-ground: key id " << a.keyId << " of " << g_.keyFile
             << " is the public lab key: lab rovers only, never flight\n";
    }
    if (keyFileTooOpen(g_.keyFile)) {
        err_ << "rse-ground: warning: " << g_.keyFile << " is readable by others (chmod 600 it)\n";
    }
    return a;
}

SequenceStore& CliContext::store() {
    if (!store_) {
        store_ = std::make_unique<SequenceStore>(g_.stateDir.empty() ? SequenceStore::defaultDirectory()
                                                                     : g_.stateDir);
    }
    return *store_;
}

std::unique_ptr<GroundLink> CliContext::openLink(bool listen) {
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

CliContext::Session CliContext::openSession() {
    const PacketAuth packetAuth = auth();
    Session s;
    s.link = openLink(true);
    s.session = std::make_unique<GroundSession>(*s.link, store(), packetAuth, g_.timeout);
    return s;
}

int CliContext::reportAck(const AckResult& result) {
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

// A stale or replayed number: where this ground's numbers come from, and the
// number a restarted rover takes.
void CliContext::replayHint() {
    const std::uint16_t key = g_.noAuth ? 0 : (g_.keyId ? *g_.keyId : 1);
    err_ << "hint: the rover has seen this anti-replay number (or newer ones) for key " << key
         << "; numbers come from " << store().directory()
         << " (another ground station, or a reset state directory?); --auth-seq N jumps ahead\n";
    const std::uint64_t after = std::uint64_t{store().last(key)} + cmdtlm::kReserveBlock + 1;
    if (after <= cmdtlm::kMaxUsableSequence) {
        err_ << "hint: after a rover restart every number up to its stored reservation is refused, at most "
             << cmdtlm::kReserveBlock << " above the last one it accepted: --auth-seq " << after << "\n";
    }
}

void CliContext::hint(const AckResult& result) {
    using cmdtlm::CommandReject;
    switch (static_cast<CommandReject>(result.reason)) {
        case CommandReject::kStaleSequence:
        case CommandReject::kReplayedSequence:
            replayHint();
            break;
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

}  // namespace rse::ground

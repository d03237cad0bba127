// What every rse-ground sub-command works with: the global options (the link,
// the key, the anti-replay state, the acknowledgement timeout), the output
// streams, the link opened on demand, and the acknowledgement of a command
// printed with the hint that goes with its rejection (docs/ground.md).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ground/cli_options.hpp"
#include "ground/ground_cli.hpp"
#include "ground/ground_link.hpp"
#include "ground/ground_session.hpp"
#include "ground/sequence_store.hpp"

namespace rse::ground {

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

// The global options of a parse of globalCliOptions() (values checked: UsageError).
GlobalOptions globalOptionsFrom(const ParsedOptions& parsed);

class CliContext {
public:
    CliContext(GlobalOptions options, std::ostream& out, std::ostream& err, const LinkFactory& linkFactory,
               const ServeCommand& serveCommand);

    const GlobalOptions& options() const { return g_; }
    std::ostream& out() { return out_; }
    std::ostream& err() { return err_; }
    const ServeCommand& serveCommand() const { return serveCommand_; }

    // The key commands are signed with (warnings about a lab key or an open key
    // file on err); UsageError for --no-auth with a key file or key id.
    PacketAuth auth();
    // The anti-replay numbers, from --state-dir (opened on first use).
    SequenceStore& store();
    // The link of the global options, or the factory's; listen: telemetry wanted.
    std::unique_ptr<GroundLink> openLink(bool listen);
    // A signed session on a new listening link: what every command that waits for its acknowledgement uses.
    struct Session {
        std::unique_ptr<GroundLink> link;
        std::unique_ptr<GroundSession> session;
    };
    Session openSession();
    // A command's acknowledgement printed (with the hint a rejection calls for)
    // and the exit code it means.
    int reportAck(const AckResult& result);

private:
    void hint(const AckResult& result);
    void replayHint();

    GlobalOptions g_;
    std::ostream& out_;
    std::ostream& err_;
    std::unique_ptr<SequenceStore> store_;
    const LinkFactory& linkFactory_;
    const ServeCommand& serveCommand_;
};

}  // namespace rse::ground

// rse-ground's entry: the global options (getopt_long, up to the first operand:
// the sub-command), the sub-command called with the words after it, and every
// error turned into its exit code (ground/ground_cli.hpp). The sub-commands live
// in ground/cli_*.cpp (ground/cli_subcommands.hpp), the usage text and the option
// parsing in ground/cli_options.cpp.
#include "ground/ground_cli.hpp"

#include <ostream>
#include <string>
#include <vector>

#include "ground/cli_context.hpp"
#include "ground/cli_options.hpp"
#include "ground/cli_subcommands.hpp"
#include "ground/command_encoder.hpp"
#include "ground/key_file.hpp"
#include "ground/sequence_store.hpp"

namespace rse::ground {
namespace {

// The mission control server (ground/mission_control/serve_command.hpp) on the
// link `watch` and `record` use.
int runServeCommand(CliContext& cli, const Words& words) {
    if (!cli.serveCommand()) {
        throw UsageError("serve is not built into this program (rse-ground has it)");
    }
    return cli.serveCommand()(words, [&cli] { return cli.openLink(true); }, cli.out(), cli.err());
}

struct SubCommand {
    const char* name;
    int (*run)(CliContext& cli, const Words& words);
};

constexpr SubCommand kSubCommands[] = {
    {"send", runSend},       {"resync", runResync}, {"watch", runWatch},   {"run", runScript},
    {"record", runRecord},   {"summary", runSummary}, {"report", runReport}, {"table", runTable},
    {"encode", runEncode},   {"dict", runDict},     {"plan", runPlan},     {"serve", runServeCommand},
    {"map", runMap},
};

std::string commandNames() {
    std::string names;
    for (const SubCommand& c : kSubCommands) {
        names += (names.empty() ? "" : ", ") + std::string(c.name);
    }
    return names;
}

// The global options, then the sub-command with the words after it.
int dispatch(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
             const LinkFactory& linkFactory, const ServeCommand& serveCommand) {
    const ParsedOptions global = parseCliOptions("", args, globalCliOptions(), OperandOrder::kOptionsFirst);
    GlobalOptions options = globalOptionsFrom(global);
    if (global.operands.empty()) {
        throw UsageError("which command? (usage: rse-ground [global options] COMMAND ...; commands: " +
                         commandNames() + ")");
    }
    const std::string& command = global.operands[0];
    const Words words(global.operands.begin() + 1, global.operands.end());
    if (command == "help") {
        throw HelpRequested{};
    }
    for (const SubCommand& c : kSubCommands) {
        if (command == c.name) {
            CliContext cli(std::move(options), out, err, linkFactory, serveCommand);
            return c.run(cli, words);
        }
    }
    throw UsageError("unknown command '" + command + "' (commands: " + commandNames() + ")");
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
        return dispatch(args, out, err, linkFactory, serveCommand);
    } catch (const HelpRequested&) {
        out << groundUsage();
        return kExitOk;
    } catch (const UsageError& e) {
        return reportUsageError(err, e.what());
    } catch (const CommandError& e) {
        // A command argument the dictionary refuses: a bad command line too.
        return reportUsageError(err, e.what());
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

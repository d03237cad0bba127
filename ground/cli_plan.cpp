// rse-ground plan: load, short and abort over the link (ground/plan_transfer.hpp),
// each plan checked first as `plan check` checks it; plan check itself is the
// plan tool's (ground/plan_tool.hpp).
#include <algorithm>
#include <fstream>
#include <iterator>
#include <ostream>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/cli_subcommands.hpp"
#include "ground/plan_tool.hpp"
#include "ground/plan_transfer.hpp"

namespace rse::ground {
namespace {

int abortPlan(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("plan abort", words, {});
    expectOperands(parsed, 0, "plan abort", "usage: rse-ground plan abort");
    CliContext::Session s = cli.openSession();
    return cli.reportAck(s.session->sendCommand(cmdtlm::describe(cmdtlm::CommandCode::PLAN_ABORT), {}));
}

// plan load FILE / plan short TEXT: the plan checked under the component
// states given (refused unless --force), then sent and its verdict awaited.
int uplinkPlan(CliContext& cli, const std::string& sub, const Words& words) {
    const bool load = sub == "load";
    std::vector<CliOption> options = componentStateOptions();
    options.push_back({"force", 0, false});
    const ParsedOptions parsed = parseCliOptions("plan " + sub, words, options);
    plan_executive::SelectionInput components;
    if (const std::optional<std::string> why = applyComponentStates(parsed, &components)) {
        throw UsageError("plan " + sub + ": " + *why);
    }
    expectOperands(parsed, 1, "plan " + sub,
                   "usage: rse-ground plan " + sub + (load ? " FILE" : " TEXT") +
                       " [--failed C,...] [--degraded C,...] [--force]");
    std::string text = parsed.operands[0];
    if (load) {
        std::ifstream file(parsed.operands[0], std::ios::binary);
        if (!file) {
            cli.err() << "plan load: cannot read '" << parsed.operands[0] << "'\n";
            return kExitLink;
        }
        text.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    }
    const std::string where = load ? parsed.operands[0] : "plan short";
    if (const int rc = checkPlanForUplink(text, where, load ? kPlanUploadBytes : kPlanShortBytes, components,
                                          parsed.has("--force"), cli.out(), cli.err())) {
        return rc;
    }
    CliContext::Session s = cli.openSession();
    const double verdictSeconds = std::max(cli.options().timeout, kPlanVerdictSeconds);
    return load ? loadPlanText(*s.session, text, verdictSeconds, cli.out(), cli.err())
                : sendShortPlan(*s.session, text, verdictSeconds, cli.out(), cli.err());
}

}  // namespace

int runPlan(CliContext& cli, const Words& words) {
    const std::string sub = words.empty() ? std::string() : words[0];
    const Words rest(words.begin() + (words.empty() ? 0 : 1), words.end());
    if (sub == "abort") {
        return abortPlan(cli, rest);
    }
    if (sub == "load" || sub == "short") {
        return uplinkPlan(cli, sub, rest);
    }
    if (sub == "check") {
        return runPlanCommand(words, cli.out(), cli.err());
    }
    throw UsageError(sub.empty() ? "plan: check, load, short or abort"
                                 : "plan: unknown sub-command '" + sub + "' (check, load, short or abort)");
}

}  // namespace rse::ground

// rse-ground map: check a site map image with the flight check, load it over
// the link (MAP_LOAD chunks, MAP_COMMIT), abort an upload
// (ground/map_transfer.hpp, docs/site_map.md).
#include <fstream>
#include <iterator>
#include <ostream>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/cli_subcommands.hpp"
#include "ground/map_transfer.hpp"

namespace rse::ground {
namespace {

bool readImage(const std::string& path, std::vector<std::uint8_t>* image) {
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        return false;
    }
    image->assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    return true;
}

int checkOrLoad(CliContext& cli, const std::string& sub, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("map " + sub, words, {});
    expectOperands(parsed, 1, "map " + sub, "usage: rse-ground map " + sub + " IMAGE");
    std::vector<std::uint8_t> image;
    if (!readImage(parsed.operands[0], &image)) {
        cli.err() << "map " << sub << ": cannot read '" << parsed.operands[0] << "'\n";
        return kExitLink;
    }
    // The ground checks first what the rover will check: a bad image is not sent.
    if (const int rc = checkSiteMapFile(image, parsed.operands[0], cli.out(), cli.err())) {
        return rc;
    }
    if (sub == "check") {
        return 0;
    }
    CliContext::Session s = cli.openSession();
    return loadSiteMap(*s.session, image, cli.out(), cli.err());
}

int abortMap(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("map abort", words, {});
    expectOperands(parsed, 0, "map abort", "usage: rse-ground map abort");
    CliContext::Session s = cli.openSession();
    return cli.reportAck(s.session->sendCommand(cmdtlm::describe(cmdtlm::CommandCode::MAP_ABORT), {}));
}

}  // namespace

int runMap(CliContext& cli, const Words& words) {
    const std::string sub = words.empty() ? std::string() : words[0];
    const Words rest(words.begin() + (words.empty() ? 0 : 1), words.end());
    if (sub == "check" || sub == "load") {
        return checkOrLoad(cli, sub, rest);
    }
    if (sub == "abort") {
        return abortMap(cli, rest);
    }
    throw UsageError(sub.empty() ? "map: check, load or abort"
                                 : "map: unknown sub-command '" + sub + "' (check, load or abort)");
}

}  // namespace rse::ground

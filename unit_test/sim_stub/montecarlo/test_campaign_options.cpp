// rse-montecarlo's command line (sim_stub/montecarlo/campaign_options.hpp):
// the commands and their options, operands before and after the options,
// --help before or after the command, and the bad command lines named in one
// line (docs/operations.md, "Command lines").
#include <string>
#include <vector>

#include "sim_stub/montecarlo/campaign_options.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim::mc;

namespace {

CampaignParse parse(std::vector<const char*> args, CampaignArgs* a, std::string* error) {
    args.insert(args.begin(), "rse-montecarlo");
    return parseCampaignArgs(static_cast<int>(args.size()), args.data(), a, error);
}

}  // namespace

TEST_GROUP(CampaignOptions) {
    CampaignArgs a;
    std::string error;
};

TEST(CampaignOptions, RunTakesItsOptionsAndTheMissionsInRseDemosWords) {
    CHECK(CampaignParse::kRun == parse({"run", "--seeds", "5:10", "--jobs=3", "--out", "r.txt", "--table", "t.txt",
                                        "--no-faults", "--goto", "4,0", "--duration", "60", "--scenario", "s.toml"},
                                       &a, &error));
    CHECK(CampaignCommand::kRun == a.command);
    LONGS_EQUAL(5, a.first);
    LONGS_EQUAL(10, a.count);
    CHECK_TRUE(a.seedsGiven);
    LONGS_EQUAL(3, a.jobs);
    STRCMP_EQUAL("r.txt", a.out.c_str());
    STRCMP_EQUAL("t.txt", a.table.c_str());
    const std::vector<std::string> mission = {"--no-faults", "--goto", "4,0", "--duration", "60", "--scenario",
                                              "s.toml"};
    CHECK_TRUE(mission == a.mission);
}

TEST(CampaignOptions, TheDefaultsAreTwoHundredSeedsFromOne) {
    CHECK(CampaignParse::kRun == parse({"run"}, &a, &error));
    LONGS_EQUAL(1, a.first);
    LONGS_EQUAL(200, a.count);
    CHECK_FALSE(a.seedsGiven);
    LONGS_EQUAL(0, a.jobs);
    LONGS_EQUAL(-1, a.task);
}

TEST(CampaignOptions, MergeTakesFilesAmongItsOptionsAndSeedItsNumber) {
    CHECK(CampaignParse::kRun == parse({"merge", "a.txt", "--table", "t.txt", "dir", "--out", "m.txt"}, &a, &error));
    CHECK(CampaignCommand::kMerge == a.command);
    const std::vector<std::string> inputs = {"a.txt", "dir"};
    CHECK_TRUE(inputs == a.inputs);
    STRCMP_EQUAL("t.txt", a.table.c_str());
    CampaignArgs s;
    CHECK(CampaignParse::kRun == parse({"seed", "17", "--console"}, &s, &error));
    CHECK(CampaignCommand::kSeed == s.command);
    LONGS_EQUAL(17, s.seed);
    CHECK_TRUE(s.console);
}

TEST(CampaignOptions, BlockNeedsItsSeedsBlockSizeAndOut) {
    CHECK(CampaignParse::kRun ==
          parse({"block", "--seeds", "1:100", "--block-size", "25", "--task", "3", "--out", "dir"}, &a, &error));
    CHECK(CampaignCommand::kBlock == a.command);
    LONGS_EQUAL(25, a.blockSize);
    LONGS_EQUAL(3, a.task);
    CampaignArgs b;
    CHECK(CampaignParse::kUsageError == parse({"block", "--seeds", "1:100", "--out", "dir"}, &b, &error));
    STRCMP_EQUAL("block: --seeds, --block-size and --out are needed", error.c_str());
}

TEST(CampaignOptions, HelpBeforeOrAfterTheCommand) {
    CHECK(CampaignParse::kHelp == parse({"--help"}, &a, &error));
    CHECK(CampaignParse::kHelp == parse({"-h"}, &a, &error));
    CHECK(CampaignParse::kHelp == parse({"help"}, &a, &error));
    CHECK(CampaignParse::kHelp == parse({"run", "--seeds", "1:2", "--help"}, &a, &error));
}

TEST(CampaignOptions, BadCommandLinesSayWhatIsWrong) {
    const struct {
        std::vector<const char*> args;
        const char* error;
    } bad[] = {
        {{}, "no command (run, block, merge or seed)"},
        {{"fly"}, "unknown command 'fly' (run, block, merge or seed)"},
        {{"--jobs", "2", "run"}, "unknown or incomplete option '--jobs'"},
        {{"run", "--fast"}, "unknown or incomplete option '--fast'"},
        {{"run", "--seeds"}, "option '--seeds' needs a value"},
        {{"run", "--seeds", "5"}, "--seeds '5': expected FIRST:COUNT, COUNT > 0"},
        {{"run", "--seeds", "5:0"}, "--seeds '5:0': expected FIRST:COUNT, COUNT > 0"},
        {{"run", "--jobs", "0"}, "--jobs '0': 1..1024"},
        {{"run", "--jobs", "2x"}, "--jobs '2x': 1..1024"},
        {{"run", "--block-size", "0"}, "--block-size '0': a count > 0"},
        {{"run", "--task", "-1"}, "--task '-1': an array index"},
        {{"run", "extra"}, "run: unexpected argument 'extra'"},
        {{"seed"}, "seed: one seed number"},
        {{"seed", "1", "2"}, "seed: one seed number"},
        {{"seed", "x"}, "seed: one seed number"},
    };
    for (const auto& b : bad) {
        CampaignArgs fresh;
        error.clear();
        if (parse(b.args, &fresh, &error) != CampaignParse::kUsageError) {
            FAIL((std::string("accepted; expected: ") + b.error).c_str());
        }
        STRCMP_EQUAL(b.error, error.c_str());
    }
}

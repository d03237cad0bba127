// rse-fsw's command line (fsw/app/fsw_options.hpp): every option parsed into
// FswOptions, --help, and a bad command line refused with one line naming the
// option and the value (docs/operations.md, "Command lines"); no heap used.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "fsw/app/fsw_options.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using rse::app::FswCommandLine;
using rse::app::FswOptions;

namespace {

// argv for one parse: the program name, then args (kept alive while it lives).
struct CommandLine {
    explicit CommandLine(std::vector<std::string> args) : words(std::move(args)) {
        words.insert(words.begin(), "rse-fsw");
        for (std::string& w : words) {
            argv.push_back(&w[0]);
        }
        argv.push_back(nullptr);
    }
    FswCommandLine parse() {
        return rse::app::parseFswOptions(static_cast<int>(words.size()), argv.data(), &options, why, sizeof why);
    }
    std::vector<std::string> words;
    std::vector<char*> argv;
    FswOptions options;
    char why[320] = "";
};

bool contains(const char* text, const char* part) { return std::strstr(text, part) != nullptr; }

// Parses args expecting a bad command line; the reason given.
std::string refused(std::vector<std::string> args) {
    CommandLine c(std::move(args));
    const FswCommandLine result = c.parse();
    CHECK_TEXT(result == FswCommandLine::kBad, c.words[1].c_str());
    CHECK_TEXT(std::strchr(c.why, '\n') == nullptr, c.why);  // one line
    return c.why;
}

}  // namespace

TEST_GROUP(FswOptions){};

TEST(FswOptions, DefaultsWithTheLabKey) {
    CommandLine c({"--lab-key"});
    CHECK_TRUE(c.parse() == FswCommandLine::kRun);
    const FswOptions& o = c.options;
    CHECK_FALSE(o.lockstep);
    CHECK_TRUE(o.realtimePosture);
    CHECK_TRUE(o.authRequired);
    CHECK_TRUE(o.keyOptions.labKeyAllowed);
    CHECK_TRUE(o.canInterface == nullptr);
    STRCMP_EQUAL("127.0.0.1", o.udpBind);
    LONGS_EQUAL(1234, o.commandPort);
    LONGS_EQUAL(1235, o.telemetryPort);
    STRCMP_EQUAL("rse-fsw-auth.dat", o.authStore);
    LONGS_EQUAL(30, o.watchdogTimeoutS);
    LONGS_EQUAL(0, o.timeScale);
    LONGS_EQUAL(-1, o.spinMarginUs);
    CHECK_EQUAL(0.0, o.durationSec);
}

TEST(FswOptions, EveryOptionIsParsed) {
    CommandLine c({"--can", "vcan0", "--duration", "2.5", "--quiet", "--no-rt", "--udp", "--udp-bind", "0.0.0.0",
                   "--cmd-port", "2000", "--tlm-host", "10.0.0.2", "--tlm-port=2001", "--key-file", "k.keys",
                   "--allow-readable-key", "--allow-weak-key", "--lab-key", "--lab-no-auth", "--watchdog",
                   "/dev/watchdog", "--watchdog-timeout", "60", "--auth-store", "a.dat", "--auth-store-create",
                   "--auth-store-sync", "--time-scale", "1", "--spin-margin-us", "300"});
    CHECK_TEXT(c.parse() == FswCommandLine::kRun, c.why);
    const FswOptions& o = c.options;
    STRCMP_EQUAL("vcan0", o.canInterface);
    CHECK_EQUAL(2.5, o.durationSec);
    CHECK_TRUE(o.quiet);
    CHECK_FALSE(o.realtimePosture);
    CHECK_TRUE(o.udp);
    STRCMP_EQUAL("0.0.0.0", o.udpBind);
    LONGS_EQUAL(2000, o.commandPort);
    STRCMP_EQUAL("10.0.0.2", o.telemetryHost);
    LONGS_EQUAL(2001, o.telemetryPort);
    STRCMP_EQUAL("k.keys", o.keyFile);
    CHECK_TRUE(o.keyOptions.readableFileAllowed);
    CHECK_TRUE(o.keyOptions.weakKeyAllowed);
    CHECK_TRUE(o.keyOptions.labKeyAllowed);
    CHECK_FALSE(o.authRequired);
    STRCMP_EQUAL("/dev/watchdog", o.watchdogDevice);
    LONGS_EQUAL(60, o.watchdogTimeoutS);
    STRCMP_EQUAL("a.dat", o.authStore);
    CHECK_TRUE(o.authStoreCreate);
    CHECK_TRUE(o.authStoreSync);
    LONGS_EQUAL(1, o.timeScale);
    LONGS_EQUAL(300, o.spinMarginUs);
}

TEST(FswOptions, LockstepWithADuration) {
    CommandLine c({"--lockstep", "--duration", "5", "--lab-key"});
    CHECK_TRUE(c.parse() == FswCommandLine::kRun);
    CHECK_TRUE(c.options.lockstep);
    CHECK_EQUAL(5.0, c.options.durationSec);
}

TEST(FswOptions, HelpWinsWhereverItStands) {
    CHECK_TRUE(CommandLine({"--help"}).parse() == FswCommandLine::kHelp);
    CHECK_TRUE(CommandLine({"-h"}).parse() == FswCommandLine::kHelp);
    CHECK_TRUE(CommandLine({"--lab-key", "--help", "--bogus"}).parse() == FswCommandLine::kHelp);
}

TEST(FswOptions, UnknownOptionsAndArgumentsAreNamed) {
    STRCMP_EQUAL("unknown option '--no-such-option'", refused({"--no-such-option"}).c_str());
    STRCMP_EQUAL("unknown option '--bogus'", refused({"--lab-key", "--bogus=3"}).c_str());
    STRCMP_EQUAL("unknown option '-x'", refused({"-x"}).c_str());
    STRCMP_EQUAL("option '--udp' takes no value", refused({"--udp=1", "--lab-key"}).c_str());
    CHECK_TRUE(contains(refused({"--lab-key", "run"}).c_str(), "unexpected argument 'run'"));
}

// getopt_long takes a unique abbreviation of a long option (--dur 5), but not of
// one that weakens command authentication: a typo must not switch it off.
TEST(FswOptions, OptionsThatWeakenAuthenticationMustBeWrittenInFull) {
    STRCMP_EQUAL("'--lab-n' must be written in full as '--lab-no-auth' (it weakens command authentication)",
                 refused({"--lab-key", "--lab-n"}).c_str());
    CHECK_TRUE(contains(refused({"--lab-k"}).c_str(), "as '--lab-key'"));
    CHECK_TRUE(contains(refused({"--key-file", "k", "--allow-r"}).c_str(), "as '--allow-readable-key'"));
    CHECK_TRUE(contains(refused({"--key-file", "k", "--allow-w"}).c_str(), "as '--allow-weak-key'"));
    CHECK_TRUE(contains(refused({"--lab-key", "--auth-store-c"}).c_str(), "as '--auth-store-create'"));
    CommandLine full({"--lab-key", "--lab-no-auth", "--auth-store-create", "--dur", "5"});
    CHECK_TRUE(full.parse() == FswCommandLine::kRun);
    CHECK_TRUE(full.options.keyOptions.labKeyAllowed);
    DOUBLES_EQUAL(5.0, full.options.durationSec, 0.0);
}

TEST(FswOptions, MissingValuesSayWhatIsNeeded) {
    STRCMP_EQUAL("--can needs an interface name", refused({"--lab-key", "--can"}).c_str());
    STRCMP_EQUAL("--duration needs a number of seconds in (0, 1e7]", refused({"--duration"}).c_str());
    STRCMP_EQUAL("--key-file needs a value", refused({"--key-file"}).c_str());
    STRCMP_EQUAL("--time-scale needs a whole factor 1..100", refused({"--lab-key", "--time-scale"}).c_str());
    STRCMP_EQUAL("--auth-store needs a path of 1..240 characters", refused({"--auth-store"}).c_str());
}

TEST(FswOptions, NumbersAreWholeAndInRange) {
    STRCMP_EQUAL("--duration needs a number of seconds in (0, 1e7], not '-3'",
                 refused({"--duration", "-3", "--lab-key"}).c_str());
    for (const char* bad : {"0", "x", "1e8", "inf", "nan", " 1", "1s", ""}) {
        CHECK_TRUE(contains(refused({"--duration", bad, "--lab-key"}).c_str(), "--duration needs"));
    }
    for (const char* bad : {"0", "101", "x", "-2", "1.5", "", " 3"}) {
        CHECK_TRUE(contains(refused({"--time-scale", bad, "--lab-key"}).c_str(), "--time-scale needs a whole factor 1..100"));
    }
    for (const char* bad : {"-1", "2001", "abc", "10x", ""}) {
        CHECK_TRUE(contains(refused({"--spin-margin-us", bad, "--lab-key"}).c_str(),
                            "--spin-margin-us needs whole microseconds 0..2000"));
    }
    STRCMP_EQUAL("--cmd-port needs a port number 1..65535, not '0'", refused({"--cmd-port", "0", "--lab-key"}).c_str());
    STRCMP_EQUAL("--tlm-port needs a port number 1..65535, not '65536'",
                 refused({"--tlm-port", "65536", "--lab-key"}).c_str());
    STRCMP_EQUAL("--watchdog-timeout needs a number of seconds 1..3600, not '3601'",
                 refused({"--watchdog-timeout", "3601", "--lab-key"}).c_str());
    STRCMP_EQUAL("--auth-store needs a path of 1..240 characters, not one of 0",
                 refused({"--auth-store", "", "--lab-key"}).c_str());
    CHECK_TRUE(contains(refused({"--auth-store", std::string(241, 'a'), "--lab-key"}).c_str(), "not one of 241"));
}

TEST(FswOptions, ConflictsAndMissingKeysAreRefused) {
    CHECK_TRUE(contains(refused({"--lockstep", "--lab-key"}).c_str(), "--lockstep needs --duration"));
    CHECK_TRUE(contains(refused({"--lockstep", "--duration", "1", "--can", "vcan0", "--lab-key"}).c_str(),
                        "cannot use a real CAN interface"));
    CHECK_TRUE(contains(refused({"--lockstep", "--duration", "1", "--watchdog", "/dev/null", "--lab-key"}).c_str(),
                        "a watchdog would time out"));
    CHECK_TRUE(contains(refused({"--lockstep", "--duration", "1", "--time-scale", "2", "--lab-key"}).c_str(),
                        "--lockstep has none"));
    CHECK_TRUE(contains(refused({"--lockstep", "--duration", "1", "--spin-margin-us", "0", "--lab-key"}).c_str(),
                        "--spin-margin-us shapes real-time waits"));
    CHECK_TRUE(contains(refused({"--time-scale", "2", "--watchdog", "/dev/null", "--lab-key"}).c_str(),
                        "a watchdog counts real seconds"));
    CHECK_TRUE(contains(refused({"--duration", "1"}).c_str(), "no command key: give --key-file FILE, or --lab-key"));
    CHECK_TRUE(contains(refused({"--allow-weak-key", "--lab-key"}).c_str(), "need --key-file"));
}

// Parsing comes before initialisation, but the flight rule holds anyway.
TEST(FswOptions, ParsingUsesNoHeap) {
    CommandLine good({"--lockstep", "--duration", "3", "--key-file", "k.keys", "--tlm-port", "4000"});
    CommandLine bad({"--duration", "1", "--bogus"});
    rse::test::AllocationWatch watch;
    CHECK_TRUE(good.parse() == FswCommandLine::kRun);
    CHECK_TRUE(bad.parse() == FswCommandLine::kBad);
    LONGS_EQUAL(0, watch.count());
}

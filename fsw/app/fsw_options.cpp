#include "fsw/app/fsw_options.hpp"

#include <getopt.h>

#include <cctype>
#include <cerrno>
#include <cstdarg>
#include <cstdlib>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "hal/nvm/file_record_store.hpp"

namespace rse::app {
namespace {

// getopt_long's val for each long option: -h is the only short one.
enum OptionKey : int {
    kHelp = 'h',
    kCan = 256,
    kLockstep,
    kDuration,
    kQuiet,
    kNoRt,
    kUdp,
    kUdpBind,
    kCmdPort,
    kTlmHost,
    kTlmPort,
    kKeyFile,
    kAllowReadableKey,
    kAllowWeakKey,
    kLabKey,
    kLabNoAuth,
    kWatchdog,
    kWatchdogTimeout,
    kAuthStore,
    kAuthStoreCreate,
    kAuthStoreSync,
    kTimeScale,
    kSpinMarginUs,
};

// Leading ':': a missing value comes back as ':' (not '?'), so it is told apart
// from an unknown option.
constexpr const char* kShortOptions = ":h";

const option kLongOptions[] = {
    {"help", no_argument, nullptr, kHelp},
    {"can", required_argument, nullptr, kCan},
    {"lockstep", no_argument, nullptr, kLockstep},
    {"duration", required_argument, nullptr, kDuration},
    {"quiet", no_argument, nullptr, kQuiet},
    {"no-rt", no_argument, nullptr, kNoRt},
    {"udp", no_argument, nullptr, kUdp},
    {"udp-bind", required_argument, nullptr, kUdpBind},
    {"cmd-port", required_argument, nullptr, kCmdPort},
    {"tlm-host", required_argument, nullptr, kTlmHost},
    {"tlm-port", required_argument, nullptr, kTlmPort},
    {"key-file", required_argument, nullptr, kKeyFile},
    {"allow-readable-key", no_argument, nullptr, kAllowReadableKey},
    {"allow-weak-key", no_argument, nullptr, kAllowWeakKey},
    {"lab-key", no_argument, nullptr, kLabKey},
    {"lab-no-auth", no_argument, nullptr, kLabNoAuth},
    {"watchdog", required_argument, nullptr, kWatchdog},
    {"watchdog-timeout", required_argument, nullptr, kWatchdogTimeout},
    {"auth-store", required_argument, nullptr, kAuthStore},
    {"auth-store-create", no_argument, nullptr, kAuthStoreCreate},
    {"auth-store-sync", no_argument, nullptr, kAuthStoreSync},
    {"time-scale", required_argument, nullptr, kTimeScale},
    {"spin-margin-us", required_argument, nullptr, kSpinMarginUs},
    {nullptr, 0, nullptr, 0},
};

constexpr long kMaxSpinMarginUs = static_cast<long>(core::MonotonicClock::kMaxSpinMargin / core::kNsPerUs);

// One parse: the options being filled and where the reason for a refusal goes.
struct Parse {
    FswOptions* options;
    char* why;
    std::size_t whySize;
};

// Writes the reason into p.why; returns false so a check can `return say(...)`.
__attribute__((format(printf, 2, 3))) bool say(const Parse& p, const char* format, ...) {
    std::va_list args;
    va_start(args, format);
    (void)std::vsnprintf(p.why, p.whySize, format, args);
    va_end(args);
    return false;
}

// "OPTION needs WHAT", and the value refused when one was given (nullptr: none).
bool needs(const Parse& p, const char* option, const char* what, const char* value) {
    return value == nullptr ? say(p, "%s needs %s", option, what) : say(p, "%s needs %s, not '%s'", option, what, value);
}

// The whole text a decimal whole number in [min, max] (no sign but '-', no blanks).
bool parseWhole(const char* text, long min, long max, long* out) {
    if (text == nullptr || !(std::isdigit(static_cast<unsigned char>(text[0])) != 0 || text[0] == '-')) {
        return false;
    }
    errno = 0;
    char* end = nullptr;
    const long value = std::strtol(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0' || value < min || value > max) {
        return false;
    }
    *out = value;
    return true;
}

// The whole text a finite number of seconds in (0, 1e7].
bool parseDuration(const char* text, double* out) {
    if (text == nullptr || text[0] == '\0' || std::isspace(static_cast<unsigned char>(text[0])) != 0) {
        return false;
    }
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end == text || *end != '\0' || !(value > 0.0) || value > 1.0e7) {
        return false;
    }
    *out = value;
    return true;
}

// An option without a value; false when key is not one.
bool applyFlag(int key, FswOptions* o) {
    switch (key) {
        case kLockstep: o->lockstep = true; return true;
        case kQuiet: o->quiet = true; return true;
        case kNoRt: o->realtimePosture = false; return true;
        case kUdp: o->udp = true; return true;
        case kLabNoAuth: o->authRequired = false; return true;
        case kAuthStoreCreate: o->authStoreCreate = true; return true;
        case kAuthStoreSync: o->authStoreSync = true; return true;
        case kLabKey: o->keyOptions.labKeyAllowed = true; return true;
        case kAllowWeakKey: o->keyOptions.weakKeyAllowed = true; return true;
        case kAllowReadableKey: o->keyOptions.readableFileAllowed = true; return true;
        default: return false;
    }
}

// The long option whose val is key ("" for none).
const char* optionName(int key) {
    for (const option& o : kLongOptions) {
        if (o.name != nullptr && o.val == key) {
            return o.name;
        }
    }
    return "";
}

// An option taking a name or a path (value nullptr: the value is missing).
bool applyText(const Parse& p, int key, const char* value) {
    FswOptions* o = p.options;
    if (key == kAuthStore) {
        // FileRecordStore holds the path in a fixed buffer.
        const std::size_t length = value == nullptr ? 0 : std::strlen(value);
        if (value == nullptr) {
            return say(p, "--auth-store needs a path of 1..%zu characters", hal::FileRecordStore::kMaxPath);
        }
        if (length == 0 || length > hal::FileRecordStore::kMaxPath) {
            return say(p, "--auth-store needs a path of 1..%zu characters, not one of %zu",
                       hal::FileRecordStore::kMaxPath, length);
        }
        o->authStore = value;
        return true;
    }
    if (value == nullptr) {
        return key == kCan ? say(p, "--can needs an interface name") : say(p, "--%s needs a value", optionName(key));
    }
    switch (key) {
        case kCan: o->canInterface = value; break;
        case kUdpBind: o->udpBind = value; break;
        case kTlmHost: o->telemetryHost = value; break;
        case kKeyFile: o->keyFile = value; break;
        default: o->watchdogDevice = value; break;
    }
    return true;
}

// An option taking a number (value nullptr: the value is missing).
bool applyNumber(const Parse& p, int key, const char* value) {
    FswOptions* o = p.options;
    long n = 0;
    char what[64];
    switch (key) {
        case kDuration:
            return parseDuration(value, &o->durationSec) ||
                   needs(p, "--duration", "a number of seconds in (0, 1e7]", value);
        case kWatchdogTimeout:
            if (!parseWhole(value, 1, 3600, &n)) {
                return needs(p, "--watchdog-timeout", "a number of seconds 1..3600", value);
            }
            o->watchdogTimeoutS = static_cast<int>(n);
            return true;
        case kTimeScale:
            if (!parseWhole(value, 1, static_cast<long>(core::ScaledMonotonicClock::kMaxFactor), &n)) {
                std::snprintf(what, sizeof what, "a whole factor 1..%u",
                              static_cast<unsigned>(core::ScaledMonotonicClock::kMaxFactor));
                return needs(p, "--time-scale", what, value);
            }
            o->timeScale = static_cast<std::uint32_t>(n);
            return true;
        case kSpinMarginUs:
            if (!parseWhole(value, 0, kMaxSpinMarginUs, &n)) {
                std::snprintf(what, sizeof what, "whole microseconds 0..%ld", kMaxSpinMarginUs);
                return needs(p, "--spin-margin-us", what, value);
            }
            o->spinMarginUs = n;
            return true;
        default: break;
    }
    if (!parseWhole(value, 1, 65535, &n)) {
        return needs(p, key == kCmdPort ? "--cmd-port" : "--tlm-port", "a port number 1..65535", value);
    }
    (key == kCmdPort ? o->commandPort : o->telemetryPort) = static_cast<std::uint16_t>(n);
    return true;
}

bool applyValue(const Parse& p, int key, const char* value) {
    switch (key) {
        case kCan:
        case kUdpBind:
        case kTlmHost:
        case kKeyFile:
        case kWatchdog:
        case kAuthStore: return applyText(p, key, value);
        default: return applyNumber(p, key, value);
    }
}

// Options that cannot go together, and what must be given.
bool checkCombination(const Parse& p) {
    const FswOptions& o = *p.options;
    if (o.lockstep && o.canInterface != nullptr) {
        return say(p, "--lockstep runs on a virtual clock and cannot use a real CAN interface");
    }
    if (o.lockstep && o.watchdogDevice != nullptr) {
        return say(p, "--lockstep runs on a virtual clock: a watchdog would time out on real time");
    }
    if (o.lockstep && o.timeScale != 0) {
        return say(p, "--time-scale slows the real-time clock: --lockstep has none");
    }
    if (o.lockstep && o.spinMarginUs >= 0) {
        return say(p, "--spin-margin-us shapes real-time waits: --lockstep has none");
    }
    if (o.timeScale > 1 && o.watchdogDevice != nullptr) {
        return say(p, "--time-scale is for the lab: a watchdog counts real seconds and would time out on a slowed "
                      "timeline");
    }
    if (o.lockstep && o.durationSec <= 0.0) {
        return say(p, "--lockstep needs --duration (it would never yield)");
    }
    if (o.keyFile == nullptr && !o.keyOptions.labKeyAllowed) {
        return say(p, "no command key: give --key-file FILE, or --lab-key to use the public lab key (lab only, never "
                      "flight)");
    }
    if (o.keyFile == nullptr && (o.keyOptions.weakKeyAllowed || o.keyOptions.readableFileAllowed)) {
        return say(p, "--allow-weak-key and --allow-readable-key need --key-file");
    }
    return true;
}

// The option getopt_long refused, as the user wrote it: a long one without its
// "=value" (named as taking none when it is known), a short one as "-c".
void sayRefused(const Parse& p, char** argv) {
    const char* written = optind > 0 ? argv[optind - 1] : "";
    if (std::strncmp(written, "--", 2) != 0) {
        (void)say(p, "unknown option '-%c'", optopt != 0 ? static_cast<char>(optopt) : '?');
        return;
    }
    const int length = static_cast<int>(std::strcspn(written, "="));
    if (optopt >= kCan && written[length] == '=') {
        (void)say(p, "option '%.*s' takes no value", length, written);
    } else {
        (void)say(p, "unknown option '%.*s'", length, written);
    }
}

// The options that weaken command authentication (the public lab key, no
// authentication, a weak or readable key file, a new anti-replay store) are
// taken only when written in full: getopt_long would take an abbreviation
// ("--lab-n"), and a typo must not switch security off.
bool weakensSecurity(int key) {
    return key == kLabKey || key == kLabNoAuth || key == kAllowWeakKey || key == kAllowReadableKey ||
           key == kAuthStoreCreate;
}

bool writtenInFull(const Parse& p, int key, char** argv) {
    const char* written = optind > 0 ? argv[optind - 1] : "";
    const char* name = optionName(key);
    if (std::strncmp(written, "--", 2) == 0 && std::strcmp(written + 2, name) == 0) {
        return true;
    }
    return say(p, "'%s' must be written in full as '--%s' (it weakens command authentication)", written, name);
}

}  // namespace

FswCommandLine parseFswOptions(int argc, char** argv, FswOptions* options, char* why, std::size_t whySize) {
    const Parse p{options, why, whySize};
    why[0] = '\0';
    opterr = 0;  // the messages are ours
    optind = 0;  // glibc: start afresh (a second parse in the same process, as the unit tests do)
    // Bounded: each pass consumes at least one argv element.
    for (int pass = 0; pass <= argc; ++pass) {
        const int key = getopt_long(argc, argv, kShortOptions, kLongOptions, nullptr);
        if (key == -1) {
            break;
        }
        if (key == kHelp) {
            return FswCommandLine::kHelp;
        }
        if (key == ':' && optopt >= kCan) {  // a long option without its value
            (void)applyValue(p, optopt, nullptr);
            return FswCommandLine::kBad;
        }
        if (key == '?' || key == ':') {
            sayRefused(p, argv);
            return FswCommandLine::kBad;
        }
        if (weakensSecurity(key) && !writtenInFull(p, key, argv)) {
            return FswCommandLine::kBad;
        }
        if (!applyFlag(key, options) && !applyValue(p, key, optarg)) {
            return FswCommandLine::kBad;
        }
    }
    if (optind < argc) {
        (void)say(p, "unexpected argument '%s' (rse-fsw takes options only)", argv[optind]);
        return FswCommandLine::kBad;
    }
    return checkCombination(p) ? FswCommandLine::kRun : FswCommandLine::kBad;
}

void printFswUsage(std::FILE* out) {
    std::fprintf(out,
                 "usage: rse-fsw [--can IFACE] [--lockstep] [--duration SECONDS] [--quiet] [--no-rt]\n"
                 "               [--udp] [--udp-bind ADDR] [--cmd-port N] [--tlm-host ADDR] [--tlm-port N]\n"
                 "               (--key-file FILE [--allow-readable-key] [--allow-weak-key] | --lab-key)\n"
                 "               [--lab-no-auth] [--watchdog DEV] [--watchdog-timeout S]\n"
                 "               [--auth-store PATH] [--auth-store-create] [--auth-store-sync]\n"
                 "               [--time-scale N] [--spin-margin-us N] [--help]\n"
                 "  --can IFACE         SocketCAN interface of the rover bus (default: none attached);\n"
                 "                      the ground link runs over ISO-TP on it (rx 0x6C0, tx 0x6C1)\n"
                 "  --lockstep          virtual clock, as fast as possible (needs --duration)\n"
                 "  --duration SECONDS  stop after this much executive time (default: until SIGINT/SIGTERM)\n"
                 "  --quiet             no console housekeeping or event lines\n"
                 "  --no-rt             real time without mlockall/SCHED_FIFO\n"
                 "  --udp               add the UDP ground link\n"
                 "  --udp-bind ADDR     address the command port binds to (default 127.0.0.1)\n"
                 "  --cmd-port N        UDP command port (default 1234)\n"
                 "  --tlm-host ADDR     where UDP telemetry goes (default 127.0.0.1)\n"
                 "  --tlm-port N        UDP telemetry port (default 1235)\n"
                 "  --key-file FILE     command authentication keys, lines ID:64-hex-digits (chmod 600);\n"
                 "                      rse-fsw does not start without one unless --lab-key is given\n"
                 "  --allow-readable-key  load a key file group or others may read or write (warns)\n"
                 "  --allow-weak-key    load weak keys (all zero, all equal, < 8 distinct bytes; warns)\n"
                 "  --lab-key           use the PUBLIC lab key (id 1 without a key file; with one, the\n"
                 "                      file may hold it): lab only, never flight (warns)\n"
                 "  --lab-no-auth       lab setting: also accept unauthenticated commands\n"
                 "  --auth-store PATH   where the anti-replay reservations persist (default rse-fsw-auth.dat);\n"
                 "                      missing or corrupt: commands refused until AUTH_RESYNC\n"
                 "  --auth-store-create first boot: create a missing store (floor 0) and add loaded keys it lacks;\n"
                 "                      never touches a corrupt store or a stored reservation\n"
                 "  --auth-store-sync   write reservations inside the command task, without the writer thread\n"
                 "                      (emulators whose threads do not run, e.g. qemu-user 7.2 here); a write\n"
                 "                      then takes 0.7-5 ms of that task's 2 ms budget\n"
                 "  --watchdog DEV      arm the Linux watchdog DEV (/dev/watchdog) and feed it while every task is live;\n"
                 "                      a hung rse-fsw then restarts the computer (a clean stop disarms it)\n"
                 "  --watchdog-timeout S  watchdog timeout asked for, 1..3600 s (default 30)\n"
                 "  --time-scale N      lab only: mission time runs N times slower than CLOCK_MONOTONIC (1..%u;\n"
                 "                      1 = real time), for a machine too slow for 100 Hz (the qemu VM); give\n"
                 "                      rse-sim the same N. Frame periods, timeouts, budgets and --duration are\n"
                 "                      in mission time; HK.time_scale says N\n"
                 "  --spin-margin-us N  real time: sleep to N us before each frame start and spin the rest\n"
                 "                      (0..%ld; default 0 = sleep only): frame starts on time despite the\n"
                 "                      kernel's timer wake-up latency, for up to N us of CPU a frame\n"
                 "  -h, --help          this text\n"
                 "exit: 0 after a clean stop (or --help), 1 if initialisation failed, 2 for a bad command line\n",
                 static_cast<unsigned>(core::ScaledMonotonicClock::kMaxFactor), kMaxSpinMarginUs);
}

}  // namespace rse::app

// rse-fsw: the flight executable.
//
//   rse-fsw [--can IFACE] [--lockstep] [--duration SECONDS] [--quiet] [--no-rt]
//           [--udp] [--udp-bind ADDR] [--cmd-port N] [--tlm-host ADDR] [--tlm-port N]
//           (--key-file FILE [--allow-readable-key] [--allow-weak-key] | --lab-key)
//           [--lab-no-auth] [--watchdog DEV] [--watchdog-timeout S]
//           [--auth-store PATH] [--auth-store-create] [--auth-store-sync]
//           [--time-scale N] [--spin-margin-us N]
//
// --can IFACE opens that SocketCAN interface (can0, vcan0, ...) as the rover bus;
// without it the flight software runs on an in-memory bus with nothing attached.
// The ground link always runs over ISO-TP on the rover bus; --udp adds the UDP
// link (commands on ADDR:1234, telemetry to 127.0.0.1:1235 by default: the cFS
// lab ports). Commands must be authenticated with a key from --key-file (lines
// "ID:64-hex-digits"; the file must not be open to group or others and may hold
// neither a weak key nor the public lab key, unless an option says so). Without
// a key file rse-fsw does not start, unless --lab-key asks for the public lab
// key (lab only: it warns, and HK.lab_key_in_use says so). --lab-no-auth also
// accepts unauthenticated commands (docs/icd.md §5.3).
// The anti-replay state persists in --auth-store PATH (default rse-fsw-auth.dat
// in the working directory); a missing or corrupt store refuses commands until
// the ground re-synchronises (AUTH_RESYNC), except that --auth-store-create
// creates a missing one at floor 0 (first boot).
// Real-time mode (default) runs on CLOCK_MONOTONIC until SIGINT/SIGTERM or the
// duration; lockstep mode runs the same tasks on a virtual clock as fast as the
// CPU allows (a duration is then required). --time-scale N (lab only) slows
// the real-time timeline N times (core::ScaledMonotonicClock): for a machine
// too slow for the rover's 100 Hz, with rse-sim --time-scale N on the same bus.
// --spin-margin-us N makes real-time waits hybrid (core::MonotonicClock): sleep
// to N us before the frame start, spin the rest (docs/performance.md, "Frame-start
// jitter"; 0, the default, sleeps only).
// Exit status: 0 after a clean stop,
// 1 if initialisation failed, 2 for a bad command line.
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fsw/app/fsw_app.hpp"
#include "fsw/cmdtlm/key_loader.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/realtime_process.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/can/socketcan_bus.hpp"
#include "hal/link/udp_packet_link.hpp"
#include "hal/nvm/file_record_store.hpp"
#include "hal/nvm/threaded_record_writer.hpp"
#include "hal/watchdog/watchdog_device.hpp"

namespace {

volatile std::sig_atomic_t g_stopRequested = 0;

// Only sets a flag: the executive checks it once per frame.
void onStopSignal(int) { g_stopRequested = 1; }

struct Options {
    bool lockstep = false;
    bool quiet = false;
    bool realtimePosture = true;
    double durationSec = 0.0;  // 0: until a signal
    const char* canInterface = nullptr;
    bool udp = false;
    const char* udpBind = "127.0.0.1";
    std::uint16_t commandPort = rse::hal::kDefaultCommandPort;
    const char* telemetryHost = "127.0.0.1";
    std::uint16_t telemetryPort = rse::hal::kDefaultTelemetryPort;
    const char* keyFile = nullptr;
    rse::cmdtlm::KeyLoadOptions keyOptions;  // --lab-key, --allow-weak-key, --allow-readable-key
    bool authRequired = true;
    const char* authStore = "rse-fsw-auth.dat";
    bool authStoreCreate = false;
    bool authStoreSync = false;
    const char* watchdogDevice = nullptr;
    int watchdogTimeoutS = 30;
    std::uint32_t timeScale = 0;  // 0: not given (CLOCK_MONOTONIC as it is)
    long spinMarginUs = -1;       // -1: not given (sleep only)
};

void usage(std::FILE* out) {
    std::fprintf(out,
                 "usage: rse-fsw [--can IFACE] [--lockstep] [--duration SECONDS] [--quiet] [--no-rt]\n"
                 "               [--udp] [--udp-bind ADDR] [--cmd-port N] [--tlm-host ADDR] [--tlm-port N]\n"
                 "               (--key-file FILE [--allow-readable-key] [--allow-weak-key] | --lab-key)\n"
                 "               [--lab-no-auth] [--watchdog DEV] [--watchdog-timeout S]\n"
                 "               [--auth-store PATH] [--auth-store-create] [--auth-store-sync]\n"
                 "               [--time-scale N] [--spin-margin-us N]\n"
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
                 "                      (0..%lld; default 0 = sleep only): frame starts on time despite the\n"
                 "                      kernel's timer wake-up latency, for up to N us of CPU a frame\n",
                 static_cast<unsigned>(rse::core::ScaledMonotonicClock::kMaxFactor),
                 static_cast<long long>(rse::core::MonotonicClock::kMaxSpinMargin / rse::core::kNsPerUs));
}

// Returns false (after printing why) on a bad command line.
bool parseOptions(int argc, char** argv, Options* options) {
    for (int i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        if (std::strcmp(arg, "--lockstep") == 0) {
            options->lockstep = true;
        } else if (std::strcmp(arg, "--quiet") == 0) {
            options->quiet = true;
        } else if (std::strcmp(arg, "--no-rt") == 0) {
            options->realtimePosture = false;
        } else if (std::strcmp(arg, "--can") == 0) {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "rse-fsw: --can needs an interface name\n");
                return false;
            }
            options->canInterface = argv[++i];
        } else if (std::strcmp(arg, "--duration") == 0) {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "rse-fsw: --duration needs a number of seconds\n");
                return false;
            }
            char* end = nullptr;
            const double value = std::strtod(argv[++i], &end);
            if (end == argv[i] || *end != '\0' || !(value > 0.0) || value > 1.0e7) {
                std::fprintf(stderr, "rse-fsw: --duration '%s' is not a number of seconds in (0, 1e7]\n",
                             argv[i]);
                return false;
            }
            options->durationSec = value;
        } else if (std::strcmp(arg, "--udp") == 0) {
            options->udp = true;
        } else if (std::strcmp(arg, "--lab-no-auth") == 0) {
            options->authRequired = false;
        } else if (std::strcmp(arg, "--auth-store-create") == 0) {
            options->authStoreCreate = true;
        } else if (std::strcmp(arg, "--auth-store-sync") == 0) {
            options->authStoreSync = true;
        } else if (std::strcmp(arg, "--lab-key") == 0) {
            options->keyOptions.labKeyAllowed = true;
        } else if (std::strcmp(arg, "--allow-weak-key") == 0) {
            options->keyOptions.weakKeyAllowed = true;
        } else if (std::strcmp(arg, "--allow-readable-key") == 0) {
            options->keyOptions.readableFileAllowed = true;
        } else if (std::strcmp(arg, "--udp-bind") == 0 || std::strcmp(arg, "--tlm-host") == 0 ||
                   std::strcmp(arg, "--key-file") == 0 || std::strcmp(arg, "--watchdog") == 0 ||
                   std::strcmp(arg, "--auth-store") == 0) {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "rse-fsw: %s needs a value\n", arg);
                return false;
            }
            const char* value = argv[++i];
            if (std::strcmp(arg, "--udp-bind") == 0) {
                options->udpBind = value;
            } else if (std::strcmp(arg, "--tlm-host") == 0) {
                options->telemetryHost = value;
            } else if (std::strcmp(arg, "--watchdog") == 0) {
                options->watchdogDevice = value;
            } else if (std::strcmp(arg, "--auth-store") == 0) {
                if (value[0] == '\0' || std::strlen(value) > rse::hal::FileRecordStore::kMaxPath) {
                    std::fprintf(stderr, "rse-fsw: --auth-store needs a path of 1..%zu characters\n",
                                 rse::hal::FileRecordStore::kMaxPath);
                    return false;
                }
                options->authStore = value;
            } else {
                options->keyFile = value;
            }
        } else if (std::strcmp(arg, "--watchdog-timeout") == 0) {
            char* end = nullptr;
            const long seconds = i + 1 < argc ? std::strtol(argv[i + 1], &end, 10) : 0;
            if (i + 1 >= argc || end == argv[i + 1] || *end != '\0' || seconds < 1 || seconds > 3600) {
                std::fprintf(stderr, "rse-fsw: --watchdog-timeout needs a number of seconds 1..3600\n");
                return false;
            }
            ++i;
            options->watchdogTimeoutS = static_cast<int>(seconds);
        } else if (std::strcmp(arg, "--time-scale") == 0) {
            char* end = nullptr;
            const unsigned long factor = i + 1 < argc ? std::strtoul(argv[i + 1], &end, 10) : 0;
            if (i + 1 >= argc || end == argv[i + 1] || *end != '\0' || argv[i + 1][0] == '-' || factor < 1 ||
                factor > rse::core::ScaledMonotonicClock::kMaxFactor) {
                std::fprintf(stderr, "rse-fsw: --time-scale needs a whole factor 1..%u\n",
                             static_cast<unsigned>(rse::core::ScaledMonotonicClock::kMaxFactor));
                return false;
            }
            ++i;
            options->timeScale = static_cast<std::uint32_t>(factor);
        } else if (std::strcmp(arg, "--spin-margin-us") == 0) {
            char* end = nullptr;
            const long maxUs = static_cast<long>(rse::core::MonotonicClock::kMaxSpinMargin / rse::core::kNsPerUs);
            const long us = i + 1 < argc ? std::strtol(argv[i + 1], &end, 10) : -1;
            if (i + 1 >= argc || end == argv[i + 1] || *end != '\0' || us < 0 || us > maxUs) {
                std::fprintf(stderr, "rse-fsw: --spin-margin-us needs whole microseconds 0..%ld\n", maxUs);
                return false;
            }
            ++i;
            options->spinMarginUs = us;
        } else if (std::strcmp(arg, "--cmd-port") == 0 || std::strcmp(arg, "--tlm-port") == 0) {
            char* end = nullptr;
            const unsigned long port = i + 1 < argc ? std::strtoul(argv[i + 1], &end, 10) : 0;
            if (i + 1 >= argc || end == argv[i + 1] || *end != '\0' || port == 0 || port > 65535) {
                std::fprintf(stderr, "rse-fsw: %s needs a port number 1..65535\n", arg);
                return false;
            }
            ++i;
            (std::strcmp(arg, "--cmd-port") == 0 ? options->commandPort : options->telemetryPort) =
                static_cast<std::uint16_t>(port);
        } else if (std::strcmp(arg, "--help") == 0 || std::strcmp(arg, "-h") == 0) {
            usage(stdout);
            std::exit(0);
        } else {
            std::fprintf(stderr, "rse-fsw: unknown option '%s'\n", arg);
            return false;
        }
    }
    if (options->lockstep && options->canInterface != nullptr) {
        std::fprintf(stderr, "rse-fsw: --lockstep runs on a virtual clock and cannot use a real CAN interface\n");
        return false;
    }
    if (options->lockstep && options->watchdogDevice != nullptr) {
        std::fprintf(stderr, "rse-fsw: --lockstep runs on a virtual clock: a watchdog would time out on real time\n");
        return false;
    }
    if (options->lockstep && options->timeScale != 0) {
        std::fprintf(stderr, "rse-fsw: --time-scale slows the real-time clock: --lockstep has none\n");
        return false;
    }
    if (options->lockstep && options->spinMarginUs >= 0) {
        std::fprintf(stderr, "rse-fsw: --spin-margin-us shapes real-time waits: --lockstep has none\n");
        return false;
    }
    if (options->timeScale > 1 && options->watchdogDevice != nullptr) {
        std::fprintf(stderr, "rse-fsw: --time-scale is for the lab: a watchdog counts real seconds and would "
                             "time out on a slowed timeline\n");
        return false;
    }
    if (options->lockstep && options->durationSec <= 0.0) {
        std::fprintf(stderr, "rse-fsw: --lockstep needs --duration (it would never yield)\n");
        return false;
    }
    if (options->keyFile == nullptr && !options->keyOptions.labKeyAllowed) {
        std::fprintf(stderr,
                     "rse-fsw: no command key: give --key-file FILE, or --lab-key to use the public lab key "
                     "(lab only, never flight)\n");
        return false;
    }
    if (options->keyFile == nullptr &&
        (options->keyOptions.weakKeyAllowed || options->keyOptions.readableFileAllowed)) {
        std::fprintf(stderr, "rse-fsw: --allow-weak-key and --allow-readable-key need --key-file\n");
        return false;
    }
    return true;
}

// Loads the key file into the app's key store (start-up only), with the checks of
// cmdtlm::loadKeyFile; says on stderr why a file is refused, and warns.
bool loadKeys(const Options& options, rse::app::FswApp& app) {
    if (options.keyFile == nullptr) {
        if (!rse::core::isOk(app.useLabKey())) {
            std::fprintf(stderr, "rse-fsw: cannot load the lab key\n");
            return false;
        }
        std::fprintf(stderr, "rse-fsw: warning: --lab-key: the PUBLIC lab key (id %u) authenticates commands: "
                             "lab only, never flight\n",
                     static_cast<unsigned>(rse::cmdtlm::kLabKeyId));
        return true;
    }
    const char* path = options.keyFile;
    const rse::cmdtlm::KeyLoadResult r = rse::cmdtlm::loadKeyFile(path, options.keyOptions, app.keys(), app.events());
    using rse::cmdtlm::KeyLoadError;
    switch (r.error) {
        case KeyLoadError::kNone: break;
        case KeyLoadError::kCannotOpen:
            std::fprintf(stderr, "rse-fsw: cannot read key file '%s': %s\n", path, std::strerror(r.osError));
            return false;
        case KeyLoadError::kNotRegularFile:
        case KeyLoadError::kOpenToOthers:
        case KeyLoadError::kNoKeyInFile:
            std::fprintf(stderr, "rse-fsw: key file '%s' refused: %s\n", path, rse::cmdtlm::toString(r.error));
            return false;
        case KeyLoadError::kBadLine:
            std::fprintf(stderr, "rse-fsw: %s:%u: not a key line (want ID:64-hex-digits)\n", path, r.line);
            return false;
        case KeyLoadError::kTooManyKeys:
            std::fprintf(stderr, "rse-fsw: %s:%u: key id %u refused (at most %zu keys)\n", path, r.line,
                         static_cast<unsigned>(r.keyId), rse::cmdtlm::kMaxKeys);
            return false;
        case KeyLoadError::kWeakKeyRefused:
            std::fprintf(stderr, "rse-fsw: %s:%u: key id %u refused: weak key (%s); --allow-weak-key loads it\n",
                         path, r.line, static_cast<unsigned>(r.keyId), rse::cmdtlm::toString(r.weakness));
            return false;
        case KeyLoadError::kDuplicateKeyId:
        case KeyLoadError::kLabKeyRefused:
            std::fprintf(stderr, "rse-fsw: %s:%u: key id %u refused: %s\n", path, r.line,
                         static_cast<unsigned>(r.keyId), rse::cmdtlm::toString(r.error));
            return false;
    }
    if (r.openFileAccepted) {
        std::fprintf(stderr, "rse-fsw: warning: key file '%s' is open to group or others (--allow-readable-key)\n",
                     path);
    }
    if (r.weakKeysAccepted > 0) {
        std::fprintf(stderr, "rse-fsw: warning: %u weak key(s) loaded (--allow-weak-key): not for flight\n",
                     static_cast<unsigned>(r.weakKeysAccepted));
    }
    if (app.keys().labKeyInUse()) {
        std::fprintf(stderr, "rse-fsw: warning: key id %u of '%s' is the PUBLIC lab key (--lab-key): lab only, "
                             "never flight\n",
                     static_cast<unsigned>(app.keys().labKeyId()), path);
    }
    return true;
}

void installStopHandlers() {
    struct sigaction action {};
    action.sa_handler = onStopSignal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

// Everything the flight software uses is reserved here, before the first frame.
rse::core::MonotonicClock g_monotonicClock;
rse::core::ScaledMonotonicClock g_scaledClock;  // --time-scale only
rse::core::VirtualClock g_virtualClock;
rse::hal::SocketCanBus g_socketCan;
rse::hal::MemoryCanBus g_detachedBus(g_virtualClock);  // nothing else attached
rse::hal::FileRecordStore g_authStore;
// Reservation writes (fsync: milliseconds) run on this writer's thread, never in the command task.
rse::hal::ThreadedRecordWriter g_authWriter(g_authStore);
char g_stdoutBuffer[16384];

}  // namespace

int main(int argc, char** argv) {
    // A static stdout buffer: stdio would otherwise allocate one on first write.
    std::setvbuf(stdout, g_stdoutBuffer, _IOLBF, sizeof g_stdoutBuffer);

    Options options;
    if (!parseOptions(argc, argv, &options)) {
        usage(stderr);
        return 2;
    }
    // Anchored before anything reads it: mission time is continuous with
    // CLOCK_MONOTONIC at this point and runs N times slower from here.
    if (options.timeScale != 0 && !g_scaledClock.start(options.timeScale)) {
        std::fprintf(stderr, "rse-fsw: --time-scale %u refused\n", static_cast<unsigned>(options.timeScale));
        return 2;
    }
    if (options.spinMarginUs > 0) {
        const rse::core::TimeNs margin = options.spinMarginUs * rse::core::kNsPerUs;
        if (!g_monotonicClock.setSpinMargin(margin) || !g_scaledClock.setSpinMargin(margin)) {
            std::fprintf(stderr, "rse-fsw: --spin-margin-us %ld refused\n", options.spinMarginUs);
            return 2;
        }
    }
    rse::core::Clock& clock = options.lockstep         ? static_cast<rse::core::Clock&>(g_virtualClock)
                               : options.timeScale != 0 ? static_cast<rse::core::Clock&>(g_scaledClock)
                                                        : static_cast<rse::core::Clock&>(g_monotonicClock);
    rse::hal::CanBus* can = g_detachedBus.attach("rse-fsw");
    if (options.canInterface != nullptr) {
        if (!rse::core::isOk(g_socketCan.open(options.canInterface))) {
            std::fprintf(stderr, "rse-fsw: cannot open CAN interface '%s': %s\n", options.canInterface,
                         std::strerror(g_socketCan.lastErrno()));
            return 1;
        }
        can = &g_socketCan;
    }
    static rse::app::FswApp app(clock, *can);
    if (!loadKeys(options, app)) {
        return 1;
    }
    app.setAuthRequired(options.authRequired);
    app.setTimeScale(static_cast<std::uint8_t>(options.timeScale != 0 ? options.timeScale : 1));
    // The anti-replay store: always a file (a restart must not reopen numbers).
    if (!rse::core::isOk(g_authStore.open(options.authStore))) {
        std::fprintf(stderr, "rse-fsw: cannot use '%s' as the anti-replay store\n", options.authStore);
        return 1;
    }
    int writerError = 0;
    if (!options.authStoreSync && !rse::core::isOk(g_authWriter.start(&writerError))) {
        std::fprintf(stderr, "rse-fsw: cannot start the anti-replay store writer: %s\n", std::strerror(writerError));
        return 1;
    }
    app.attachAuthStore(&g_authStore, options.authStoreCreate, options.authStoreSync ? nullptr : &g_authWriter);
    std::uint64_t nonce = 0;
    int randomError = 0;
    if (rse::core::isOk(rse::hal::readRandom64(&nonce, &randomError))) {
        app.setAuthChallengeSeed(nonce);
    } else {
        std::fprintf(stderr, "rse-fsw: no random source for the AUTH_RESYNC nonce (%s): AUTH_RESYNC refused\n",
                     std::strerror(randomError));
    }
    static rse::hal::UdpPacketLink g_udpLink(app.events());
    if (options.udp) {
        if (!rse::core::isOk(g_udpLink.open(options.udpBind, options.commandPort, options.telemetryHost,
                                            options.telemetryPort))) {
            std::fprintf(stderr, "rse-fsw: cannot open the UDP ground link on %s:%u: %s\n", options.udpBind,
                         static_cast<unsigned>(options.commandPort), std::strerror(g_udpLink.lastErrno()));
            return 1;
        }
        (void)app.addGroundLink(&g_udpLink);
    }
    if (!rse::core::isOk(app.init(options.quiet ? nullptr : stdout))) {
        std::fprintf(stderr, "rse-fsw: initialisation failed:\n");
        rse::core::Event event;
        while (rse::core::isOk(app.events().pop(&event))) {
            std::fprintf(stderr, "  EVT %u %s\n", static_cast<unsigned>(event.id), event.text);
        }
        return 1;
    }
    // Armed only once the flight software is ready to feed it.
    static rse::hal::WatchdogDevice g_watchdog(app.events());
    if (options.watchdogDevice != nullptr) {
        if (!rse::core::isOk(g_watchdog.open(options.watchdogDevice, options.watchdogTimeoutS))) {
            std::fprintf(stderr, "rse-fsw: cannot open watchdog '%s': %s\n", options.watchdogDevice,
                         std::strerror(g_watchdog.lastErrno()));
            return 1;
        }
        app.attachWatchdog(&g_watchdog);
    }
    installStopHandlers();
    if (!options.lockstep && options.realtimePosture) {
        (void)rse::core::enterRealtimePosture(app.events(), 50);
    }

    const std::uint64_t maxFrames =
        options.durationSec > 0.0
            ? static_cast<std::uint64_t>(options.durationSec * static_cast<double>(rse::core::kNsPerSec) /
                                         static_cast<double>(rse::app::kMinorFramePeriod) + 0.5)
            : 0;
    char timeline[160] = "";
    if (options.timeScale != 0) {
        std::snprintf(timeline, sizeof timeline, " (time scale %u: 1 s of mission time every %u s, lab only)",
                      static_cast<unsigned>(options.timeScale), static_cast<unsigned>(options.timeScale));
    }
    if (options.spinMarginUs > 0) {
        const std::size_t used = std::strlen(timeline);
        std::snprintf(timeline + used, sizeof timeline - used, " (frame starts: sleep, then spin the last %ld us)",
                      options.spinMarginUs);
    }
    std::printf("rse-fsw: %s%s mode, %s, CAN %s\n", options.lockstep ? "lockstep (virtual clock)" : "real-time", timeline,
                maxFrames > 0 ? "fixed duration" : "until SIGINT/SIGTERM",
                options.canInterface != nullptr ? options.canInterface : "none attached");
    app.run(&g_stopRequested, maxFrames);

    g_watchdog.disarm();  // a clean stop must not restart the computer
    app.shutdown(g_stopRequested != 0 ? "stop signal received" : "duration reached");
    g_authWriter.stop();  // a reservation in flight is written before we exit
    app.printSummary(stdout);
    return 0;
}

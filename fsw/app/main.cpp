// rse-fsw: the flight executable.
//
//   rse-fsw [--can IFACE] [--lockstep] [--duration SECONDS] [--quiet] [--no-rt]
//           [--udp] [--udp-bind ADDR] [--cmd-port N] [--tlm-host ADDR] [--tlm-port N]
//           [--key-file FILE] [--lab-no-auth] [--watchdog DEV] [--watchdog-timeout S]
//
// --can IFACE opens that SocketCAN interface (can0, vcan0, ...) as the rover bus;
// without it the flight software runs on an in-memory bus with nothing attached.
// The ground link always runs over ISO-TP on the rover bus; --udp adds the UDP
// link (commands on ADDR:1234, telemetry to 127.0.0.1:1235 by default: the cFS
// lab ports). Commands must be authenticated with a key from --key-file (lines
// "ID:64-hex-digits"), or with the public lab key when no file is given;
// --lab-no-auth also accepts unauthenticated commands (docs/icd.md).
// Real-time mode (default) runs on CLOCK_MONOTONIC until SIGINT/SIGTERM or the
// duration; lockstep mode runs the same tasks on a virtual clock as fast as the
// CPU allows (a duration is then required). Exit status: 0 after a clean stop,
// 1 if initialisation failed, 2 for a bad command line.
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fsw/app/fsw_app.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/realtime_process.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/can/socketcan_bus.hpp"
#include "hal/link/udp_packet_link.hpp"
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
    bool authRequired = true;
    const char* watchdogDevice = nullptr;
    int watchdogTimeoutS = 30;
};

void usage(std::FILE* out) {
    std::fprintf(out,
                 "usage: rse-fsw [--can IFACE] [--lockstep] [--duration SECONDS] [--quiet] [--no-rt]\n"
                 "               [--udp] [--udp-bind ADDR] [--cmd-port N] [--tlm-host ADDR] [--tlm-port N]\n"
                 "               [--key-file FILE] [--lab-no-auth] [--watchdog DEV] [--watchdog-timeout S]\n"
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
                 "  --key-file FILE     command authentication keys, lines ID:64-hex-digits\n"
                 "                      (default: the public lab key, id 1 - not for flight)\n"
                 "  --lab-no-auth       lab setting: also accept unauthenticated commands\n"
                 "  --watchdog DEV      arm the Linux watchdog DEV (/dev/watchdog) and feed it while every task is live;\n"
                 "                      a hung rse-fsw then restarts the computer (a clean stop disarms it)\n"
                 "  --watchdog-timeout S  watchdog timeout asked for, 1..3600 s (default 30)\n");
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
        } else if (std::strcmp(arg, "--udp-bind") == 0 || std::strcmp(arg, "--tlm-host") == 0 ||
                   std::strcmp(arg, "--key-file") == 0 || std::strcmp(arg, "--watchdog") == 0) {
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
    if (options->lockstep && options->durationSec <= 0.0) {
        std::fprintf(stderr, "rse-fsw: --lockstep needs --duration (it would never yield)\n");
        return false;
    }
    return true;
}

// Reads the key file into the app's key store (start-up only). Any bad line
// refuses the whole file: a half-loaded key set is worse than none.
bool loadKeyFile(const char* path, rse::cmdtlm::KeyStore& keys) {
    std::FILE* file = std::fopen(path, "r");
    if (file == nullptr) {
        std::fprintf(stderr, "rse-fsw: cannot read key file '%s': %s\n", path, std::strerror(errno));
        return false;
    }
    char line[256];
    unsigned lineNumber = 0;
    bool ok = true;
    while (ok && std::fgets(line, sizeof line, file) != nullptr) {
        ++lineNumber;
        std::uint16_t id = 0;
        std::uint8_t key[rse::cmdtlm::kKeySize];
        bool isKey = false;
        if (!rse::core::isOk(rse::cmdtlm::parseKeyLine(line, &id, key, &isKey))) {
            std::fprintf(stderr, "rse-fsw: %s:%u: not a key line (want ID:64-hex-digits)\n", path, lineNumber);
            ok = false;
        } else if (isKey && !rse::core::isOk(keys.add(id, key))) {
            std::fprintf(stderr, "rse-fsw: %s:%u: key id %u refused (at most %zu keys)\n", path, lineNumber,
                         static_cast<unsigned>(id), rse::cmdtlm::kMaxKeys);
            ok = false;
        }
    }
    std::fclose(file);
    if (ok && keys.size() == 0) {
        std::fprintf(stderr, "rse-fsw: key file '%s' holds no key\n", path);
        ok = false;
    }
    return ok;
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
rse::core::VirtualClock g_virtualClock;
rse::hal::SocketCanBus g_socketCan;
rse::hal::MemoryCanBus g_detachedBus(g_virtualClock);  // nothing else attached
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
    rse::core::Clock& clock = options.lockstep ? static_cast<rse::core::Clock&>(g_virtualClock)
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
    if (options.keyFile != nullptr && !loadKeyFile(options.keyFile, app.keys())) {
        return 1;
    }
    app.setAuthRequired(options.authRequired);
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
    std::printf("rse-fsw: %s mode, %s, CAN %s\n", options.lockstep ? "lockstep (virtual clock)" : "real-time",
                maxFrames > 0 ? "fixed duration" : "until SIGINT/SIGTERM",
                options.canInterface != nullptr ? options.canInterface : "none attached");
    app.run(&g_stopRequested, maxFrames);

    g_watchdog.disarm();  // a clean stop must not restart the computer
    app.shutdown(g_stopRequested != 0 ? "stop signal received" : "duration reached");
    app.printSummary(stdout);
    return 0;
}

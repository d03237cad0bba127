// rse-fsw: the flight executable.
//
//   rse-fsw [--can IFACE] [--lockstep] [--duration SECONDS] [--quiet] [--no-rt]
//
// --can IFACE opens that SocketCAN interface (can0, vcan0, ...) as the rover bus;
// without it the flight software runs on an in-memory bus with nothing attached.
// Real-time mode (default) runs on CLOCK_MONOTONIC until SIGINT/SIGTERM or the
// duration; lockstep mode runs the same tasks on a virtual clock as fast as the
// CPU allows (a duration is then required). Exit status: 0 after a clean stop,
// 1 if initialisation failed, 2 for a bad command line.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fsw/app/fsw_app.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/realtime_process.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/can/socketcan_bus.hpp"

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
};

void usage(std::FILE* out) {
    std::fprintf(out,
                 "usage: rse-fsw [--can IFACE] [--lockstep] [--duration SECONDS] [--quiet] [--no-rt]\n"
                 "  --can IFACE         SocketCAN interface of the rover bus (default: none attached)\n"
                 "  --lockstep          virtual clock, as fast as possible (needs --duration)\n"
                 "  --duration SECONDS  stop after this much executive time (default: until SIGINT/SIGTERM)\n"
                 "  --quiet             no console housekeeping or event lines\n"
                 "  --no-rt             real time without mlockall/SCHED_FIFO\n");
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
    if (options->lockstep && options->durationSec <= 0.0) {
        std::fprintf(stderr, "rse-fsw: --lockstep needs --duration (it would never yield)\n");
        return false;
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
    if (!rse::core::isOk(app.init(options.quiet ? nullptr : stdout))) {
        std::fprintf(stderr, "rse-fsw: initialisation failed:\n");
        rse::core::Event event;
        while (rse::core::isOk(app.events().pop(&event))) {
            std::fprintf(stderr, "  EVT %u %s\n", static_cast<unsigned>(event.id), event.text);
        }
        return 1;
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

    app.shutdown(g_stopRequested != 0 ? "stop signal received" : "duration reached");
    app.printSummary(stdout);
    return 0;
}

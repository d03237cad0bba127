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
// The options are parsed in fsw/app/fsw_options.cpp (getopt_long; --help prints
// them all). Exit status: 0 after a clean stop (or --help), 1 if initialisation
// failed, 2 for a bad command line (one line saying what is wrong, then
// "see 'rse-fsw --help'", on stderr).
#include <csignal>
#include <cstdio>
#include <cstring>

#include "fsw/app/fsw_app.hpp"
#include "fsw/app/fsw_options.hpp"
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

using Options = rse::app::FswOptions;

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

// Anchored before anything reads it: mission time is continuous with
// CLOCK_MONOTONIC at this point and runs N times slower from here. False (said)
// when the clocks refuse the factor or the margin.
bool startClocks(const Options& options) {
    if (options.timeScale != 0 && !g_scaledClock.start(options.timeScale)) {
        std::fprintf(stderr, "rse-fsw: --time-scale %u refused\n", static_cast<unsigned>(options.timeScale));
        return false;
    }
    if (options.spinMarginUs > 0) {
        const rse::core::TimeNs margin = options.spinMarginUs * rse::core::kNsPerUs;
        if (!g_monotonicClock.setSpinMargin(margin) || !g_scaledClock.setSpinMargin(margin)) {
            std::fprintf(stderr, "rse-fsw: --spin-margin-us %ld refused\n", options.spinMarginUs);
            return false;
        }
    }
    return true;
}

rse::core::Clock& chosenClock(const Options& options) {
    if (options.lockstep) {
        return g_virtualClock;
    }
    if (options.timeScale != 0) {
        return g_scaledClock;
    }
    return g_monotonicClock;
}

// The rover bus: the SocketCAN interface asked for, else the in-memory bus with
// nothing attached; nullptr (said) when the interface cannot be opened.
rse::hal::CanBus* openRoverBus(const Options& options) {
    rse::hal::CanBus* can = g_detachedBus.attach("rse-fsw");
    if (options.canInterface != nullptr) {
        if (!rse::core::isOk(g_socketCan.open(options.canInterface))) {
            std::fprintf(stderr, "rse-fsw: cannot open CAN interface '%s': %s\n", options.canInterface,
                         std::strerror(g_socketCan.lastErrno()));
            return nullptr;
        }
        can = &g_socketCan;
    }
    return can;
}

// The anti-replay store (always a file: a restart must not reopen numbers) and
// its writer thread, attached; then the AUTH_RESYNC nonce from the random source.
bool attachAuthStore(const Options& options, rse::app::FswApp& app) {
    if (!rse::core::isOk(g_authStore.open(options.authStore))) {
        std::fprintf(stderr, "rse-fsw: cannot use '%s' as the anti-replay store\n", options.authStore);
        return false;
    }
    int writerError = 0;
    if (!options.authStoreSync && !rse::core::isOk(g_authWriter.start(&writerError))) {
        std::fprintf(stderr, "rse-fsw: cannot start the anti-replay store writer: %s\n", std::strerror(writerError));
        return false;
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
    return true;
}

// --udp: the UDP ground link beside the ISO-TP one.
bool addUdpLink(const Options& options, rse::app::FswApp& app, rse::hal::UdpPacketLink& link) {
    if (!options.udp) {
        return true;
    }
    if (!rse::core::isOk(
            link.open(options.udpBind, options.commandPort, options.telemetryHost, options.telemetryPort))) {
        std::fprintf(stderr, "rse-fsw: cannot open the UDP ground link on %s:%u: %s\n", options.udpBind,
                     static_cast<unsigned>(options.commandPort), std::strerror(link.lastErrno()));
        return false;
    }
    (void)app.addGroundLink(&link);
    return true;
}

// FswApp::init; on failure the events that say why, on stderr.
bool initialise(const Options& options, rse::app::FswApp& app) {
    if (rse::core::isOk(app.init(options.quiet ? nullptr : stdout))) {
        return true;
    }
    std::fprintf(stderr, "rse-fsw: initialisation failed:\n");
    rse::core::Event event;
    while (rse::core::isOk(app.events().pop(&event))) {
        std::fprintf(stderr, "  EVT %u %s\n", static_cast<unsigned>(event.id), event.text);
    }
    return false;
}

// --watchdog: armed only once the flight software is ready to feed it.
bool armWatchdog(const Options& options, rse::app::FswApp& app, rse::hal::WatchdogDevice& watchdog) {
    if (options.watchdogDevice == nullptr) {
        return true;
    }
    if (!rse::core::isOk(watchdog.open(options.watchdogDevice, options.watchdogTimeoutS))) {
        std::fprintf(stderr, "rse-fsw: cannot open watchdog '%s': %s\n", options.watchdogDevice,
                     std::strerror(watchdog.lastErrno()));
        return false;
    }
    app.attachWatchdog(&watchdog);
    return true;
}

// --duration in minor frames (0: until a signal).
std::uint64_t frameLimit(const Options& options) {
    return options.durationSec > 0.0
               ? static_cast<std::uint64_t>(options.durationSec * static_cast<double>(rse::core::kNsPerSec) /
                                                static_cast<double>(rse::app::kMinorFramePeriod) +
                                            0.5)
               : 0;
}

// "rse-fsw: real-time mode, until SIGINT/SIGTERM, CAN none attached" and the like.
void printStartLine(const Options& options, std::uint64_t maxFrames) {
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
}

}  // namespace

int main(int argc, char** argv) {
    // A static stdout buffer: stdio would otherwise allocate one on first write.
    std::setvbuf(stdout, g_stdoutBuffer, _IOLBF, sizeof g_stdoutBuffer);

    Options options;
    char why[320];
    switch (rse::app::parseFswOptions(argc, argv, &options, why, sizeof why)) {
        case rse::app::FswCommandLine::kHelp:
            rse::app::printFswUsage(stdout);
            return 0;
        case rse::app::FswCommandLine::kBad:
            std::fprintf(stderr, "rse-fsw: %s\nrse-fsw: see 'rse-fsw --help'\n", why);
            return 2;
        case rse::app::FswCommandLine::kRun: break;
    }
    if (!startClocks(options)) {
        return 2;
    }
    rse::hal::CanBus* can = openRoverBus(options);
    if (can == nullptr) {
        return 1;
    }
    static rse::app::FswApp app(chosenClock(options), *can);
    if (!loadKeys(options, app)) {
        return 1;
    }
    app.setAuthRequired(options.authRequired);
    app.setTimeScale(static_cast<std::uint8_t>(options.timeScale != 0 ? options.timeScale : 1));
    if (!attachAuthStore(options, app)) {
        return 1;
    }
    static rse::hal::UdpPacketLink g_udpLink(app.events());
    if (!addUdpLink(options, app, g_udpLink) || !initialise(options, app)) {
        return 1;
    }
    static rse::hal::WatchdogDevice g_watchdog(app.events());
    if (!armWatchdog(options, app, g_watchdog)) {
        return 1;
    }
    installStopHandlers();
    if (!options.lockstep && options.realtimePosture) {
        (void)rse::core::enterRealtimePosture(app.events(), 50);
    }
    const std::uint64_t maxFrames = frameLimit(options);
    printStartLine(options, maxFrames);
    app.run(&g_stopRequested, maxFrames);

    g_watchdog.disarm();  // a clean stop must not restart the computer
    app.shutdown(g_stopRequested != 0 ? "stop signal received" : "duration reached");
    g_authWriter.stop();  // a reservation in flight is written before we exit
    app.printSummary(stdout);
    return 0;
}

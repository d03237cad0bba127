// rse-sim: the rover and its world as a separate process on a SocketCAN bus.
//
//   rse-sim --can IFACE --scenario FILE [--duration SECONDS] [--quiet] [--time-scale N]
//   rse-sim --coarse-map-source FILE
//   rse-sim --site-file FILE
//
// The second form prints the COARSE_MAP table source of the scenario's site
// and known rocks (sim_stub/scenario/coarse_map_source.hpp) for the operator
// to compile and load (`rse-ground table build`, `table load`), so that
// the rover plans on the map the simulator drives it through. The third prints
// the scenario's rocks as a site file (sim_stub/scenario/site_file.hpp) that
// another scenario may name with [site] file: with a [field] it is the site
// generator (Golombek and Rapp's model at the field's k and seed).
//
// Each of the six drive emulators gets its own socket (as six controllers would
// have), the other devices share one. The world steps at 1 kHz on
// CLOCK_MONOTONIC with absolute deadlines; --time-scale N slows that clock N
// times (core::ScaledMonotonicClock), as rse-fsw --time-scale N does its own,
// so both keep one mission timeline on a machine too slow for real time. Prints the truth once a second (for
// the operator and integration tests; the flight software never sees it).
// Exit status: 0 after a clean stop (or --help), 1 if the bus or scenario
// cannot be used (a task_stall fault included: it needs a ground link, which
// rse-sim has not), 2 for a bad command line (docs/operations.md, "Command
// lines": one line on stderr says why).
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "sim_stub/cli/command_line.hpp"

#include "fsw/core/clock.hpp"
#include "hal/can/socketcan_bus.hpp"
#include "sim_stub/drives/drive_bank.hpp"
#include "sim_stub/rover_sim.hpp"
#include "sim_stub/scenario/coarse_map_source.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "sim_stub/scenario/site_file.hpp"

namespace {

using rse::sim::cli::OptionScanner;

volatile std::sig_atomic_t g_stop = 0;
void onStop(int) { g_stop = 1; }

constexpr double kMaxDurationS = 1e7;  // the scenario files' own limit on times

void usage(std::FILE* out) {
    std::fprintf(out,
                 "usage: rse-sim --can IFACE --scenario FILE [--duration SECONDS] [--quiet] [--time-scale N]\n"
                 "       rse-sim --coarse-map-source FILE\n"
                 "       rse-sim --site-file FILE\n"
                 "       rse-sim --help\n"
                 "  --can IFACE        SocketCAN interface shared with rse-fsw (e.g. vcan0)\n"
                 "  --scenario FILE    TOML scenario (sim_stub/scenarios/README.md)\n"
                 "  --duration SECONDS stop after this long (default: the scenario's duration_s; at most 1e7)\n"
                 "  --quiet            no once-a-second truth lines\n"
                 "  --time-scale N     simulated time runs N times slower than CLOCK_MONOTONIC (1..100; the\n"
                 "                     same N as rse-fsw --time-scale); --duration and the scenario are in\n"
                 "                     simulated seconds\n"
                 "  --coarse-map-source FILE  print the scenario's COARSE_MAP table source and exit\n"
                 "  --site-file FILE   print the scenario's rocks as a site file ([site] file = ...) and exit\n"
                 "  -h, --help         this text (on stdout, exit status 0)\n"
                 "Exit status: 0 stopped cleanly, 1 the bus or the scenario cannot be used, 2 bad usage.\n");
}

struct Options {
    const char* can = nullptr;
    const char* scenario = nullptr;
    const char* mapSource = nullptr;
    const char* siteFile = nullptr;
    double duration = 0.0;
    bool quiet = false;
    std::uint32_t timeScale = 1;
};

enum : int { kOptCan = 1000, kOptScenario, kOptDuration, kOptQuiet, kOptTimeScale, kOptCoarseMapSource, kOptSiteFile };
const option kLongOptions[] = {
    {"can", required_argument, nullptr, kOptCan},
    {"scenario", required_argument, nullptr, kOptScenario},
    {"duration", required_argument, nullptr, kOptDuration},
    {"quiet", no_argument, nullptr, kOptQuiet},
    {"time-scale", required_argument, nullptr, kOptTimeScale},
    {"coarse-map-source", required_argument, nullptr, kOptCoarseMapSource},
    {"site-file", required_argument, nullptr, kOptSiteFile},
    {"help", no_argument, nullptr, 'h'},
    {nullptr, 0, nullptr, 0},
};

// One option and its value into *o; false with the reason in *error.
bool applyOption(int id, const char* value, Options* o, std::string* error) {
    switch (id) {
        case kOptCan: o->can = value; return true;
        case kOptScenario: o->scenario = value; return true;
        case kOptCoarseMapSource: o->mapSource = value; return true;
        case kOptSiteFile: o->siteFile = value; return true;
        case kOptQuiet: o->quiet = true; return true;
        case kOptDuration:
            if (!rse::sim::cli::parseFiniteNumber(value, &o->duration) || !(o->duration > 0.0) ||
                o->duration > kMaxDurationS) {
                *error = std::string("--duration '") + value + "' is not a positive number of seconds (at most 1e7)";
                return false;
            }
            return true;
        case kOptTimeScale: {
            std::uint64_t n = 0;
            if (!rse::sim::cli::parseWholeNumber(value, rse::core::ScaledMonotonicClock::kMaxFactor, &n) || n < 1) {
                *error = std::string("--time-scale '") + value + "' is not a whole factor 1.." +
                         std::to_string(rse::core::ScaledMonotonicClock::kMaxFactor);
                return false;
            }
            o->timeScale = static_cast<std::uint32_t>(n);
            return true;
        }
        default: break;
    }
    *error = "option " + std::to_string(id) + " is not rse-sim's";  // a table entry without a case
    return false;
}

enum class Parsed { kRun, kHelp, kUsageError };

Parsed parse(int argc, const char* const* argv, Options* o, std::string* error) {
    OptionScanner scanner(argc, argv, "h", kLongOptions);
    for (int id = scanner.next(); id != OptionScanner::kEnd; id = scanner.next()) {
        if (id == OptionScanner::kBad) {
            *error = scanner.error();
            return Parsed::kUsageError;
        }
        if (id == 'h') {
            return Parsed::kHelp;
        }
        if (!applyOption(id, scanner.value(), o, error)) {
            return Parsed::kUsageError;
        }
    }
    if (scanner.index() < argc) {
        *error = std::string("unexpected argument '") + argv[scanner.index()] + "' (rse-sim takes options only)";
        return Parsed::kUsageError;
    }
    if (o->mapSource != nullptr && o->siteFile != nullptr) {
        *error = "--coarse-map-source and --site-file: one at a time";
        return Parsed::kUsageError;
    }
    if (o->mapSource == nullptr && o->siteFile == nullptr && (o->can == nullptr || o->scenario == nullptr)) {
        *error = "--can and --scenario are required";
        return Parsed::kUsageError;
    }
    return Parsed::kRun;
}

bool openBus(rse::hal::SocketCanBus& bus, const char* name) {
    if (rse::core::isOk(bus.open(name))) {
        return true;
    }
    std::fprintf(stderr, "rse-sim: cannot open CAN interface '%s': %s\n", name, std::strerror(bus.lastErrno()));
    return false;
}

// The scenario at path, or false with the reason on stderr.
bool loadScenarioOrSay(const char* path, rse::sim::Scenario* scenario) {
    std::string error;
    if (!rse::sim::tryLoadScenarioFile(path, scenario, &error)) {
        std::fprintf(stderr, "rse-sim: %s\n", error.c_str());
        return false;
    }
    return true;
}

// rse-sim --coarse-map-source FILE: the scenario's COARSE_MAP table source on stdout.
int printCoarseMapSource(const char* path) {
    rse::sim::Scenario scenario;
    if (!loadScenarioOrSay(path, &scenario)) {
        return 1;
    }
    try {
        std::fputs(rse::sim::coarseMapSource(scenario).c_str(), stdout);
    } catch (const rse::sim::CoarseMapError& e) {
        std::fprintf(stderr, "rse-sim: %s\n", e.what());
        return 1;
    }
    return 0;
}

// rse-sim --site-file FILE: the scenario's rocks as a site file on stdout.
int printSiteFile(const char* path) {
    rse::sim::Scenario scenario;
    if (!loadScenarioOrSay(path, &scenario)) {
        return 1;
    }
    std::fputs(rse::sim::siteFileText(scenario).c_str(), stdout);
    return 0;
}

// rse-sim only exchanges CAN frames: a flight task stall needs the ground
// link (EXEC_SET_TASK), which rse-sim does not have. Refused, not ignored.
bool refuseTaskStalls(const rse::sim::Scenario& scenario, const char* path) {
    for (std::size_t i = 0; i < scenario.faults.size(); ++i) {
        const rse::sim::FaultSpec& f = scenario.faults[i];
        if (f.type == rse::sim::FaultType::kTaskStall) {
            std::fprintf(stderr,
                         "rse-sim: %s: faults[%zu] task_stall (%s%s at %.3f s) is not applicable over CAN: rse-sim "
                         "has no ground link; send EXEC_SET_TASK with rse-ground instead, or run the scenario "
                         "in lockstep (rse-demo)\n",
                         path, i, f.taskName.empty() ? "row " : "",
                         f.taskName.empty() ? std::to_string(f.taskRow).c_str() : f.taskName.c_str(),
                         static_cast<double>(f.at) * 1e-9);
            return false;
        }
    }
    return true;
}

// The bus endpoints: one for the devices, one per drive (as six controllers would have).
struct Buses {
    std::unique_ptr<rse::hal::SocketCanBus> devices;
    std::array<std::unique_ptr<rse::hal::SocketCanBus>, rse::sim::kWheelCount> drives;
    std::array<rse::hal::CanBus*, rse::sim::kWheelCount> drivePtrs{};
};

bool openBuses(const char* can, Buses* b) {
    b->devices = std::make_unique<rse::hal::SocketCanBus>();
    if (!openBus(*b->devices, can)) {
        return false;
    }
    for (std::size_t w = 0; w < rse::sim::kWheelCount; ++w) {
        b->drives[w] = std::make_unique<rse::hal::SocketCanBus>();
        if (!openBus(*b->drives[w], can)) {
            return false;
        }
        b->drivePtrs[w] = b->drives[w].get();
    }
    return true;
}

void installStopHandlers() {
    struct sigaction action {};
    action.sa_handler = onStop;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

// The world at 1 kHz on the (scaled) monotonic clock with absolute deadlines,
// the truth once a second, until the duration or a stop signal; then how late
// its steps started.
void runWorld(rse::sim::RoverSim& rover, rse::sim::DriveBank& drives, const Options& o, double duration) {
    rse::core::ScaledMonotonicClock clock;
    (void)clock.start(o.timeScale);  // 1..kMaxFactor, checked by parse()
    drives.powerOn();
    const rse::core::TimeNs origin = clock.now();
    const rse::core::TimeNs step = rse::core::kNsPerMs;
    const auto steps = static_cast<std::int64_t>(duration * 1000.0);
    // How far behind its timeline the world ran (simulated time): a step that
    // starts more than a step late delays what the devices put on the bus.
    rse::core::TimeNs maxLateness = 0;
    std::int64_t lateSteps = 0;
    std::int64_t stepsRun = 0;
    for (std::int64_t k = 0; k <= steps && g_stop == 0; ++k) {
        const rse::core::TimeNs t = k * step;
        clock.sleepUntil(origin + t);
        const rse::core::TimeNs lateness = clock.now() - (origin + t);
        maxLateness = lateness > maxLateness ? lateness : maxLateness;
        lateSteps += lateness > step ? 1 : 0;
        ++stepsRun;
        rover.step(t);
        if (!o.quiet && k % 1000 == 0) {
            const auto& truth = rover.truth();
            std::printf("[%8.3f] TRUTH x=%.3f y=%.3f theta=%.4f v=%.3f soc=%.4f collisions=%u faults_fired=%zu\n",
                        static_cast<double>(t) * 1e-9, truth.pose.x, truth.pose.y, truth.pose.theta, truth.speedMS,
                        truth.stateOfCharge, static_cast<unsigned>(truth.collisions), rover.faultSchedule().fired());
            std::fflush(stdout);
        }
    }
    std::printf("rse-sim: timing: %lld of %lld steps started more than 1 ms late, the latest %.1f ms "
                "(simulated time)\n",
                static_cast<long long>(lateSteps), static_cast<long long>(stepsRun),
                static_cast<double>(maxLateness) * 1e-6);
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    std::string error;
    switch (parse(argc, argv, &o, &error)) {
        case Parsed::kHelp:
            usage(stdout);
            return 0;
        case Parsed::kUsageError:
            return rse::sim::cli::usageError(stderr, "rse-sim", error);
        case Parsed::kRun:
            break;
    }
    if (o.mapSource != nullptr) {
        return printCoarseMapSource(o.mapSource);
    }
    if (o.siteFile != nullptr) {
        return printSiteFile(o.siteFile);
    }
    rse::sim::Scenario scenario;
    if (!loadScenarioOrSay(o.scenario, &scenario)) {
        return 1;
    }
    if (!refuseTaskStalls(scenario, o.scenario)) {
        return 1;
    }
    Buses buses;
    if (!openBuses(o.can, &buses)) {
        return 1;
    }
    auto drives = std::make_unique<rse::sim::DriveBank>(buses.drivePtrs, scenario);  // node ids, noise, seed
    rse::sim::RoverSimWiring wiring;
    wiring.driveFaults = drives.get();  // bus faults need the in-memory bus: counted as unhandled here
    auto rover = std::make_unique<rse::sim::RoverSim>(scenario, *buses.devices, drives->wheels(), wiring);
    installStopHandlers();

    const double duration = o.duration > 0.0 ? o.duration : scenario.durationS;
    std::printf("rse-sim: scenario '%s' on %s for %.1f s", scenario.name.c_str(), o.can, duration);
    if (o.timeScale > 1) {
        std::printf(" (time scale %u: 1 simulated second every %u s)", static_cast<unsigned>(o.timeScale),
                    static_cast<unsigned>(o.timeScale));
    }
    std::printf("\n");
    std::fflush(stdout);
    runWorld(*rover, *drives, o, duration);
    std::printf("rse-sim: stopped (%s)\n", g_stop != 0 ? "signal" : "duration reached");
    return 0;
}

// rse-sim: the rover and its world as a separate process on a SocketCAN bus.
//
//   rse-sim --can IFACE --scenario FILE [--duration SECONDS] [--quiet] [--time-scale N]
//   rse-sim --coarse-map-source FILE
//
// The second form prints the COARSE_MAP table source of the scenario's site
// and known rocks (sim_stub/scenario/coarse_map_source.hpp) for the operator
// to compile and load (`rse-ground table build`, `table load`), so that
// the rover plans on the map the simulator drives it through.
//
// Each of the six drive emulators gets its own socket (as six controllers would
// have), the other devices share one. The world steps at 1 kHz on
// CLOCK_MONOTONIC with absolute deadlines; --time-scale N slows that clock N
// times (core::ScaledMonotonicClock), as rse-fsw --time-scale N does its own,
// so both keep one mission timeline on a machine too slow for real time. Prints the truth once a second (for
// the operator and integration tests; the flight software never sees it).
// Exit status: 0 after a clean stop, 1 if the bus or scenario cannot be used
// (a task_stall fault included: it needs a ground link, which rse-sim has
// not), 2 for a bad command line.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "fsw/core/clock.hpp"
#include "hal/can/socketcan_bus.hpp"
#include "sim_stub/drives/drive_bank.hpp"
#include "sim_stub/rover_sim.hpp"
#include "sim_stub/scenario/coarse_map_source.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void onStop(int) { g_stop = 1; }

void usage(std::FILE* out) {
    std::fprintf(out,
                 "usage: rse-sim --can IFACE --scenario FILE [--duration SECONDS] [--quiet] [--time-scale N]\n"
                 "       rse-sim --coarse-map-source FILE\n"
                 "  --can IFACE        SocketCAN interface shared with rse-fsw (e.g. vcan0)\n"
                 "  --scenario FILE    TOML scenario (sim_stub/scenarios/README.md)\n"
                 "  --duration SECONDS stop after this long (default: the scenario's duration_s)\n"
                 "  --quiet            no once-a-second truth lines\n"
                 "  --time-scale N     simulated time runs N times slower than CLOCK_MONOTONIC (1..100; the\n"
                 "                     same N as rse-fsw --time-scale); --duration and the scenario are in\n"
                 "                     simulated seconds\n"
                 "  --coarse-map-source FILE  print the scenario's COARSE_MAP table source and exit\n");
}

struct Options {
    const char* can = nullptr;
    const char* scenario = nullptr;
    const char* mapSource = nullptr;
    double duration = 0.0;
    bool quiet = false;
    std::uint32_t timeScale = 1;
};

bool parse(int argc, char** argv, Options* o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool hasValue = i + 1 < argc;
        if (a == "--can" && hasValue) {
            o->can = argv[++i];
        } else if (a == "--scenario" && hasValue) {
            o->scenario = argv[++i];
        } else if (a == "--duration" && hasValue) {
            char* end = nullptr;
            o->duration = std::strtod(argv[++i], &end);
            if (*end != '\0' || !(o->duration > 0.0)) {
                std::fprintf(stderr, "rse-sim: --duration '%s' is not a positive number of seconds\n", argv[i]);
                return false;
            }
        } else if (a == "--time-scale" && hasValue) {
            char* end = nullptr;
            const char* v = argv[++i];
            const unsigned long n = std::strtoul(v, &end, 10);
            if (*end != '\0' || v[0] < '0' || v[0] > '9' || n < 1 || n > rse::core::ScaledMonotonicClock::kMaxFactor) {
                std::fprintf(stderr, "rse-sim: --time-scale '%s' is not a whole factor 1..%u\n", v,
                             static_cast<unsigned>(rse::core::ScaledMonotonicClock::kMaxFactor));
                return false;
            }
            o->timeScale = static_cast<std::uint32_t>(n);
        } else if (a == "--coarse-map-source" && hasValue) {
            o->mapSource = argv[++i];
        } else if (a == "--quiet") {
            o->quiet = true;
        } else if (a == "--help" || a == "-h") {
            usage(stdout);
            std::exit(0);
        } else {
            std::fprintf(stderr, "rse-sim: unknown or incomplete option '%s'\n", a.c_str());
            return false;
        }
    }
    if (o->mapSource != nullptr) {
        return true;
    }
    if (o->can == nullptr || o->scenario == nullptr) {
        std::fprintf(stderr, "rse-sim: --can and --scenario are required\n");
        return false;
    }
    return true;
}

bool openBus(rse::hal::SocketCanBus& bus, const char* name) {
    if (rse::core::isOk(bus.open(name))) {
        return true;
    }
    std::fprintf(stderr, "rse-sim: cannot open CAN interface '%s': %s\n", name, std::strerror(bus.lastErrno()));
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse(argc, argv, &o)) {
        usage(stderr);
        return 2;
    }
    rse::sim::Scenario scenario;
    std::string error;
    if (o.mapSource != nullptr) {
        if (!rse::sim::tryLoadScenarioFile(o.mapSource, &scenario, &error)) {
            std::fprintf(stderr, "rse-sim: %s\n", error.c_str());
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
    if (!rse::sim::tryLoadScenarioFile(o.scenario, &scenario, &error)) {
        std::fprintf(stderr, "rse-sim: %s\n", error.c_str());
        return 1;
    }
    // rse-sim only exchanges CAN frames: a flight task stall needs the ground
    // link (EXEC_SET_TASK), which rse-sim does not have. Refused, not ignored.
    for (std::size_t i = 0; i < scenario.faults.size(); ++i) {
        const rse::sim::FaultSpec& f = scenario.faults[i];
        if (f.type == rse::sim::FaultType::kTaskStall) {
            std::fprintf(stderr,
                         "rse-sim: %s: faults[%zu] task_stall (%s%s at %.3f s) is not applicable over CAN: rse-sim "
                         "has no ground link; send EXEC_SET_TASK with rse-ground instead, or run the scenario "
                         "in lockstep (rse-demo)\n",
                         o.scenario, i, f.taskName.empty() ? "row " : "",
                         f.taskName.empty() ? std::to_string(f.taskRow).c_str() : f.taskName.c_str(),
                         static_cast<double>(f.at) * 1e-9);
            return 1;
        }
    }
    using rse::sim::kWheelCount;
    auto devicesBus = std::make_unique<rse::hal::SocketCanBus>();
    std::array<std::unique_ptr<rse::hal::SocketCanBus>, kWheelCount> driveBuses;
    std::array<rse::hal::CanBus*, kWheelCount> driveBusPtrs{};
    if (!openBus(*devicesBus, o.can)) {
        return 1;
    }
    for (std::size_t w = 0; w < kWheelCount; ++w) {
        driveBuses[w] = std::make_unique<rse::hal::SocketCanBus>();
        if (!openBus(*driveBuses[w], o.can)) {
            return 1;
        }
        driveBusPtrs[w] = driveBuses[w].get();
    }
    auto drives = std::make_unique<rse::sim::DriveBank>(driveBusPtrs, scenario);  // node ids, noise, seed
    rse::sim::RoverSimWiring wiring;
    wiring.driveFaults = drives.get();  // bus faults need the in-memory bus: counted as unhandled here
    auto rover = std::make_unique<rse::sim::RoverSim>(scenario, *devicesBus, drives->wheels(), wiring);

    struct sigaction action {};
    action.sa_handler = onStop;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);

    const double duration = o.duration > 0.0 ? o.duration : scenario.durationS;
    std::printf("rse-sim: scenario '%s' on %s for %.1f s", scenario.name.c_str(), o.can, duration);
    if (o.timeScale > 1) {
        std::printf(" (time scale %u: 1 simulated second every %u s)", static_cast<unsigned>(o.timeScale),
                    static_cast<unsigned>(o.timeScale));
    }
    std::printf("\n");
    std::fflush(stdout);
    rse::core::ScaledMonotonicClock clock;
    (void)clock.start(o.timeScale);  // 1..kMaxFactor, checked above
    drives->powerOn();
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
        rover->step(t);
        if (!o.quiet && k % 1000 == 0) {
            const auto& truth = rover->truth();
            std::printf("[%8.3f] TRUTH x=%.3f y=%.3f theta=%.4f v=%.3f soc=%.4f collisions=%u faults_fired=%zu\n",
                        static_cast<double>(t) * 1e-9, truth.pose.x, truth.pose.y, truth.pose.theta, truth.speedMS,
                        truth.stateOfCharge, static_cast<unsigned>(truth.collisions), rover->faultSchedule().fired());
            std::fflush(stdout);
        }
    }
    std::printf("rse-sim: timing: %lld of %lld steps started more than 1 ms late, the latest %.1f ms "
                "(simulated time)\n",
                static_cast<long long>(lateSteps), static_cast<long long>(stepsRun),
                static_cast<double>(maxLateness) * 1e-6);
    std::printf("rse-sim: stopped (%s)\n", g_stop != 0 ? "signal" : "duration reached");
    return 0;
}

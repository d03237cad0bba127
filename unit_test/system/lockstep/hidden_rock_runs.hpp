// The hidden-rock missions of test_lockstep_hidden_rock.cpp and its host-only
// rest (test_lockstep_hidden_rock_sweep_host.cpp): the demo scenario with one
// line changed (the hidden rock moved, another seed), written to a temporary
// file and flown like `rse-demo --no-faults --quiet --scenario FILE --goto
// 20,0,RISK`, and whether it reached the goal cleanly.
#pragma once

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <unistd.h>

#include "sim_stub/lockstep/mission_runner.hpp"

#include "CppUTest/TestHarness.h"

namespace rse::test::hidden_rock {

using sim::MissionOptions;
using sim::MissionOutcome;
using sim::MissionSummary;

constexpr const char* kHiddenRockLine = "vertices = [[12.5, -0.5], [13.0, -0.5], [13.0, 0.0], [12.5, 0.0]]";
constexpr const char* kSeedLine = "seed = 20240611";

inline std::string demoText() {
    std::ifstream in(sim::kDefaultMissionScenario);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// The demo scenario with `from` replaced by `to`, in a temporary file; "" when
// the line is not there (the demo changed: the test must be updated).
inline std::string variant(const std::string& from, const std::string& to) {
    std::string text = demoText();
    const std::size_t at = text.find(from);
    if (at == std::string::npos) {
        return "";
    }
    text.replace(at, from.size(), to);
    char path[] = "/tmp/rse_hidden_rock_XXXXXX";
    const int fd = mkstemp(path);
    if (fd < 0) {
        return "";
    }
    close(fd);
    std::ofstream(path) << text;
    return path;
}

inline std::string rockAt(double x) {
    char line[128];
    std::snprintf(line, sizeof line, "vertices = [[%.1f, -0.5], [%.1f, -0.5], [%.1f, 0.5], [%.1f, 0.5]]", x - 0.5,
                  x + 0.5, x + 0.5, x - 0.5);
    return variant(kHiddenRockLine, line);
}

// As `rse-demo --no-faults --quiet --scenario FILE --goto 20,0,RISK`.
inline MissionSummary runDemo(const std::string& scenario, const char* risk) {
    const std::string gotoArg = std::string("20,0,") + risk;
    const char* argv[] = {"rse-demo", "--no-faults", "--quiet", "--scenario", scenario.c_str(), "--goto", gotoArg.c_str()};
    MissionOptions o;
    std::string error;
    if (sim::parseMissionArgs(7, argv, &o, &error) != sim::ParseOutcome::kRun) {
        std::printf("\nbad options: %s\n", error.c_str());
        return MissionSummary{};
    }
    return sim::runMission(o, nullptr);
}

// Reached, at the goal, without contact; else the reason on stdout.
inline bool reachedCleanly(const MissionSummary& s, const char* what) {
    const bool ok = s.outcome == MissionOutcome::kGoalReached && s.goalDistanceM < 0.6 && s.collisions == 0;
    if (!ok) {
        std::printf("\n%s: %s (%s) at %.1f s, %.2f m from the goal, %u collisions, %u fail-ups, %u replans\n", what,
                    sim::toString(s.outcome), s.callHomeText.c_str(), s.outcomeTimeS, s.goalDistanceM,
                    static_cast<unsigned>(s.collisions), static_cast<unsigned>(s.failUps),
                    static_cast<unsigned>(s.replans));
    }
    return ok;
}

// The rock at each of metres (a 1 m square centred on (x, 0)), one mission
// each: every one must reach the goal without contact.
inline void sweep(std::initializer_list<int> metres) {
    CHECK_FALSE(demoText().empty());
    const auto t0 = std::chrono::steady_clock::now();
    unsigned reached = 0;
    unsigned failUps = 0;
    for (const int x : metres) {
        const std::string path = rockAt(static_cast<double>(x));
        CHECK_FALSE(path.empty());
        const MissionSummary s = runDemo(path, "1e-3");
        std::remove(path.c_str());
        char what[32];
        std::snprintf(what, sizeof what, "rock at x = %d", x);
        reached += reachedCleanly(s, what) ? 1U : 0U;
        failUps += s.failUps;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("\n  hidden-rock sweep: %u of %zu reached, %u fail-ups in all, %.1f s wall\n", reached, metres.size(),
                failUps, wall);
    LONGS_EQUAL(metres.size(), reached);
}

}  // namespace rse::test::hidden_rock

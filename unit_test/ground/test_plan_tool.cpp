// `rse-ground plan check` (ground/plan_tool.hpp): the flight parser, method
// selection and temporal network run on the ground, so a plan is checked
// before it is sent: the two-targets plan's methods and cost with every
// component ok and with the grinder failed, no selection with both
// instruments failed, the parser's own reason and line for a bad plan.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ground/ground_cli.hpp"

#include "CppUTest/TestHarness.h"

namespace {

const char* const kTwoTargets = "unit_test/fuzz/corpus/plan/two_targets.plan";

struct Run {
    int rc = -1;
    std::string out, err;
};

Run planCli(std::vector<std::string> args) {
    args.insert(args.begin(), "rse-ground");
    std::vector<char*> argv;
    for (std::string& a : args) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    std::ostringstream out, err;
    Run r;
    r.rc = rse::ground::runGroundCli(static_cast<int>(args.size()), argv.data(), out, err);
    r.out = out.str();
    r.err = err.str();
    return r;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_GROUP(PlanTool){};

TEST(PlanTool, TheTwoTargetsPlanSamplesBothTargetsWhenEverythingWorks) {
    const Run r = planCli({"plan", "check", kTwoTargets});
    CHECK_TEXT(r.rc == 0, r.err.c_str());
    CHECK(has(r.out, "plan 'two_targets': 5 events, 6 activities, 1 constraints, 2 choices"));
    CHECK(has(r.out, "choice science1: sample"));
    CHECK(has(r.out, "choice science2: sample"));
    CHECK(has(r.out, "expected cost: 32.500"));  // 10 + 5 + 12.5 + 5
    CHECK(has(r.out, "  done2: ["));
    CHECK(has(r.out, "3600.000]"));  // the deadline bounds done2
}

// The drives' goals: a point, or a region (`within R`, the flight parser's).
TEST(PlanTool, EachSelectedDriveIsShownWithItsPointOrRegion) {
    const Run r = planCli({"plan", "check", kTwoTargets});
    CHECK_TEXT(has(r.out, "drives (m):\n  drive1: to (10.000, 0.000) (the point)\n"
                          "  drive2: to (20.000, 5.000) (the point)\n"),
               r.out.c_str());
    const Run region = planCli({"plan", "check", "unit_test/fuzz/corpus/plan/drive_region.plan"});
    CHECK_TEXT(region.rc == 0, region.err.c_str());
    CHECK_TEXT(has(region.out, "  drive1: to (10.000, 0.000) within 3.000\n"), region.out.c_str());
    // A bare number after the point is refused as on board, with its reason.
    const std::string path = "build/test_plan_tool_radius.plan";
    {
        std::ofstream f(path);
        f << "event a\nactivity go drive start a [0, 600] at 5 5 2\nend\n";
    }
    const Run bare = planCli({"plan", "check", path});
    LONGS_EQUAL(2, bare.rc);
    CHECK_TEXT(has(bare.err, path + ":2: number after a drive's point (a region is written within R) at '2'"),
               bare.err.c_str());
    std::remove(path.c_str());
}

TEST(PlanTool, AFailedGrinderMakesBothTargetsImagesAtAHigherCost) {
    const Run r = planCli({"plan", "check", kTwoTargets, "--failed", "grinder"});
    CHECK_TEXT(r.rc == 0, r.err.c_str());
    CHECK(has(r.out, "choice science1: image"));
    CHECK(has(r.out, "choice science2: image"));
    CHECK(has(r.out, "expected cost: 42.500"));  // 10 + (8 + 2) + 12.5 + (8 + 2)
    // A degraded middle-left drive prices the drives higher (decision-theoretic
    // costs): drive1 asks it (x 1.5) and every drive pays x 1.25 per degraded drive.
    const Run d = planCli({"plan", "check", kTwoTargets, "--failed", "grinder", "--degraded", "drive_ML"});
    CHECK(d.rc == 0);
    CHECK(has(d.out, "expected cost: 54.375"));  // 10 x 1.5 x 1.25 + 12.5 x 1.25 + 2 x (8 + 2)
    // "ask camera=ok" is not met by a degraded camera: with the grinder out, no method is left.
    LONGS_EQUAL(2, planCli({"plan", "check", kTwoTargets, "--failed", "grinder", "--degraded", "camera"}).rc);
}

TEST(PlanTool, NoInstrumentLeftMeansNoSelection) {
    const Run r = planCli({"plan", "check", kTwoTargets, "--failed", "grinder,camera"});
    LONGS_EQUAL(2, r.rc);
    CHECK(has(r.err, "no valid selection of methods"));
}

TEST(PlanTool, APlanTheRoverWouldRefuseIsRefusedWithTheSameReasonAndLine) {
    const std::string path = "build/test_plan_tool_bad.plan";
    {
        std::ofstream f(path);
        f << "plan bad\nevent a\nactivity x teleport start a [0, 1]\nend\n";
    }
    const Run r = planCli({"plan", "check", path});
    LONGS_EQUAL(2, r.rc);
    CHECK_TEXT(has(r.err, path + ":3: unknown activity kind at 'teleport'"), r.err.c_str());
    std::remove(path.c_str());
}

TEST(PlanTool, UsageAndUnreadableFiles) {
    LONGS_EQUAL(2, planCli({"plan"}).rc);
    LONGS_EQUAL(2, planCli({"plan", "send", kTwoTargets}).rc);
    const Run unknown = planCli({"plan", "check", kTwoTargets, "--failed", "laser"});
    LONGS_EQUAL(2, unknown.rc);
    CHECK(has(unknown.err, "unknown component 'laser'"));
    LONGS_EQUAL(2, planCli({"plan", "check", kTwoTargets, "--broken"}).rc);
    LONGS_EQUAL(1, planCli({"plan", "check", "build/no_such_plan.plan"}).rc);
}

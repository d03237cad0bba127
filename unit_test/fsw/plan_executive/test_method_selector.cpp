// Method selection: the two-targets example (sample cheaper than image; the
// grinder failed: images, dearer; a deprecated option), nested choices,
// plan-variable causal links, an option whose bounds break a deadline, no
// valid selection reported as proven, the expected-cost penalties, bad plans;
// exactness against an exhaustive reference on seeded random plans; the hard
// work budget on the largest plan; sliced runs equal to one-shot runs; no
// heap use. Regeneration inputs (executed times, not before): a late first
// activity rules out the slow option, contradicting times give kNoneExists,
// random plans with random execution states against the reference.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/stn.hpp"
#include "unit_test/fsw/plan_executive/selection_reference.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::plan_executive;
using rse::core::Status;
using rse::test::plan::exhaustiveOptimum;
using rse::test::plan::kTwoTargetsText;
using rse::test::plan::missionPlan;
using rse::test::plan::pickOf;
using rse::test::plan::PlanBuilder;
using rse::test::plan::randomSmallPlan;
using rse::test::plan::ReferenceOutcome;
using rse::test::plan::referenceCost;
using rse::test::plan::referenceValid;
using rse::test::plan::twoTargets;
using rse::test::plan::under;

namespace {

// Static storage, as in flight.
MethodSelector selector;
MethodSelector twin;
Tpn plan;
Stn stn;
SelectionResult result;

constexpr std::uint8_t kSample = 0;
constexpr std::uint8_t kImage = 1;

SelectionParams unlimited() {
    SelectionParams p;
    p.workBudget = std::numeric_limits<std::uint32_t>::max();
    return p;
}

std::uint32_t rejected(RejectReason r) { return selector.stats().rejected[static_cast<std::size_t>(r)]; }

// The selection's STN (loadStn) is consistent, so what the selector chose
// can be dispatched, and the reference judges it valid under the same input.
void checkDispatchable(const Tpn& t, const Selection& s, const SelectionInput& input = SelectionInput{}) {
    CHECK(loadStn(t, s, &stn) == Status::kOk);
    CHECK(stn.check() == StnState::kConsistent);
    std::uint8_t pick[kMaxChoices] = {};
    pickOf(s, t.choiceCount, pick);
    CHECK(referenceValid(t, pick, input, &stn));
}

// The plan selected under the input (unlimited budget) agrees with the
// exhaustive reference: status, cost, and the selection valid and priced
// alike by the reference. True when a valid selection exists.
bool agreesWithReference(std::uint32_t seed, const SelectionInput& input, std::size_t* selections) {
    const SelectionParams params = unlimited();
    const SelectionStatus st = selector.solve(plan, input, params, &result);
    const ReferenceOutcome ref = exhaustiveOptimum(plan, input, params, &stn);
    *selections += ref.selections;
    const std::string where = "seed " + std::to_string(seed);
    if (!ref.found) {
        CHECK_TEXT(st == SelectionStatus::kNoneExists, where.c_str());
        return false;
    }
    CHECK_TEXT(st == SelectionStatus::kSelected, where.c_str());
    DOUBLES_EQUAL_TEXT(ref.cost, result.cost, 1e-9 * (1.0 + std::fabs(ref.cost)), where.c_str());
    std::uint8_t pick[kMaxChoices] = {};
    pickOf(result.selection, plan.choiceCount, pick);
    CHECK_TEXT(referenceValid(plan, pick, input, &stn), where.c_str());
    DOUBLES_EQUAL_TEXT(referenceCost(plan, pick, input, params), result.cost, 1e-9, where.c_str());
    return true;
}

}  // namespace

TEST_GROUP(MethodSelector){};

TEST(MethodSelector, TwoTargetsSampleBothWhenTheGrinderWorks) {
    twoTargets(&plan);
    CHECK(selector.solve(plan, SelectionInput{}, SelectionParams{}, &result) == SelectionStatus::kSelected);
    CHECK(result.hasSelection);
    CHECK_EQUAL(kSample, result.selection.option[0]);
    CHECK_EQUAL(kSample, result.selection.option[1]);
    DOUBLES_EQUAL(10.0 + 3.0 + 10.0 + 3.0, result.cost, 1e-12);
    DOUBLES_EQUAL(result.cost, selectionCost(plan, result.selection, SelectionInput{}, SelectionParams{}), 1e-12);
    DOUBLES_EQUAL(result.cost, selector.stats().rootBound, 1e-12);
    checkDispatchable(plan, result.selection);
}

TEST(MethodSelector, TwoTargetsImageBothWhenTheGrinderHasFailed) {
    twoTargets(&plan);
    SelectionInput input;
    input.components[static_cast<std::size_t>(Component::kGrinder)] = ComponentState::kFailed;
    CHECK(selector.solve(plan, input, SelectionParams{}, &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kImage, result.selection.option[0]);
    CHECK_EQUAL(kImage, result.selection.option[1]);
    DOUBLES_EQUAL(10.0 + 5.0 + 10.0 + 5.0, result.cost, 1e-12);  // up from 26
    CHECK_EQUAL(2U, rejected(RejectReason::kAskFailed));
    // A degraded grinder fails "grinder = ok" too.
    input.components[static_cast<std::size_t>(Component::kGrinder)] = ComponentState::kDegraded;
    CHECK(selector.solve(plan, input, SelectionParams{}, &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kImage, result.selection.option[1]);
}

TEST(MethodSelector, ADeprecatedOptionIsNotChosen) {
    twoTargets(&plan);
    SelectionInput input;
    input.deprecated[1][kSample] = true;  // sample(target 2) deprecated, sample(target 1) not
    CHECK(selector.solve(plan, input, SelectionParams{}, &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kSample, result.selection.option[0]);
    CHECK_EQUAL(kImage, result.selection.option[1]);
    DOUBLES_EQUAL(28.0, result.cost, 1e-12);
    CHECK_EQUAL(1U, rejected(RejectReason::kDeprecated));
}

TEST(MethodSelector, NestedChoicesExistOnlyUnderTheirParentsOption) {
    // Choice 0 {x: cost 5 | y: cost 2 holding choice 1 {p: 1 | q: 0.5, asks camera = ok}}.
    PlanBuilder b(&plan);
    const std::uint16_t e1 = b.event(), e2 = b.event();
    const std::uint8_t c0 = b.choice(2);
    b.activity(ActivityKind::kWait, 0, e1, 1000, 2000, 5.0, under(c0, 0));
    b.activity(ActivityKind::kWait, 0, e1, 1000, 2000, 2.0, under(c0, 1));
    const std::uint8_t c1 = b.choice(2, nullptr, under(c0, 1));
    b.activity(ActivityKind::kImage, e1, e2, 1000, 2000, 1.0, under(c1, 0));
    const std::uint16_t q = b.activity(ActivityKind::kImage, e1, e2, 1000, 2000, 0.5, under(c1, 1));
    b.ask(q, Component::kCamera, ComponentState::kOk);
    CHECK(selector.solve(plan, SelectionInput{}, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(1, result.selection.option[c0]);
    CHECK_EQUAL(1, result.selection.option[c1]);
    DOUBLES_EQUAL(2.5, result.cost, 1e-12);
    SelectionInput input;
    input.components[static_cast<std::size_t>(Component::kCamera)] = ComponentState::kFailed;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(0, result.selection.option[c1]);
    DOUBLES_EQUAL(3.0, result.cost, 1e-12);
    // Neither nested option usable: y is out, x is chosen and choice 1 does not exist.
    input.deprecated[c1][0] = true;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(0, result.selection.option[c0]);
    CHECK_EQUAL(kNoOption, result.selection.option[c1]);
    DOUBLES_EQUAL(5.0, result.cost, 1e-12);
}

TEST(MethodSelector, APlanVariableAskNeedsATellThatSurelyPrecedesIt) {
    // deploy: start -> e1 in [10, 20] s, Tells arm = deployed. Choice: sample
    // from the start (cost 1: before deploy ends, unsupported) or from e1 (cost 2).
    PlanBuilder b(&plan);
    const std::uint8_t arm = b.variable(2);  // 0 stowed, 1 deployed
    const std::uint16_t e1 = b.event(), e2 = b.event();
    const std::uint16_t deploy = b.activity(ActivityKind::kWait, 0, e1, 10000, 20000, 0.5);
    b.tell(deploy, arm, 1);
    const std::uint8_t c = b.choice(2);
    const std::uint16_t early = b.activity(ActivityKind::kSample, 0, e2, 30000, 60000, 1.0, under(c, 0));
    b.askVariable(early, arm, 1);
    const std::uint16_t late = b.activity(ActivityKind::kSample, e1, e2, 10000, 60000, 2.0, under(c, 1));
    b.askVariable(late, arm, 0, true);  // arm != stowed: deployed answers
    CHECK(selector.solve(plan, SelectionInput{}, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(1, result.selection.option[c]);
    DOUBLES_EQUAL(2.5, result.cost, 1e-12);
    CHECK(rejected(RejectReason::kCausalLinkMissing) >= 1U);
    // Nothing Tells "stowed": an Ask of it is unsupported in every selection (static).
    plan.activities[late].asks[0].negated = false;
    CHECK(selector.solve(plan, SelectionInput{}, unlimited(), &result) == SelectionStatus::kNoneExists);
    CHECK(rejected(RejectReason::kCausalLinkMissing) >= 2U);
    // A Tell only under an option not chosen supports nothing: the early
    // sample (Asking nothing now) Tells "stowed", the late one Asks it, and
    // the early one is deprecated.
    plan.activities[early].askCount = 0;
    b.tell(early, arm, 0);
    CHECK(selector.solve(plan, SelectionInput{}, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(0, result.selection.option[c]);
    SelectionInput input;
    input.deprecated[c][0] = true;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kNoneExists);
}

TEST(MethodSelector, AnOptionWhoseBoundsBreakADeadlineIsAvoided) {
    twoTargets(&plan);
    // Target 1's window is 200 s: its sample (>= 300 s) cannot fit, alone (presolve).
    plan.constraints[plan.constraintCount++] = TemporalConstraint{1, 2, Bounds{0, 200000}, Guard{}};
    CHECK(selector.solve(plan, SelectionInput{}, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kImage, result.selection.option[0]);
    CHECK_EQUAL(kSample, result.selection.option[1]);
    CHECK_EQUAL(1U, rejected(RejectReason::kInconsistent));
    checkDispatchable(plan, result.selection);
    // A deadline of 500 s for the whole plan: drives take >= 120 s, so one
    // sample (300 s) and one image (60 s) fit, two samples do not (search).
    twoTargets(&plan);
    plan.constraints[0].bounds.ubMs = 500000;
    CHECK(selector.solve(plan, SelectionInput{}, unlimited(), &result) == SelectionStatus::kSelected);
    DOUBLES_EQUAL(28.0, result.cost, 1e-12);
    CHECK(result.selection.option[0] != result.selection.option[1]);
    CHECK(rejected(RejectReason::kInconsistent) >= 1U);
    checkDispatchable(plan, result.selection);
}

TEST(MethodSelector, NoValidSelectionIsReportedAsProven) {
    twoTargets(&plan);
    SelectionInput input;
    input.components[static_cast<std::size_t>(Component::kGrinder)] = ComponentState::kFailed;
    input.components[static_cast<std::size_t>(Component::kCamera)] = ComponentState::kFailed;
    CHECK(selector.solve(plan, input, SelectionParams{}, &result) == SelectionStatus::kNoneExists);
    CHECK_FALSE(result.hasSelection);
    CHECK_EQUAL(4U, rejected(RejectReason::kAskFailed));
    // A deadline no selection meets (the drives alone need 120 s).
    twoTargets(&plan);
    plan.constraints[0].bounds.ubMs = 119999;
    CHECK(selector.solve(plan, SelectionInput{}, SelectionParams{}, &result) == SelectionStatus::kNoneExists);
    CHECK(rejected(RejectReason::kInconsistent) >= 1U);
    // An unguarded activity asking a failed component.
    twoTargets(&plan);
    plan.activities[0].asks[plan.activities[0].askCount++] =
        Condition{false, static_cast<std::uint8_t>(Component::kDriveFL), 2, true};
    input = SelectionInput{};
    input.components[static_cast<std::size_t>(Component::kDriveFL)] = ComponentState::kFailed;
    CHECK(selector.solve(plan, input, SelectionParams{}, &result) == SelectionStatus::kNoneExists);
}

TEST(MethodSelector, DegradedComponentsRaiseTheExpectedCost) {
    // A long drive (10, asks nothing) or a short one (8, asks drive FL != failed).
    PlanBuilder b(&plan);
    const std::uint16_t e1 = b.event();
    const std::uint8_t c = b.choice(2);
    b.activity(ActivityKind::kDrive, 0, e1, 1000, 2000, 10.0, under(c, 0));
    const std::uint16_t shortDrive = b.activity(ActivityKind::kDrive, 0, e1, 1000, 2000, 8.0, under(c, 1));
    b.ask(shortDrive, Component::kDriveFL, ComponentState::kFailed, true);
    CHECK(selector.solve(plan, SelectionInput{}, SelectionParams{}, &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(1, result.selection.option[c]);
    DOUBLES_EQUAL(8.0, result.cost, 1e-12);
    // Drive FL degraded: long 10 x (1 + 0.25) = 12.5; short 8 x 1.5 x 1.25 = 15.
    SelectionInput input;
    input.components[static_cast<std::size_t>(Component::kDriveFL)] = ComponentState::kDegraded;
    SelectionParams params;
    params.degradedPenalty = 0.5;
    params.drivePenalty = 0.25;
    CHECK(selector.solve(plan, input, params, &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(0, result.selection.option[c]);
    DOUBLES_EQUAL(12.5, result.cost, 1e-12);
    // With no penalties the short drive wins again.
    params.degradedPenalty = params.drivePenalty = 0.0;
    CHECK(selector.solve(plan, input, params, &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(1, result.selection.option[c]);
}

TEST(MethodSelector, BadPlansAndParametersAreRefused) {
    twoTargets(&plan);
    plan.choices[0].guard = under(1, 0);
    plan.choices[1].guard = under(0, 0);  // a nesting cycle
    CHECK(selector.start(plan, SelectionInput{}, SelectionParams{}) == Status::kInvalidArgument);
    CHECK(selector.finished());
    CHECK(selector.result().status == SelectionStatus::kBadPlan);
    twoTargets(&plan);
    plan.activities[0].duration = Bounds{5, 4};
    CHECK(selector.start(plan, SelectionInput{}, SelectionParams{}) == Status::kInvalidArgument);
    twoTargets(&plan);
    plan.activities[1].to = plan.eventCount;
    CHECK(selector.start(plan, SelectionInput{}, SelectionParams{}) == Status::kInvalidArgument);
    twoTargets(&plan);
    plan.activities[1].cost = std::nan("");
    CHECK(selector.start(plan, SelectionInput{}, SelectionParams{}) == Status::kInvalidArgument);
    twoTargets(&plan);
    plan.activities[1].guard = under(0, 2);  // choice 0 has two options
    CHECK(selector.start(plan, SelectionInput{}, SelectionParams{}) == Status::kInvalidArgument);
    twoTargets(&plan);
    SelectionParams params;
    params.drivePenalty = -1.0;
    CHECK(selector.start(plan, SelectionInput{}, params) == Status::kInvalidArgument);
    params = SelectionParams{};
    params.workBudget = 0;
    CHECK(selector.start(plan, SelectionInput{}, params) == Status::kInvalidArgument);
    CHECK(selector.start(plan, SelectionInput{}, SelectionParams{}) == Status::kOk);
}

TEST(MethodSelector, EqualsTheExhaustiveReferenceOnRandomPlans) {
    // Seeded random plans of up to 6 choices (nested, guarded constraints,
    // component and plan-variable Asks, random states and deprecations): the
    // selector's status, cost and feasibility equal the exhaustive optimum's,
    // and what it selects is valid by the reference's own judgement.
    std::size_t feasible = 0, infeasible = 0, selections = 0;
    for (std::uint32_t seed = 1; seed <= 600; ++seed) {
        SelectionInput input;
        randomSmallPlan(seed, 6, &plan, &input);
        const bool found = agreesWithReference(seed, input, &selections);
        feasible += found ? 1U : 0U;
        infeasible += found ? 0U : 1U;
    }
    std::printf("\n  exhaustive reference: %zu plans with a valid selection, %zu without; %zu selections judged\n",
                feasible, infeasible, selections);
    // The generator must exercise both outcomes.
    CHECK(feasible > 100);
    CHECK(infeasible > 30);
}

namespace {

constexpr std::int32_t kSecond = 1000;

void parsed(const char* text) {
    const ParseResult r = rse::test::plan::parseText(text, &plan);
    CHECK_TEXT(r.error == PlanError::kOk, toString(r.error));
}

// A drive to a, then a slow cheap sample or a fast dear image, all done by 1000 s.
const char* const kOneStop =
    "plan one_stop; event a; event b; choice science sample image\n"
    "activity go drive start a [60, 900] cost 10 at 1 0\n"
    "activity s sample a b [300, 600] cost 5 target 1 when science.sample\n"
    "activity i image a b [30, 60] cost 8 target 1 when science.image\n"
    "constraint start b [0, 1000]\n"
    "end\n";

}  // namespace

TEST(MethodSelector, ALateFirstActivityRulesOutTheSlowOption) {
    parsed(kOneStop);
    constexpr std::uint16_t kA = 1, kB = 2;
    SelectionInput input;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kSample, result.selection.option[0]);
    DOUBLES_EQUAL(15.0, result.cost, 1e-12);
    // The drive arrived at 650 s: the sample (>= 300 s) still ends by 1000 s.
    input.executedAtMs[kA] = 650 * kSecond;
    input.notBeforeMs = 650 * kSecond;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kSample, result.selection.option[0]);
    // At 800 s it cannot: the image is chosen, dearer.
    input.executedAtMs[kA] = 800 * kSecond;
    input.notBeforeMs = 800 * kSecond;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kImage, result.selection.option[0]);
    DOUBLES_EQUAL(18.0, result.cost, 1e-12);
    CHECK(rejected(RejectReason::kInconsistent) >= 1U);
    checkDispatchable(plan, result.selection, input);
    // The dispatcher's network (loadStn with the input) holds a at its time.
    CHECK(loadStn(plan, result.selection, input, &stn) == Status::kOk);
    CHECK(stn.check() == StnState::kConsistent);
    CHECK_EQUAL(800 * kSecond, stn.window(kA).earliestMs);
    CHECK_EQUAL(800 * kSecond, stn.window(kA).latestMs);
    CHECK_EQUAL(830 * kSecond, stn.window(kB).earliestMs);
    CHECK_EQUAL(860 * kSecond, stn.window(kB).latestMs);
    // Not before alone (nothing executed yet) rules the sample out too.
    input = SelectionInput{};
    input.notBeforeMs = 800 * kSecond;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kImage, result.selection.option[0]);
}

TEST(MethodSelector, TwoTargetsReSelectedWithTheFirstScienceDoneAndALongDrive) {
    parsed(kTwoTargetsText);
    CHECK(selector.solve(plan, SelectionInput{}, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kSample, result.selection.option[1]);
    DOUBLES_EQUAL(32.5, result.cost, 1e-12);
    // Sampled target 1 (at1 600 s, done1 800 s); the second drive took until
    // 3500 s: sampling target 2 (>= 120 s) would pass the 3600 s deadline.
    // The first choice is done: the caller forces it by deprecating image1.
    SelectionInput input;
    input.executedAtMs[1] = 600 * kSecond;
    input.executedAtMs[2] = 800 * kSecond;
    input.executedAtMs[3] = 3500 * kSecond;
    input.notBeforeMs = 3500 * kSecond;
    input.deprecated[0][kImage] = true;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kSample, result.selection.option[0]);
    CHECK_EQUAL(kImage, result.selection.option[1]);
    DOUBLES_EQUAL(37.5, result.cost, 1e-12);
    checkDispatchable(plan, result.selection, input);
    // The grinder has failed since: sample(target 1) is done, its Ask is not
    // judged again when it is marked started; unmarked, nothing is left.
    input.components[static_cast<std::size_t>(Component::kGrinder)] = ComponentState::kFailed;
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kNoneExists);
    input.started[0] = input.started[1] = input.started[3] = true;  // drive1, sample1, drive2
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK_EQUAL(kSample, result.selection.option[0]);
    CHECK_EQUAL(kImage, result.selection.option[1]);
    checkDispatchable(plan, result.selection, input);
}

TEST(MethodSelector, ExecutedTimesThatContradictThePlanHaveNoSelection) {
    parsed(kOneStop);
    SelectionInput input;
    input.executedAtMs[1] = 30 * kSecond;  // the drive takes at least 60 s
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kNoneExists);
    CHECK_FALSE(result.hasSelection);
    input.executedAtMs[1] = 950 * kSecond;  // and at most 900 s
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kNoneExists);
    input.executedAtMs[1] = kInfiniteMs;
    input.notBeforeMs = 1001 * kSecond;  // b can no longer meet its deadline
    CHECK(selector.solve(plan, input, unlimited(), &result) == SelectionStatus::kNoneExists);
    // Times out of range are refused, not judged.
    input.notBeforeMs = -1;
    CHECK(selector.start(plan, input, unlimited()) == Status::kInvalidArgument);
    CHECK(loadStn(plan, Selection{}, input, &stn) == Status::kInvalidArgument);
    input.notBeforeMs = 0;
    input.executedAtMs[2] = kMaxBoundMs + 1;
    CHECK(selector.start(plan, input, unlimited()) == Status::kInvalidArgument);
    input.executedAtMs[2] = kInfiniteMs;
    input.executedAtMs[0] = -5;  // ignored: the start is at 0
    CHECK(selector.start(plan, input, unlimited()) == Status::kOk);
}

TEST(MethodSelector, DefaultExecutionInputsLoadTheSameNetwork) {
    parsed(kTwoTargetsText);
    CHECK(selector.solve(plan, SelectionInput{}, unlimited(), &result) == SelectionStatus::kSelected);
    CHECK(loadStn(plan, result.selection, &stn) == Status::kOk);
    CHECK(stn.check() == StnState::kConsistent);
    static Stn withInput;
    CHECK(loadStn(plan, result.selection, SelectionInput{}, &withInput) == Status::kOk);
    CHECK(withInput.check() == StnState::kConsistent);
    for (std::size_t a = 0; a < plan.eventCount; ++a) {
        for (std::size_t b = 0; b < plan.eventCount; ++b) {
            CHECK_EQUAL(stn.distance(a, b), withInput.distance(a, b));
        }
    }
}

TEST(MethodSelector, EqualsTheReferenceOnRandomPlansMidExecution) {
    // The random plans again, re-selected mid-execution: a random "not
    // before" and about a third of the events executed at random times.
    std::size_t feasible = 0, infeasible = 0;
    for (std::uint32_t seed = 1; seed <= 300; ++seed) {
        SelectionInput input;
        randomSmallPlan(seed, 6, &plan, &input);
        std::mt19937 rng(seed * 7919U);
        const auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
        input.notBeforeMs = uniform(0, 20) * kSecond;
        for (std::size_t e = 1; e < plan.eventCount; ++e) {
            const bool executed = uniform(0, 2) == 0;
            const std::int32_t at = uniform(0, 40) * kSecond;
            input.executedAtMs[e] = executed ? at : kInfiniteMs;
        }
        std::size_t selections = 0;
        const bool found = agreesWithReference(seed, input, &selections);
        feasible += found ? 1U : 0U;
        infeasible += found ? 0U : 1U;
    }
    std::printf("\n  mid-execution reference: %zu plans with a valid selection, %zu without\n", feasible, infeasible);
    CHECK(feasible > 20);
    CHECK(infeasible > 20);
}

TEST(MethodSelector, TheWorkBudgetIsHardOnTheLargestPlan) {
    // kMaxActivities activities (the choices kMaxChoices allows; the third
    // plan with tight deadlines, whose search the budget ends), run one
    // action at a time (step(1)) and in slices: no action does more than
    // kMaxActionWork, and no selection passes its budget by more than that.
    std::uint64_t largestAction = 0, largestExcess = 0, largestSliceExcess = 0;
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
        missionPlan(seed, kMaxActivities, &plan, seed == 3);
        CHECK_EQUAL(kMaxActivities, plan.activityCount);
        for (const std::uint32_t budget : {300U, 3000U, 30000U, 300000U, 4000000U}) {
            SelectionParams params;
            params.workBudget = budget;
            CHECK(selector.start(plan, SelectionInput{}, params) == Status::kOk);
            for (std::uint32_t k = 0; k < 10000000 && !selector.finished(); ++k) {
                const std::uint64_t before = selector.work();
                (void)selector.step(1);
                const std::uint64_t did = selector.work() - before;
                largestAction = did > largestAction ? did : largestAction;
            }
            CHECK(selector.finished());
            const std::uint64_t excess = selector.work() > budget ? selector.work() - budget : 0;
            largestExcess = excess > largestExcess ? excess : largestExcess;
            const SelectionStatus st = selector.result().status;
            CHECK(st != SelectionStatus::kBadPlan && st != SelectionStatus::kRunning);
            if (budget <= 300U) {
                CHECK(st == SelectionStatus::kNoneFound);
            }
            // Slices of 5000: each step stops within an action of its slice.
            CHECK(twin.start(plan, SelectionInput{}, params) == Status::kOk);
            for (std::uint32_t k = 0; k < 100000 && !twin.finished(); ++k) {
                const std::uint64_t before = twin.work();
                (void)twin.step(5000);
                const std::uint64_t over = twin.work() - before > 5000 ? twin.work() - before - 5000 : 0;
                largestSliceExcess = over > largestSliceExcess ? over : largestSliceExcess;
            }
            CHECK(twin.result().status == st);
            CHECK_EQUAL(selector.work(), twin.work());
        }
    }
    std::printf("\n  largest plan: largest action %llu work units (kMaxActionWork %llu), largest excess over the "
                "budget %llu, over a slice %llu; last: %s, cost %.2f, %llu units\n",
                static_cast<unsigned long long>(largestAction),
                static_cast<unsigned long long>(MethodSelector::kMaxActionWork),
                static_cast<unsigned long long>(largestExcess), static_cast<unsigned long long>(largestSliceExcess),
                toString(selector.result().status), selector.result().cost,
                static_cast<unsigned long long>(selector.work()));
    CHECK(largestAction <= MethodSelector::kMaxActionWork);
    CHECK(largestExcess < MethodSelector::kMaxActionWork);
    CHECK(largestSliceExcess < MethodSelector::kMaxActionWork);
}

TEST(MethodSelector, TheLargestPlanIsSelectedOptimallyWithTheDefaultBudget) {
    missionPlan(7, kMaxActivities, &plan);
    CHECK(selector.solve(plan, SelectionInput{}, SelectionParams{}, &result) == SelectionStatus::kSelected);
    checkDispatchable(plan, result.selection);
    // The grinder fails: every sample and dig goes; images remain.
    SelectionInput input;
    input.components[static_cast<std::size_t>(Component::kGrinder)] = ComponentState::kFailed;
    const double before = result.cost;
    CHECK(selector.solve(plan, input, SelectionParams{}, &result) == SelectionStatus::kSelected);
    CHECK(result.cost > before);
    for (std::size_t c = 0; c < plan.choiceCount; ++c) {
        CHECK(result.selection.option[c] == kNoOption || result.selection.option[c] == kImage ||
              plan.choices[c].guard.guarded());
    }
    checkDispatchable(plan, result.selection, input);
}

TEST(MethodSelector, ASlicedSelectionEqualsAOneShotSelection) {
    for (std::uint32_t seed = 20; seed < 24; ++seed) {
        missionPlan(seed, 60, &plan);
        SelectionInput input;
        input.components[static_cast<std::size_t>(Component::kDriveMR)] = ComponentState::kDegraded;
        CHECK(selector.solve(plan, input, SelectionParams{}, &result) == SelectionStatus::kSelected);
        CHECK(twin.start(plan, input, SelectionParams{}) == Status::kOk);
        for (std::uint32_t k = 0; k < 1000000 && !twin.step(37); ++k) {
        }
        CHECK(twin.result().status == SelectionStatus::kSelected);
        DOUBLES_EQUAL(result.cost, twin.result().cost, 0.0);
        CHECK_EQUAL(selector.work(), twin.work());
        for (std::size_t c = 0; c < plan.choiceCount; ++c) {
            CHECK_EQUAL(result.selection.option[c], twin.result().selection.option[c]);
        }
    }
}

TEST(MethodSelector, NoHeapUseAcrossSelectionsAndNetworkUpdates) {
    rse::test::AllocationWatch watch;
    for (std::uint32_t seed = 1; seed <= 40; ++seed) {
        SelectionInput input;
        randomSmallPlan(seed, 6, &plan, &input);
        (void)selector.solve(plan, input, unlimited(), &result);
        missionPlan(seed, 50, &plan);
        CHECK(selector.start(plan, input, SelectionParams{}) == Status::kOk);
        for (std::uint32_t k = 0; k < 100000 && !selector.step(500); ++k) {
        }
        if (selector.result().hasSelection) {
            CHECK(loadStn(plan, selector.result().selection, &stn) == Status::kOk);
            if (stn.check() == StnState::kConsistent) {
                (void)stn.execute(1, stn.window(1).earliestMs);
            }
        }
    }
    CHECK_EQUAL(0U, watch.count());
}

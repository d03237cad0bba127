// The plan executive's plan: a Temporal Plan Network (TPN), as the parser
// builds it from the text format (docs/plan_executive.md) and as method
// selection, the Simple Temporal Network and dispatch read it. Fixed capacity,
// no heap: a plan larger than a limit below is refused by the parser, never
// truncated.
//
// The network (after Kim, Williams and Abramson's TPN and the RMPL executive):
//   - events: time points; event 0 is the plan's start (named "start"),
//     executed when the plan is started;
//   - activities: from one event to another, a kind (drive, sample, image,
//     dig, wait, communicate) with its parameters, [lb, ub] duration bounds
//     and a cost; Ask conditions that must hold for the activity to be chosen
//     and to run, and Tell conditions it makes hold at its end;
//   - temporal constraints: [lb, ub] between two events with no activity;
//   - choices: each offers 2..kMaxOptions options, exactly one of which is
//     chosen; an event, activity, constraint or nested choice guarded by an
//     option exists only when that option is chosen (the option's thread).
// Times are integer milliseconds (kInfiniteMs: no upper bound).
//
// Conditions. A variable is a component (its state comes from mode
// estimation or the device's own status: ok, degraded or failed) or a plan
// variable (declared in the plan with its values; an activity's Tell sets it
// at the activity's end, and an activity that Asks it must start after a
// Tell that sets it, in every schedule).
#pragma once

#include <cstddef>
#include <cstdint>

namespace rse::plan_executive {

// Compile-time limits of a plan (docs/plan_executive.md "Limits").
constexpr std::size_t kMaxEvents = 256;
constexpr std::size_t kMaxActivities = 256;
constexpr std::size_t kMaxConstraints = 128;
constexpr std::size_t kMaxChoices = 64;
constexpr std::size_t kMaxOptions = 4;           // per choice
constexpr std::size_t kMaxPlanVariables = 16;
constexpr std::size_t kMaxVariableValues = 8;    // per plan variable
constexpr std::size_t kMaxAsks = 4;              // per activity
constexpr std::size_t kMaxTells = 2;             // per activity
constexpr std::size_t kNameSize = 24;            // names, NUL included
constexpr std::size_t kMaxPlanText = 16384;      // bytes of plan text

constexpr std::int32_t kInfiniteMs = INT32_MAX;
constexpr std::int32_t kMaxBoundMs = 1000000000;  // finite bounds up to ~11.6 days
constexpr std::uint8_t kNoChoice = 0xFF;          // Guard::choice of an unguarded element

enum class ActivityKind : std::uint8_t {
    kDrive = 0,        // to a point (x, y), or anywhere within a radius of it
    kSample = 1,       // grinder/sampler on a target
    kImage = 2,        // camera on a target
    kDig = 3,          // grinder/sampler, dig mode, on a target
    kWait = 4,         // nothing but time
    kCommunicate = 5,  // a communication window (nothing commanded)
};
constexpr std::size_t kActivityKindCount = 6;

// A science activity: one an instrument carries out on a target (a sample, an
// image, a dig), which may be extended (PLAN_EXTEND) and must name its target.
constexpr bool isScience(ActivityKind k) {
    return k == ActivityKind::kSample || k == ActivityKind::kImage || k == ActivityKind::kDig;
}

// Components whose state mode estimation or the device reports.
enum class Component : std::uint8_t {
    kDriveFL = 0,
    kDriveML = 1,
    kDriveRL = 2,
    kDriveFR = 3,
    kDriveMR = 4,
    kDriveRR = 5,
    kGrinder = 6,
    kCamera = 7,
};
constexpr std::size_t kComponentCount = 8;

enum class ComponentState : std::uint8_t { kOk = 0, kDegraded = 1, kFailed = 2 };
constexpr std::size_t kComponentStateCount = 3;

// One Ask or Tell: variable (component or plan variable) = or != value.
struct Condition {
    bool planVariable = false;  // false: a Component
    std::uint8_t variable = 0;  // Component, or index into Tpn::variables
    std::uint8_t value = 0;     // ComponentState, or index into the variable's values
    bool negated = false;       // != (Ask only; a Tell always sets =)
};

struct Bounds {
    std::int32_t lbMs = 0;
    std::int32_t ubMs = kInfiniteMs;
};

// The option a guarded element exists under (choice kNoChoice: always).
struct Guard {
    std::uint8_t choice = kNoChoice;
    std::uint8_t option = 0;
    bool guarded() const { return choice != kNoChoice; }
};

struct PlanEvent {
    char name[kNameSize] = {};
    Guard guard;
};

struct Activity {
    char name[kNameSize] = {};
    ActivityKind kind = ActivityKind::kWait;
    std::uint16_t from = 0;  // event index
    std::uint16_t to = 0;
    Bounds duration;
    double cost = 0.0;
    // kDrive: the goal (x, y) m, reached to HABITUAL.goal_tolerance_m; with
    // `within R`, anywhere within radiusMm (mm, 1..kMaxGoalRadiusM of
    // goal_msgs.hpp; 0: the point). Millimetres, as the text's 3 decimals:
    // 16 bits keep the activity at 96 B.
    double x = 0.0, y = 0.0;
    std::uint16_t radiusMm = 0;
    // kSample, kImage, kDig: the science target's id (1..255).
    std::uint8_t target = 0;
    std::uint8_t askCount = 0;
    std::uint8_t tellCount = 0;
    Guard guard;
    Condition asks[kMaxAsks];
    Condition tells[kMaxTells];
};

struct TemporalConstraint {
    std::uint16_t from = 0;
    std::uint16_t to = 0;
    Bounds bounds;
    Guard guard;
};

struct ChoiceOption {
    char name[kNameSize] = {};
    double cost = 0.0;  // added when this option is chosen
};

struct Choice {
    char name[kNameSize] = {};
    std::uint8_t optionCount = 0;
    Guard guard;  // a nested choice exists only under its parent's option
    ChoiceOption options[kMaxOptions];
};

struct PlanVariable {
    char name[kNameSize] = {};
    std::uint8_t valueCount = 0;
    char values[kMaxVariableValues][kNameSize] = {};
};

struct Tpn {
    char name[kNameSize] = {};
    std::uint16_t eventCount = 0;
    std::uint16_t activityCount = 0;
    std::uint16_t constraintCount = 0;
    std::uint8_t choiceCount = 0;
    std::uint8_t variableCount = 0;
    PlanEvent events[kMaxEvents];
    Activity activities[kMaxActivities];
    TemporalConstraint constraints[kMaxConstraints];
    Choice choices[kMaxChoices];
    PlanVariable variables[kMaxPlanVariables];
};

// Names for events, docs and the ground tool.
const char* toString(ActivityKind k);
const char* toString(Component c);
const char* toString(ComponentState s);

}  // namespace rse::plan_executive

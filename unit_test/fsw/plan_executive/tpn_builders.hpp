// Plans built directly as Tpn structs (no parser) for the plan executive's
// tests and bench_plan_executive: a small builder, the two-targets example,
// seeded random small plans (for the exhaustive reference) and seeded mission
// plans of a given size (chains of drives and science choices with
// alternatives, deadlines and a plan variable). A Tpn is ~50 KB: callers give
// static storage.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>

#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/plan_parser.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::test::plan {

using namespace rse::plan_executive;

// The two-targets example of docs/plan_executive.md as text (as in
// unit_test/fuzz/corpus/plan/two_targets.plan), for parsePlan: bounds in
// seconds, the parser's costs (not twoTargets() below).
inline constexpr const char* kTwoTargetsText =
    "# Two targets: sample each with the grinder, or image it if the grinder is out.\n"
    "plan two_targets\n"
    "var sampled no yes\n"
    "event at1\n"
    "event done1\n"
    "event at2\n"
    "event done2\n"
    "choice science1 sample image cost 2\n"
    "choice science2 sample image cost 2\n"
    "activity drive1 drive start at1 [60, 900] cost 10 at 10 0 ask drive_ML!=failed\n"
    "activity sample1 sample at1 done1 [120, 300] cost 5 target 1 ask grinder=ok tell sampled=yes when science1.sample\n"
    "activity image1 image at1 done1 [30, 60] cost 8 target 1 ask camera=ok when science1.image\n"
    "activity drive2 drive done1 at2 [60, inf] cost 12.5 at 20 5\n"
    "activity sample2 sample at2 done2 [120, 300] cost 5 target 2 ask grinder=ok when science2.sample\n"
    "activity image2 image at2 done2 [30, 60] cost 8 target 2 ask camera=ok when science2.image\n"
    "constraint start done2 [0, 3600]\n"
    "end\n";

// A NUL-terminated plan text parsed into *t.
inline ParseResult parseText(const char* text, Tpn* t) { return parsePlan(text, std::strlen(text), t); }

inline Guard under(std::size_t choice, std::size_t option) {
    Guard g;
    g.choice = static_cast<std::uint8_t>(choice);
    g.option = static_cast<std::uint8_t>(option);
    return g;
}

inline void setName(char (&dst)[kNameSize], const char* src) { std::snprintf(dst, kNameSize, "%s", src); }

class PlanBuilder {
public:
    explicit PlanBuilder(Tpn* t) : t_(t) {
        *t_ = Tpn{};
        t_->eventCount = 1;
        setName(t_->events[0].name, "start");
    }

    std::uint16_t event(Guard g = Guard{}) {
        const std::uint16_t e = t_->eventCount++;
        std::snprintf(t_->events[e].name, kNameSize, "e%u", static_cast<unsigned>(e));
        t_->events[e].guard = g;
        return e;
    }

    std::uint16_t activity(ActivityKind kind, std::size_t from, std::size_t to, std::int32_t lbMs, std::int32_t ubMs,
                           double cost, Guard g = Guard{}) {
        const std::uint16_t a = t_->activityCount++;
        Activity& act = t_->activities[a];
        std::snprintf(act.name, kNameSize, "a%u", static_cast<unsigned>(a));
        act.kind = kind;
        act.from = static_cast<std::uint16_t>(from);
        act.to = static_cast<std::uint16_t>(to);
        act.duration = Bounds{lbMs, ubMs};
        act.cost = cost;
        act.guard = g;
        return a;
    }

    void ask(std::size_t a, Component c, ComponentState s, bool negated = false) {
        Activity& act = t_->activities[a];
        act.asks[act.askCount++] =
            Condition{false, static_cast<std::uint8_t>(c), static_cast<std::uint8_t>(s), negated};
    }
    void askVariable(std::size_t a, std::size_t variable, std::size_t value, bool negated = false) {
        Activity& act = t_->activities[a];
        act.asks[act.askCount++] =
            Condition{true, static_cast<std::uint8_t>(variable), static_cast<std::uint8_t>(value), negated};
    }
    void tell(std::size_t a, std::size_t variable, std::size_t value) {
        Activity& act = t_->activities[a];
        act.tells[act.tellCount++] =
            Condition{true, static_cast<std::uint8_t>(variable), static_cast<std::uint8_t>(value), false};
    }

    std::uint16_t constraint(std::size_t from, std::size_t to, std::int32_t lbMs, std::int32_t ubMs,
                             Guard g = Guard{}) {
        const std::uint16_t k = t_->constraintCount++;
        t_->constraints[k] = TemporalConstraint{static_cast<std::uint16_t>(from), static_cast<std::uint16_t>(to),
                                                Bounds{lbMs, ubMs}, g};
        return k;
    }

    // A choice whose options cost these (their own cost, beside their activities').
    std::uint8_t choice(std::size_t options, const double* optionCosts = nullptr, Guard g = Guard{}) {
        const std::uint8_t c = t_->choiceCount++;
        Choice& ch = t_->choices[c];
        std::snprintf(ch.name, kNameSize, "c%u", static_cast<unsigned>(c));
        ch.optionCount = static_cast<std::uint8_t>(options);
        ch.guard = g;
        for (std::size_t o = 0; o < options; ++o) {
            std::snprintf(ch.options[o].name, kNameSize, "o%u", static_cast<unsigned>(o));
            ch.options[o].cost = optionCosts != nullptr ? optionCosts[o] : 0.0;
        }
        return c;
    }

    std::uint8_t variable(std::size_t values) {
        const std::uint8_t v = t_->variableCount++;
        std::snprintf(t_->variables[v].name, kNameSize, "v%u", static_cast<unsigned>(v));
        t_->variables[v].valueCount = static_cast<std::uint8_t>(values);
        for (std::size_t i = 0; i < values; ++i) {
            std::snprintf(t_->variables[v].values[i], kNameSize, "x%u", static_cast<unsigned>(i));
        }
        return v;
    }

    Tpn& plan() { return *t_; }

private:
    Tpn* t_;
};

// The example: drive to target 1, choice {sample(1) ask grinder = ok
// | image(1) ask camera = ok}, drive to target 2, choice {sample(2) | image(2)}.
// Drives cost 10, samples 3, images 5 (sample cheaper), within a 2 h plan.
// Choices 0 and 1; option 0 sample, option 1 image.
inline void twoTargets(Tpn* t) {
    PlanBuilder b(t);
    const std::uint16_t at1 = b.event(), done1 = b.event(), at2 = b.event(), done2 = b.event();
    b.activity(ActivityKind::kDrive, 0, at1, 60000, 600000, 10.0);
    for (std::size_t k = 0; k < 2; ++k) {
        const std::uint8_t c = b.choice(2);
        const std::uint16_t from = k == 0 ? at1 : at2, to = k == 0 ? done1 : done2;
        const std::uint16_t s = b.activity(ActivityKind::kSample, from, to, 300000, 900000, 3.0, under(c, 0));
        b.ask(s, Component::kGrinder, ComponentState::kOk);
        t->activities[s].target = static_cast<std::uint8_t>(k + 1);
        const std::uint16_t i = b.activity(ActivityKind::kImage, from, to, 60000, 300000, 5.0, under(c, 1));
        b.ask(i, Component::kCamera, ComponentState::kOk);
        t->activities[i].target = static_cast<std::uint8_t>(k + 1);
        if (k == 0) {
            b.activity(ActivityKind::kDrive, done1, at2, 60000, 600000, 10.0);
        }
    }
    b.constraint(0, done2, 0, 7200000);
}

// A random small plan (for the exhaustive reference): 4..10 events, a few
// unguarded activities, up to maxChoices choices of 2..3 options (some
// nested), each option 0..2 activities, guarded and unguarded constraints,
// component Asks, a plan variable with Tells and Asks. Random component
// states and deprecations go with it. Every draw is a statement of its own:
// the order of a call's arguments is unspecified, and a seed must make the
// same plan on every target.
inline void randomSmallPlan(std::uint32_t seed, std::size_t maxChoices, Tpn* t, SelectionInput* input) {
    std::mt19937 rng(seed);
    const auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    const auto u = [&](int lo, int hi) { return static_cast<std::size_t>(uniform(lo, hi)); };
    PlanBuilder b(t);
    const std::size_t events = u(4, 10);
    for (std::size_t e = 1; e < events; ++e) {
        b.event();
    }
    const auto randomActivity = [&](Guard g) {
        std::size_t from = u(0, static_cast<int>(events) - 2);
        std::size_t to = u(static_cast<int>(from) + 1, static_cast<int>(events) - 1);
        const std::int32_t lb = uniform(0, 20) * 1000;
        const std::int32_t ub = uniform(0, 4) == 0 ? kInfiniteMs : lb + uniform(0, 20) * 1000;
        const auto kind = static_cast<ActivityKind>(uniform(0, 5));
        const std::uint16_t a = b.activity(kind, from, to, lb, ub, uniform(0, 40) * 0.5, g);
        if (uniform(0, 2) == 0) {
            const auto component = static_cast<Component>(uniform(0, 7));
            const auto state = static_cast<ComponentState>(uniform(0, 2));
            const bool negated = uniform(0, 1) == 1;
            b.ask(a, component, state, negated);
        }
        return a;
    };
    const std::uint8_t var = b.variable(3);
    for (std::size_t k = u(1, 3); k > 0; --k) {
        randomActivity(Guard{});
    }
    const std::size_t choices = u(0, static_cast<int>(maxChoices));
    for (std::size_t c = 0; c < choices; ++c) {
        Guard parent;
        if (c > 0 && uniform(0, 3) == 0) {
            const std::size_t p = u(0, static_cast<int>(c) - 1);
            parent = under(p, u(0, t->choices[p].optionCount - 1));
        }
        double costs[kMaxOptions] = {};
        const std::size_t options = u(2, 3);
        for (std::size_t o = 0; o < options; ++o) {
            costs[o] = uniform(0, 10) * 0.25;
        }
        const std::uint8_t ch = b.choice(options, costs, parent);
        for (std::size_t o = 0; o < options; ++o) {
            for (std::size_t k = u(0, 2); k > 0; --k) {
                randomActivity(under(ch, o));
            }
            if (uniform(0, 4) == 0) {
                const std::size_t from = u(0, static_cast<int>(events) - 1), to = u(0, static_cast<int>(events) - 1);
                const std::int32_t lb = uniform(-5, 5) * 1000;
                const std::int32_t ub = uniform(5, 40) * 1000;
                b.constraint(from, to, lb, ub, under(ch, o));
            }
        }
    }
    for (std::size_t k = u(0, 2); k > 0; --k) {
        const std::size_t to = u(1, static_cast<int>(events) - 1);
        const std::int32_t deadline = uniform(10, 60) * 1000;
        b.constraint(0, to, 0, deadline);
    }
    // Tells and Asks of the plan variable on random activities.
    for (std::size_t k = u(0, 3); k > 0 && t->activityCount > 0; --k) {
        Activity& a = t->activities[u(0, t->activityCount - 1)];
        if (a.tellCount < kMaxTells) {
            b.tell(static_cast<std::size_t>(&a - t->activities), var, u(0, 2));
        }
    }
    for (std::size_t k = u(0, 2); k > 0 && t->activityCount > 0; --k) {
        Activity& a = t->activities[u(0, t->activityCount - 1)];
        const std::size_t value = u(0, 2);
        const bool negated = uniform(0, 3) == 0;
        if (a.askCount < kMaxAsks) {
            b.askVariable(static_cast<std::size_t>(&a - t->activities), var, value, negated);
        }
    }
    *input = SelectionInput{};
    for (ComponentState& s : input->components) {
        const int r = uniform(0, 9);
        s = r < 6 ? ComponentState::kOk : (r < 8 ? ComponentState::kDegraded : ComponentState::kFailed);
    }
    for (std::size_t c = 0; c < t->choiceCount; ++c) {
        for (std::size_t o = 0; o < t->choices[c].optionCount; ++o) {
            input->deprecated[c][o] = uniform(0, 9) == 0;
        }
    }
}

// A mission plan of exactly `activities` activities (at least 3): a warm-up
// that Tells heater = warm, then stops while the activities and kMaxChoices
// allow, each a drive (asking two drives != failed) to the stop and a science
// choice there: sample (grinder = ok, asks heater = warm; cheapest, slowest),
// image (camera = ok; dear, quick) and, at half the stops, dig (grinder = ok;
// its duration may break the stop's window). Every sixth stop's sample holds
// a nested choice: stow the arm fast (dear) or slowly (cheap). Every fourth
// stop has a deadline from the start: the fastest options' time plus the
// slack the stops so far accrued, each 0.7 - 1.4 x what its sample takes
// beyond its image, so in about half the plans some deadline binds (fewer
// samples before it than the costs alone would choose). `tight`: 0.6 - 1.2 x,
// over-subscribed: every plan has binding deadlines, and the samples before
// each compete for its slack (a knapsack: the search's hard case, see
// docs/plan_executive.md). Waits fill up to the count; a communication
// window ends it.
inline void missionPlan(std::uint32_t seed, std::size_t activities, Tpn* t, bool tight = false) {
    std::mt19937 rng(seed);
    const auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    PlanBuilder b(t);
    const std::uint8_t heater = b.variable(2);  // 0 cold, 1 warm
    const std::uint16_t warm = b.event();
    const std::uint16_t warmUp = b.activity(ActivityKind::kWait, 0, warm, 30000, 120000, 0.5);
    b.tell(warmUp, heater, 1);
    std::uint16_t here = warm;
    std::int64_t minimum = 30000;  // the least time from the start to `here` (fastest options)
    std::int64_t slack = 0;        // what the stops so far allow beyond that
    for (std::size_t stop = 1; stop <= kMaxChoices; ++stop) {
        const bool three = uniform(0, 1) == 1;
        const bool nested = stop % 6 == 0;
        const std::size_t size = (three ? 4U : 3U) + (nested ? 2U : 0U);
        if (t->activityCount + size + 1 > activities || t->choiceCount + (nested ? 2U : 1U) > kMaxChoices ||
            t->eventCount + 4U > kMaxEvents) {
            break;
        }
        const std::uint16_t at = b.event(), done = b.event();
        const std::int32_t driveLb = uniform(60, 400) * 1000;
        const std::uint16_t drive =
            b.activity(ActivityKind::kDrive, here, at, driveLb, driveLb * 3 / 2, driveLb / 20000.0 + uniform(0, 4));
        b.ask(drive, static_cast<Component>(uniform(0, 2)), ComponentState::kFailed, true);
        b.ask(drive, static_cast<Component>(uniform(3, 5)), ComponentState::kFailed, true);
        const double optionCosts[3] = {0.0, 0.5, 1.0};
        const std::uint8_t c = b.choice(three ? 3 : 2, optionCosts);
        const std::int32_t sampleLb = uniform(200, 600) * 1000;
        const std::uint16_t sample = b.activity(ActivityKind::kSample, at, done, sampleLb, sampleLb + 120000,
                                                2.0 + uniform(0, 8) * 0.25, under(c, 0));
        b.ask(sample, Component::kGrinder, ComponentState::kOk);
        b.askVariable(sample, heater, 1);
        const std::int32_t imageLb = uniform(30, 200) * 1000;
        const std::uint16_t image = b.activity(ActivityKind::kImage, at, done, imageLb, imageLb + 60000,
                                               4.0 + uniform(0, 8) * 0.25, under(c, 1));
        b.ask(image, Component::kCamera, ComponentState::kOk);
        if (three) {
            const std::int32_t digLb = uniform(100, 900) * 1000;
            const std::uint16_t dig = b.activity(ActivityKind::kDig, at, done, digLb, digLb + 200000,
                                                 3.0 + uniform(0, 8) * 0.25, under(c, 2));
            b.ask(dig, Component::kGrinder, ComponentState::kOk);
        }
        if (nested) {
            const double stowCosts[2] = {1.5, 0.25};
            const std::uint8_t n = b.choice(2, stowCosts, under(c, 0));
            const std::uint16_t stowed = b.event(under(c, 0));
            b.activity(ActivityKind::kWait, done, stowed, 10000, 20000, 0.0, under(n, 0));
            b.activity(ActivityKind::kWait, done, stowed, 60000, 90000, 0.0, under(n, 1));
        }
        // The stop's window: the sample and the image fit, a dig may not.
        b.constraint(at, done, 0, (sampleLb > imageLb ? sampleLb : imageLb) + uniform(0, 300) * 1000);
        minimum += driveLb + imageLb;
        slack += sampleLb > imageLb ? (sampleLb - imageLb) / 10 * (tight ? uniform(6, 12) : uniform(7, 14)) : 0;
        if (stop % 4 == 0) {
            b.constraint(0, done, 0, static_cast<std::int32_t>(minimum + slack));
        }
        here = done;
    }
    while (t->activityCount + 1U < activities && t->eventCount + 1U < kMaxEvents) {
        const std::uint16_t next = b.event();
        b.activity(ActivityKind::kWait, here, next, 1000, 60000, 0.1);
        here = next;
    }
    b.activity(ActivityKind::kCommunicate, here, b.event(), 300000, 600000, 1.0);
}

}  // namespace rse::test::plan

// The exhaustive reference for method selection (test_method_selector,
// bench_plan_executive): every selection of a small plan enumerated and
// judged on its own, with nothing of the selector's search, bound, presolve
// or incremental network: existence from the guards, the Asks against the
// states, deprecations, where execution stands (executed times, not before,
// started activities' Asks taken as held),
// the STN built here and closed by Floyd-Warshall
// (stn.hpp), supports read off the closed matrix, the cost summed here.
// Exponential: for plans of a few choices.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/stn.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::test::plan {

using namespace rse::plan_executive;

struct ReferenceOutcome {
    bool found = false;
    double cost = 0.0;
    Selection best;
    std::size_t selections = 0;  // distinct complete selections judged
};

// An element exists when its guard's choice exists and picks that option
// (pick: an option for every choice, whether it exists or not).
inline bool referenceExists(const Tpn& t, const std::uint8_t* pick, Guard g) {
    for (std::size_t up = 0; up <= t.choiceCount; ++up) {
        if (g.choice == kNoChoice) {
            return true;
        }
        if (pick[g.choice] != g.option) {
            return false;
        }
        g = t.choices[g.choice].guard;
    }
    return false;  // a nesting cycle: nothing exists under it
}

// The expected-cost model written out again: a degraded component asked
// raises the cost once, and each degraded drive raises a drive's cost.
inline double referenceCost(const Tpn& t, const std::uint8_t* pick, const SelectionInput& in,
                            const SelectionParams& p) {
    int degradedDrives = 0;
    for (Component d : {Component::kDriveFL, Component::kDriveML, Component::kDriveRL, Component::kDriveFR,
                        Component::kDriveMR, Component::kDriveRR}) {
        degradedDrives += in.components[static_cast<int>(d)] == ComponentState::kDegraded;
    }
    double total = 0.0;
    for (std::size_t c = 0; c < t.choiceCount; ++c) {
        if (referenceExists(t, pick, t.choices[c].guard)) {
            total += t.choices[c].options[pick[c]].cost;
        }
    }
    for (std::size_t i = 0; i < t.activityCount; ++i) {
        const Activity& a = t.activities[i];
        if (!referenceExists(t, pick, a.guard)) {
            continue;
        }
        int degradedAsked = 0;
        for (std::size_t k = 0; k < a.askCount; ++k) {
            degradedAsked += !a.asks[k].planVariable && in.components[a.asks[k].variable] == ComponentState::kDegraded;
        }
        const double drive = a.kind == ActivityKind::kDrive ? p.drivePenalty * degradedDrives : 0.0;
        total += a.cost * (degradedAsked > 0 ? 1.0 + p.degradedPenalty : 1.0) * (1.0 + drive);
    }
    return total;
}

// Whether the selection picked can run: Asks, deprecations, consistency, supports.
inline bool referenceValid(const Tpn& t, const std::uint8_t* pick, const SelectionInput& in, Stn* stn) {
    for (std::size_t c = 0; c < t.choiceCount; ++c) {
        if (referenceExists(t, pick, t.choices[c].guard) && in.deprecated[c][pick[c]]) {
            return false;
        }
    }
    if (stn->reset(t.eventCount) != rse::core::Status::kOk) {
        return false;
    }
    bool ok = true;
    // Where execution stands: an executed event at its time, the others from
    // notBeforeMs (or their own later floor) on.
    for (std::size_t e = 1; e < t.eventCount; ++e) {
        const std::int32_t at = in.executedAtMs[e];
        const std::int32_t floor = std::max(in.notBeforeMs, in.notBeforeEventMs[e]);
        const Bounds fromStart = at == kInfiniteMs ? Bounds{floor, kInfiniteMs} : Bounds{at, at};
        ok = ok && stn->addBounds(0, e, fromStart) == rse::core::Status::kOk;
    }
    for (std::size_t i = 0; i < t.activityCount && ok; ++i) {
        const Activity& a = t.activities[i];
        if (!referenceExists(t, pick, a.guard)) {
            continue;
        }
        for (std::size_t k = 0; k < a.askCount; ++k) {
            const Condition& q = a.asks[k];
            const bool holds =
                in.started[i] || (in.components[q.variable] == static_cast<ComponentState>(q.value)) != q.negated;
            ok = ok && (q.planVariable || holds);
        }
        ok = ok && stn->addBounds(a.from, a.to, a.duration) == rse::core::Status::kOk;
    }
    for (std::size_t i = 0; i < t.constraintCount && ok; ++i) {
        const TemporalConstraint& tc = t.constraints[i];
        if (referenceExists(t, pick, tc.guard)) {
            ok = stn->addBounds(tc.from, tc.to, tc.bounds) == rse::core::Status::kOk;
        }
    }
    if (!ok || stn->check() != StnState::kConsistent) {
        return false;
    }
    // Every plan-variable Ask: some existing Tell of an answer ends no later
    // than the Ask's start in every schedule.
    for (std::size_t i = 0; i < t.activityCount; ++i) {
        const Activity& a = t.activities[i];
        for (std::size_t k = 0; k < a.askCount && referenceExists(t, pick, a.guard); ++k) {
            const Condition& q = a.asks[k];
            bool supported = !q.planVariable;
            for (std::size_t j = 0; j < t.activityCount && !supported; ++j) {
                const Activity& b = t.activities[j];
                for (std::size_t m = 0; m < b.tellCount; ++m) {
                    const bool answers = b.tells[m].planVariable && b.tells[m].variable == q.variable &&
                                         (b.tells[m].value == q.value) != q.negated;
                    supported = supported || (answers && referenceExists(t, pick, b.guard) &&
                                              stn->distance(a.from, b.to) <= 0);
                }
            }
            if (!supported) {
                return false;
            }
        }
    }
    return true;
}

// Every selection: an odometer over every choice's options; a pick that
// gives a non-existing choice anything but option 0 repeats another and is
// skipped.
inline ReferenceOutcome exhaustiveOptimum(const Tpn& t, const SelectionInput& in, const SelectionParams& p,
                                          Stn* stn) {
    ReferenceOutcome out;
    std::uint8_t pick[kMaxChoices] = {};
    for (bool more = true; more;) {
        bool repeat = false;
        for (std::size_t c = 0; c < t.choiceCount; ++c) {
            repeat = repeat || (pick[c] != 0 && !referenceExists(t, pick, t.choices[c].guard));
        }
        if (!repeat) {
            ++out.selections;
            const double cost = referenceCost(t, pick, in, p);
            if ((!out.found || cost < out.cost) && referenceValid(t, pick, in, stn)) {
                out.found = true;
                out.cost = cost;
                for (std::size_t c = 0; c < t.choiceCount; ++c) {
                    out.best.option[c] = referenceExists(t, pick, t.choices[c].guard) ? pick[c] : kNoOption;
                }
            }
        }
        more = false;
        for (std::size_t c = 0; c < t.choiceCount && !more; ++c) {
            pick[c] = static_cast<std::uint8_t>(pick[c] + 1);
            more = pick[c] < t.choices[c].optionCount;
            pick[c] = more ? pick[c] : 0;
        }
    }
    return out;
}

// A selection as the reference reads it: every choice an option (0 where none).
inline void pickOf(const Selection& s, std::size_t choices, std::uint8_t* pick) {
    for (std::size_t c = 0; c < choices; ++c) {
        pick[c] = s.option[c] == kNoOption ? 0 : s.option[c];
    }
}

}  // namespace rse::test::plan

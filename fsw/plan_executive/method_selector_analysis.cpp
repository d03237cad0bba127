// Method selection's set-up (method_selector.hpp): start()'s checks of the
// plan, its analysis (which activities and options are usable and what they
// cost, the choices in preorder), the network's edge list with the implied
// edges, and the two phases before the search: presolve (each option's
// thread against the unguarded network) and the options' subtree costs,
// their ranking and the root bound.
#include <cmath>

#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/method_selector_detail.hpp"

namespace rse::plan_executive {

namespace {

bool boundsOk(const Bounds& b) {
    const bool lbOk = b.lbMs >= -kMaxBoundMs && b.lbMs <= kMaxBoundMs;
    const bool ubOk = b.ubMs == kInfiniteMs || (b.ubMs >= -kMaxBoundMs && b.ubMs <= kMaxBoundMs);
    return lbOk && ubOk && b.lbMs <= b.ubMs;
}

bool guardOk(const Tpn& plan, const Guard& g) {
    return !g.guarded() || (g.choice < plan.choiceCount && g.option < plan.choices[g.choice].optionCount);
}

bool conditionOk(const Tpn& plan, const Condition& c) {
    if (c.planVariable) {
        return c.variable < plan.variableCount && c.value < plan.variables[c.variable].valueCount;
    }
    return c.variable < kComponentCount && c.value < kComponentStateCount;
}

bool componentAskHolds(const Condition& c, const SelectionInput& input) {
    return (static_cast<std::uint8_t>(input.components[c.variable]) == c.value) != c.negated;
}

// The edges are indexed by group (1 + kMaxChoices kMaxOptions of them) and
// by tail (kMaxEvents), a counting sort each.
constexpr std::size_t kMaxSortBuckets =
    1 + kMaxChoices * kMaxOptions > kMaxEvents ? 1 + kMaxChoices * kMaxOptions : kMaxEvents;

// Items 0..count-1 sorted by key[item] (< buckets) into out; bucket b's
// items are out[start[b]] .. out[start[b + 1] - 1].
void countingSort(std::size_t count, std::size_t buckets, const std::uint16_t* key, std::uint16_t* start,
                  std::uint16_t* out) {
    std::uint16_t next[kMaxSortBuckets + 1] = {};
    for (std::size_t i = 0; i < count; ++i) {
        ++next[key[i] + 1U];
    }
    for (std::size_t b = 0; b < buckets; ++b) {
        next[b + 1] = static_cast<std::uint16_t>(next[b + 1] + next[b]);
    }
    for (std::size_t b = 0; b <= buckets; ++b) {
        start[b] = next[b];
    }
    for (std::size_t i = 0; i < count; ++i) {
        out[next[key[i]]++] = static_cast<std::uint16_t>(i);
    }
}

}  // namespace

// ---------------------------------------------------------------------------
// Checks and analysis.

bool MethodSelector::validate(const Tpn& plan) const {
    if (plan.eventCount == 0 || plan.eventCount > kMaxEvents || plan.activityCount > kMaxActivities ||
        plan.constraintCount > kMaxConstraints || plan.choiceCount > kMaxChoices ||
        plan.variableCount > kMaxPlanVariables) {
        return false;
    }
    bool ok = true;
    for (std::size_t v = 0; v < plan.variableCount; ++v) {
        ok = ok && plan.variables[v].valueCount <= kMaxVariableValues;
    }
    for (std::size_t c = 0; c < plan.choiceCount && ok; ++c) {
        const Choice& ch = plan.choices[c];
        ok = ch.optionCount >= 1 && ch.optionCount <= kMaxOptions && guardOk(plan, ch.guard);
        for (std::size_t o = 0; o < ch.optionCount && ok; ++o) {
            ok = std::isfinite(ch.options[o].cost) && ch.options[o].cost >= 0.0;
        }
        // Nesting must end at an unguarded choice within choiceCount steps
        // (else the guards make a cycle).
        std::size_t up = c;
        for (std::size_t steps = 0; ok && plan.choices[up].guard.guarded(); ++steps) {
            up = plan.choices[up].guard.choice;
            ok = steps < plan.choiceCount && guardOk(plan, plan.choices[up].guard);
        }
    }
    for (std::size_t a = 0; a < plan.activityCount && ok; ++a) {
        const Activity& act = plan.activities[a];
        ok = act.from < plan.eventCount && act.to < plan.eventCount && boundsOk(act.duration) &&
             std::isfinite(act.cost) && act.cost >= 0.0 && guardOk(plan, act.guard) && act.askCount <= kMaxAsks &&
             act.tellCount <= kMaxTells;
        for (std::size_t k = 0; k < act.askCount && ok; ++k) {
            ok = conditionOk(plan, act.asks[k]);
        }
        for (std::size_t k = 0; k < act.tellCount && ok; ++k) {
            ok = conditionOk(plan, act.tells[k]);
        }
    }
    for (std::size_t k = 0; k < plan.constraintCount && ok; ++k) {
        const TemporalConstraint& tc = plan.constraints[k];
        ok = tc.from < plan.eventCount && tc.to < plan.eventCount && boundsOk(tc.bounds) && guardOk(plan, tc.guard);
    }
    return ok;
}

void MethodSelector::analyse(const SelectionInput& input) {
    choiceCount_ = plan_->choiceCount;
    analyseActivities(input);
    analyseOptions(input);
    orderChoices();
}

// Per activity: usable (its component Asks hold, or it started: they held
// then; each plan-variable Ask answerable by some Tell of the plan), why
// not, and its expected cost; the activities with a plan-variable Ask.
void MethodSelector::analyseActivities(const SelectionInput& input) {
    const Tpn& plan = *plan_;
    // Which (variable, value) pairs some activity of the plan Tells: an Ask
    // none could answer is unsupported in every selection.
    bool tellable[kMaxPlanVariables][kMaxVariableValues] = {};
    for (std::size_t a = 0; a < plan.activityCount; ++a) {
        for (std::size_t k = 0; k < plan.activities[a].tellCount; ++k) {
            const Condition& t = plan.activities[a].tells[k];
            if (t.planVariable) {
                tellable[t.variable][t.value] = true;
            }
        }
    }
    askerCount_ = 0;
    for (std::size_t a = 0; a < plan.activityCount; ++a) {
        const Activity& act = plan.activities[a];
        activityOk_[a] = true;
        bool asksVariable = false;
        for (std::size_t k = 0; k < act.askCount && activityOk_[a]; ++k) {
            const Condition& c = act.asks[k];
            if (!c.planVariable) {
                // A started activity's Asks held when it started (SelectionInput).
                activityOk_[a] = input.started[a] || componentAskHolds(c, input);
                activityWhy_[a] = RejectReason::kAskFailed;
                continue;
            }
            asksVariable = true;
            bool any = false;
            for (std::size_t v = 0; v < plan.variables[c.variable].valueCount; ++v) {
                any = any || (tellable[c.variable][v] && (v == c.value) != c.negated);
            }
            activityOk_[a] = any;
            activityWhy_[a] = RejectReason::kCausalLinkMissing;
        }
        activityCost_[a] = expectedCost(act, input, params_);
        if (asksVariable) {
            askers_[askerCount_++] = static_cast<std::uint16_t>(a);
        }
    }
}

// Options: own cost and static usability (deprecated first, then the
// first unusable activity's reason); the unguarded part likewise.
void MethodSelector::analyseOptions(const SelectionInput& input) {
    const Tpn& plan = *plan_;
    for (std::size_t c = 0; c < choiceCount_; ++c) {
        for (std::size_t o = 0; o < plan.choices[c].optionCount; ++o) {
            optionOwn_[c][o] = plan.choices[c].options[o].cost;
            optionOk_[c][o] = !input.deprecated[c][o];
            optionWhy_[c][o] = RejectReason::kDeprecated;
        }
    }
    baseCost_ = 0.0;
    baseOk_ = true;
    for (std::size_t a = 0; a < plan.activityCount; ++a) {
        const Guard& g = plan.activities[a].guard;
        double& cost = g.guarded() ? optionOwn_[g.choice][g.option] : baseCost_;
        bool& ok = g.guarded() ? optionOk_[g.choice][g.option] : baseOk_;
        RejectReason& why = g.guarded() ? optionWhy_[g.choice][g.option] : baseWhy_;
        cost += activityCost_[a];
        why = ok && !activityOk_[a] ? activityWhy_[a] : why;
        ok = ok && activityOk_[a];
    }
    for (std::size_t c = 0; c < choiceCount_; ++c) {
        for (std::size_t o = 0; o < plan.choices[c].optionCount; ++o) {
            if (!optionOk_[c][o]) {
                reject(optionWhy_[c][o]);
            }
        }
    }
}

// Every choice under its parent's group (counting sort), then the choices
// in preorder (each parent before its nested choices, which follow it at
// once): an explicit stack, each choice pushed once.
void MethodSelector::orderChoices() {
    const Tpn& plan = *plan_;
    std::uint8_t childCount[kGroups + 1] = {};
    for (std::size_t c = 0; c < choiceCount_; ++c) {
        ++childCount[groupOf(plan.choices[c].guard) + 1];
    }
    for (std::size_t g = 0; g < kGroups; ++g) {
        childCount[g + 1] = static_cast<std::uint8_t>(childCount[g + 1] + childCount[g]);
    }
    for (std::size_t g = 0; g <= kGroups; ++g) {
        childStart_[g] = childCount[g];
    }
    for (std::size_t c = 0; c < choiceCount_; ++c) {
        childChoice_[childCount[groupOf(plan.choices[c].guard)]++] = static_cast<std::uint8_t>(c);
    }
    std::uint8_t stack[kMaxChoices] = {};
    std::size_t top = 0;
    std::size_t placed = 0;
    for (std::size_t i = childStart_[1]; i-- > childStart_[0];) {
        stack[top++] = childChoice_[i];
    }
    while (top > 0) {
        const std::uint8_t c = stack[--top];
        order_[placed++] = c;
        for (std::size_t o = plan.choices[c].optionCount; o-- > 0;) {
            const std::size_t g = group(c, o);
            for (std::size_t i = childStart_[g + 1]; i-- > childStart_[g];) {
                stack[top++] = childChoice_[i];
            }
        }
    }
}

// ---------------------------------------------------------------------------
// The network's edges.

void MethodSelector::addEdge(std::size_t from, std::size_t to, std::int32_t weight, std::size_t g) {
    edgeFrom_[edgeCount_] = static_cast<std::uint16_t>(from);
    edgeTo_[edgeCount_] = static_cast<std::uint16_t>(to);
    edgeWeight_[edgeCount_] = weight;
    edgeGroup_[edgeCount_] = static_cast<std::uint16_t>(g);
    edgeOn_[edgeCount_] = false;
    ++edgeCount_;
}

void MethodSelector::sortEdgesByGroup() {
    countingSort(edgeCount_, kGroups, edgeGroup_, groupStart_, groupEdge_);
}

std::int32_t MethodSelector::tightestInGroup(std::size_t g, std::size_t from, std::size_t to) const {
    std::int32_t w = kInfiniteMs;  // none
    for (std::size_t i = groupStart_[g]; i < groupStart_[g + 1]; ++i) {
        const std::uint16_t e = groupEdge_[i];
        if (edgeFrom_[e] == from && edgeTo_[e] == to && edgeWeight_[e] < w) {
            w = edgeWeight_[e];
        }
    }
    return w;
}

void MethodSelector::buildNetwork(const SelectionInput& input) {
    const Tpn& plan = *plan_;
    // [lb, ub] from a to b: b - a <= ub (none when ub is infinite) and a - b <= -lb.
    edgeCount_ = 0;
    const auto addBounds = [this](std::size_t from, std::size_t to, const Bounds& b, const Guard& g) {
        if (b.ubMs != kInfiniteMs) {
            addEdge(from, to, b.ubMs, groupOf(g));
        }
        addEdge(to, from, -b.lbMs, groupOf(g));
    };
    for (std::size_t a = 0; a < plan.activityCount; ++a) {
        const Activity& act = plan.activities[a];
        addBounds(act.from, act.to, act.duration, act.guard);
    }
    for (std::size_t k = 0; k < plan.constraintCount; ++k) {
        const TemporalConstraint& tc = plan.constraints[k];
        addBounds(tc.from, tc.to, tc.bounds, tc.guard);
    }
    // The start precedes every event; where execution stands, an executed
    // event is fixed and the others are no earlier than notBeforeMs (or their own floor).
    for (std::size_t e = 1; e < n_; ++e) {
        const Bounds b = selector_detail::fromStart(&input, e);
        addBounds(0, e, b, Guard{});
    }
    sortEdgesByGroup();
    addImpliedEdges();
    sortEdgesByGroup();
    countingSort(edgeCount_, n_, edgeFrom_, adjacencyStart_, adjacency_);  // adjacency by tail
    for (std::size_t v = 0; v < n_; ++v) {
        pi_[v] = 0;
        mark_[v] = selector_detail::kUnseen;
        candidate_[v] = false;
    }
}

// Implied edges: an edge a -> b that every usable option of a choice
// has (as one of its own elements' edges) holds, at the loosest of their
// weights, wherever the choice exists: it joins the choice's own group
// (its parent's option, or the unguarded network). It is redundant in
// every complete selection, so it changes no answer; it lets the search
// see a deadline break before the choices that break it are decided (an
// undecided stop would otherwise take no time at all).
void MethodSelector::addImpliedEdges() {
    const Tpn& plan = *plan_;
    for (std::size_t c = 0; c < choiceCount_; ++c) {
        std::size_t first = 0;
        while (first < plan.choices[c].optionCount && !optionOk_[c][first]) {
            ++first;
        }
        if (first == plan.choices[c].optionCount) {
            continue;  // no usable option: the choice rules itself out
        }
        const std::size_t g0 = group(c, first);
        for (std::size_t i = groupStart_[g0]; i < groupStart_[g0 + 1]; ++i) {
            const std::uint16_t e = groupEdge_[i];
            bool seen = false;  // the pair's implied edge is made once, at its first edge
            for (std::size_t j = groupStart_[g0]; j < i; ++j) {
                seen = seen || (edgeFrom_[groupEdge_[j]] == edgeFrom_[e] && edgeTo_[groupEdge_[j]] == edgeTo_[e]);
            }
            std::int32_t implied = seen ? kInfiniteMs : tightestInGroup(g0, edgeFrom_[e], edgeTo_[e]);
            for (std::size_t o = first + 1; o < plan.choices[c].optionCount && implied != kInfiniteMs; ++o) {
                const std::int32_t w =
                    optionOk_[c][o] ? tightestInGroup(group(c, o), edgeFrom_[e], edgeTo_[e]) : implied;
                implied = w > implied ? w : implied;
            }
            if (implied != kInfiniteMs) {
                addEdge(edgeFrom_[e], edgeTo_[e], implied, groupOf(plan.choices[c].guard));
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Presolve: every usable option's own thread against the unguarded network.

void MethodSelector::presolveAction() {
    if (thread_ == ThreadState::kRunning) {
        threadAction();
        if (thread_ != ThreadState::kRunning) {
            const std::size_t c = order_[presolvePos_];
            if (thread_ == ThreadState::kFailed) {
                optionOk_[c][presolveOption_] = false;
                optionWhy_[c][presolveOption_] = RejectReason::kInconsistent;
                reject(RejectReason::kInconsistent);
            }
            undoThread(group(c, presolveOption_));
            thread_ = ThreadState::kIdle;
            ++presolveOption_;
        }
        return;
    }
    ++stats_.work;
    while (presolvePos_ < choiceCount_) {
        const std::size_t c = order_[presolvePos_];
        ++stats_.work;
        if (presolveOption_ >= plan_->choices[c].optionCount) {
            ++presolvePos_;
            presolveOption_ = 0;
        } else if (!optionOk_[c][presolveOption_]) {
            ++presolveOption_;
        } else {
            beginThread(group(c, presolveOption_));
            return;
        }
    }
    computeCosts();
}

void MethodSelector::computeCosts() {
    // Children before parents (reverse preorder): an option's subtree cost is
    // its own plus each nested choice's cheapest; a nested choice with no
    // usable option makes the option unusable, for that choice's reason.
    for (std::size_t p = choiceCount_; p-- > 0;) {
        const std::size_t c = order_[p];
        const std::size_t options = plan_->choices[c].optionCount;
        choiceMin_[c] = selector_detail::kInfinite;
        for (std::size_t o = 0; o < options; ++o) {
            const std::size_t g = group(c, o);
            double cost = optionOwn_[c][o];
            for (std::size_t i = childStart_[g]; i < childStart_[g + 1] && optionOk_[c][o]; ++i) {
                const std::size_t child = childChoice_[i];
                cost += choiceMin_[child];
                if (!std::isfinite(choiceMin_[child])) {
                    optionOk_[c][o] = false;
                    optionWhy_[c][o] = optionWhy_[child][0];
                    reject(optionWhy_[c][o]);
                }
            }
            optionCost_[c][o] = optionOk_[c][o] ? cost : selector_detail::kInfinite;
            choiceMin_[c] = optionCost_[c][o] < choiceMin_[c] ? optionCost_[c][o] : choiceMin_[c];
            // Insertion into the cheapest-first ranking (ties: lower index first).
            std::size_t r = o;
            for (; r > 0 && optionCost_[c][rankedOption_[c][r - 1]] > optionCost_[c][o]; --r) {
                rankedOption_[c][r] = rankedOption_[c][r - 1];
            }
            rankedOption_[c][r] = static_cast<std::uint8_t>(o);
            stats_.work += 1U + static_cast<std::uint64_t>(childStart_[g + 1] - childStart_[g]);
        }
    }
    double open = 0.0;
    for (std::size_t i = childStart_[0]; i < childStart_[1]; ++i) {
        open += choiceMin_[childChoice_[i]];
    }
    stats_.rootBound = baseCost_ + open;
    if (!std::isfinite(stats_.rootBound)) {
        finish(SelectionStatus::kNoneExists);
        return;
    }
    cost_ = baseCost_;
    open_ = open;
    phase_ = Phase::kSearch;
    search_ = SearchStep::kDescend;
}

}  // namespace rse::plan_executive

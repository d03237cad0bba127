#include "fsw/plan_executive/method_selector.hpp"

#include <cmath>
#include <limits>

namespace rse::plan_executive {

namespace {

constexpr double kInfinite = std::numeric_limits<double>::infinity();
constexpr std::uint16_t kNoEdge = 0xFFFF;
constexpr std::int64_t kNoCutoff = std::numeric_limits<std::int64_t>::max();
constexpr std::size_t kDriveCount = 6;  // Component::kDriveFL .. kDriveRR
constexpr std::uint8_t kUnseen = 0;
constexpr std::uint8_t kQueued = 1;
constexpr std::uint8_t kSettled = 2;

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

// Whether a Tell (plan variable, value) answers an Ask.
bool tellSupports(const Condition& tell, const Condition& ask) {
    return tell.planVariable && tell.variable == ask.variable && (tell.value == ask.value) != ask.negated;
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

const char* toString(SelectionStatus s) {
    switch (s) {
        case SelectionStatus::kRunning: return "running";
        case SelectionStatus::kSelected: return "selected";
        case SelectionStatus::kSelectedInBudget: return "selected within budget";
        case SelectionStatus::kNoneExists: return "none exists";
        case SelectionStatus::kNoneFound: return "none found in budget";
        case SelectionStatus::kBadPlan: return "bad plan";
    }
    return "?";
}

double expectedCost(const Activity& a, const SelectionInput& input, const SelectionParams& params) {
    bool asksDegraded = false;
    for (std::size_t k = 0; k < a.askCount && k < kMaxAsks; ++k) {
        const Condition& c = a.asks[k];
        asksDegraded = asksDegraded || (!c.planVariable && c.variable < kComponentCount &&
                                        input.components[c.variable] == ComponentState::kDegraded);
    }
    double factor = asksDegraded ? 1.0 + params.degradedPenalty : 1.0;
    if (a.kind == ActivityKind::kDrive) {
        std::size_t degraded = 0;
        for (std::size_t d = 0; d < kDriveCount; ++d) {
            degraded += input.components[d] == ComponentState::kDegraded ? 1U : 0U;
        }
        factor *= 1.0 + params.drivePenalty * static_cast<double>(degraded);
    }
    return a.cost * factor;
}

double selectionCost(const Tpn& plan, const Selection& s, const SelectionInput& input, const SelectionParams& params) {
    double cost = 0.0;
    for (std::size_t a = 0; a < plan.activityCount && a < kMaxActivities; ++a) {
        cost += exists(plan.activities[a].guard, s) ? expectedCost(plan.activities[a], input, params) : 0.0;
    }
    for (std::size_t c = 0; c < plan.choiceCount && c < kMaxChoices; ++c) {
        const std::uint8_t o = s.option[c];
        cost += o < plan.choices[c].optionCount ? plan.choices[c].options[o].cost : 0.0;
    }
    return cost;
}

namespace {

bool timeOk(std::int32_t t) { return t >= 0 && t <= kMaxBoundMs; }

// Where execution stands is usable: times after the start, within the bounds' range.
bool executionOk(const SelectionInput& input, std::size_t events) {
    bool ok = timeOk(input.notBeforeMs);
    for (std::size_t e = 1; e < events && e < kMaxEvents; ++e) {
        ok = ok && (input.executedAtMs[e] == kInfiniteMs || timeOk(input.executedAtMs[e])) &&
             timeOk(input.notBeforeEventMs[e]);
    }
    return ok;
}

// The start's bounds to event e (SelectionInput "Regeneration"); input null: [0, inf).
Bounds fromStart(const SelectionInput* input, std::size_t e) {
    if (input == nullptr) {
        return Bounds{0, kInfiniteMs};
    }
    const std::int32_t at = input->executedAtMs[e];
    const std::int32_t floor =
        input->notBeforeEventMs[e] > input->notBeforeMs ? input->notBeforeEventMs[e] : input->notBeforeMs;
    return at == kInfiniteMs ? Bounds{floor, kInfiniteMs} : Bounds{at, at};
}

core::Status loadStnFrom(const Tpn& plan, const Selection& s, const SelectionInput* input, Stn* stn) {
    if (stn == nullptr || plan.activityCount > kMaxActivities || plan.constraintCount > kMaxConstraints ||
        (input != nullptr && !executionOk(*input, plan.eventCount))) {
        return core::Status::kInvalidArgument;
    }
    core::Status st = stn->reset(plan.eventCount);
    for (std::size_t e = 1; e < plan.eventCount && core::isOk(st); ++e) {
        st = stn->addBounds(0, e, fromStart(input, e));
    }
    for (std::size_t a = 0; a < plan.activityCount && core::isOk(st); ++a) {
        const Activity& act = plan.activities[a];
        st = exists(act.guard, s) ? stn->addBounds(act.from, act.to, act.duration) : st;
    }
    for (std::size_t k = 0; k < plan.constraintCount && core::isOk(st); ++k) {
        const TemporalConstraint& tc = plan.constraints[k];
        st = exists(tc.guard, s) ? stn->addBounds(tc.from, tc.to, tc.bounds) : st;
    }
    return st;
}

}  // namespace

core::Status loadStn(const Tpn& plan, const Selection& s, Stn* stn) { return loadStnFrom(plan, s, nullptr, stn); }

core::Status loadStn(const Tpn& plan, const Selection& s, const SelectionInput& input, Stn* stn) {
    return loadStnFrom(plan, s, &input, stn);
}

// ---------------------------------------------------------------------------
// Set-up.

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
    const Tpn& plan = *plan_;
    choiceCount_ = plan.choiceCount;
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

    // Options: own cost and static usability (deprecated first, then the
    // first unusable activity's reason); the unguarded part likewise.
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

    // Every choice under its parent's group (counting sort), then the
    // choices in preorder (each parent before its nested choices, which
    // follow it at once): an explicit stack, each choice pushed once.
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
        const Bounds b = fromStart(&input, e);
        addBounds(0, e, b, Guard{});
    }
    sortEdgesByGroup();
    // Implied edges: an edge a -> b that every usable option of a choice
    // has (as one of its own elements' edges) holds, at the loosest of their
    // weights, wherever the choice exists: it joins the choice's own group
    // (its parent's option, or the unguarded network). It is redundant in
    // every complete selection, so it changes no answer; it lets the search
    // see a deadline break before the choices that break it are decided (an
    // undecided stop would otherwise take no time at all).
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
    sortEdgesByGroup();
    countingSort(edgeCount_, n_, edgeFrom_, adjacencyStart_, adjacency_);  // adjacency by tail
    for (std::size_t v = 0; v < n_; ++v) {
        pi_[v] = 0;
        mark_[v] = kUnseen;
        candidate_[v] = false;
    }
}

core::Status MethodSelector::start(const Tpn& plan, const SelectionInput& input, const SelectionParams& params) {
    best_ = SelectionResult{};
    stats_ = SelectionStats{};
    chosen_ = Selection{};
    depth_ = 0;
    cost_ = open_ = 0.0;
    queueSize_ = touchedSize_ = 0;
    candidateCount_ = 0;
    dijkstraRunning_ = false;
    thread_ = ThreadState::kIdle;
    plan_ = &plan;
    params_ = params;
    const bool paramsOk = std::isfinite(params.degradedPenalty) && params.degradedPenalty >= 0.0 &&
                          std::isfinite(params.drivePenalty) && params.drivePenalty >= 0.0 && params.workBudget > 0;
    if (!paramsOk || !validate(plan) || !executionOk(input, plan.eventCount)) {
        finish(SelectionStatus::kBadPlan);
        return core::Status::kInvalidArgument;
    }
    n_ = plan.eventCount;
    analyse(input);
    buildNetwork(input);
    if (!baseOk_) {
        reject(baseWhy_);
        finish(SelectionStatus::kNoneExists);
        return core::Status::kOk;
    }
    phase_ = Phase::kBase;
    beginThread(0);
    return core::Status::kOk;
}

// ---------------------------------------------------------------------------
// Running.

bool MethodSelector::step(std::uint32_t maxUnits) {
    const std::uint64_t limit = stats_.work + maxUnits;
    while (phase_ != Phase::kDone && stats_.work < limit && stats_.work < params_.workBudget) {
        action();
    }
    // The slice that spends the budget ends the selection (not the next one).
    if (phase_ != Phase::kDone && stats_.work >= params_.workBudget) {
        finish(best_.hasSelection ? SelectionStatus::kSelectedInBudget : SelectionStatus::kNoneFound);
    }
    return phase_ == Phase::kDone;
}

SelectionStatus MethodSelector::solve(const Tpn& plan, const SelectionInput& input, const SelectionParams& params,
                                      SelectionResult* out) {
    if (core::isOk(start(plan, input, params))) {
        (void)step(UINT32_MAX);  // the budget fits in 32 bits: one call runs to it, or to the end
    }
    if (out != nullptr) {
        *out = best_;
    }
    return best_.status;
}

void MethodSelector::finish(SelectionStatus status) {
    if (dijkstraRunning_) {
        endDijkstra();
    }
    best_.status = status;
    phase_ = Phase::kDone;
}

void MethodSelector::action() {
    switch (phase_) {
        case Phase::kBase:
            threadAction();
            if (thread_ == ThreadState::kFailed) {
                reject(RejectReason::kInconsistent);
                finish(SelectionStatus::kNoneExists);
            } else if (thread_ == ThreadState::kDone) {
                phase_ = Phase::kPresolve;
                presolvePos_ = presolveOption_ = 0;
            }
            break;
        case Phase::kPresolve:
            presolveAction();
            break;
        case Phase::kSearch:
            searchAction();
            break;
        case Phase::kIdle:
        case Phase::kDone:
            ++stats_.work;
            break;
    }
}

// ---------------------------------------------------------------------------
// Threads and the incremental network.

void MethodSelector::beginThread(std::size_t g) {
    threadGroup_ = g;
    threadPos_ = 0;
    thread_ = ThreadState::kRunning;
}

void MethodSelector::threadAction() {
    if (dijkstraRunning_) {
        // Repairing pi after repairEdge_ (u -> v): settle the event whose
        // schedule moves most; reaching u is a negative cycle through the edge.
        const std::uint16_t x = popMin();
        if (x == edgeFrom_[repairEdge_]) {
            endDijkstra();
            thread_ = ThreadState::kFailed;
            return;
        }
        relaxFrom(x, 0);
        if (queueSize_ == 0) {
            for (std::size_t i = 0; i < touchedSize_; ++i) {
                pi_[touched_[i]] += key_[touched_[i]];  // every touched event is settled
            }
            stats_.work += touchedSize_;
            endDijkstra();
            edgeOn_[repairEdge_] = true;
        }
        return;
    }
    ++stats_.work;
    const std::size_t next = groupStart_[threadGroup_] + threadPos_;
    if (next >= groupStart_[threadGroup_ + 1]) {
        thread_ = ThreadState::kDone;
        return;
    }
    ++threadPos_;
    const std::uint16_t e = groupEdge_[next];
    const std::uint16_t u = edgeFrom_[e];
    const std::uint16_t v = edgeTo_[e];
    const std::int64_t slack = pi_[u] + edgeWeight_[e] - pi_[v];
    if (slack >= 0) {
        edgeOn_[e] = true;  // the schedule already meets it
    } else {
        repairEdge_ = e;
        beginDijkstra(v, slack);
    }
}

void MethodSelector::undoThread(std::size_t g) {
    stats_.work += 1U + groupStart_[g + 1] - groupStart_[g];
    for (std::size_t i = groupStart_[g]; i < groupStart_[g + 1]; ++i) {
        edgeOn_[groupEdge_[i]] = false;
    }
}

void MethodSelector::beginDijkstra(std::uint16_t source, std::int64_t key) {
    key_[source] = key;
    mark_[source] = kQueued;
    queue_[0] = source;
    touched_[0] = source;
    queueSize_ = touchedSize_ = 1;
    dijkstraRunning_ = true;
}

std::uint16_t MethodSelector::popMin() {
    std::size_t best = 0;
    for (std::size_t i = 1; i < queueSize_; ++i) {
        best = key_[queue_[i]] < key_[queue_[best]] ? i : best;
    }
    stats_.work += 1 + queueSize_;
    const std::uint16_t x = queue_[best];
    queue_[best] = queue_[--queueSize_];
    mark_[x] = kSettled;
    return x;
}

void MethodSelector::relaxFrom(std::uint16_t x, std::int64_t cutoff) {
    // Reduced costs pi(x) + w - pi(y) >= 0 on every edge that is on (the
    // edge under repair is not on yet), so keys settle in order.
    const std::int64_t base = key_[x] + pi_[x];
    for (std::size_t i = adjacencyStart_[x]; i < adjacencyStart_[x + 1]; ++i) {
        ++stats_.work;
        const std::uint16_t e = adjacency_[i];
        const std::uint16_t y = edgeTo_[e];
        if (!edgeOn_[e] || mark_[y] == kSettled) {
            continue;
        }
        const std::int64_t k = base + edgeWeight_[e] - pi_[y];
        if (k >= cutoff) {
            continue;  // a repair moves only events it must
        }
        if (mark_[y] == kUnseen) {
            mark_[y] = kQueued;
            key_[y] = k;
            queue_[queueSize_++] = y;
            touched_[touchedSize_++] = y;
        } else if (k < key_[y]) {
            key_[y] = k;
        }
    }
}

void MethodSelector::endDijkstra() {
    for (std::size_t i = 0; i < touchedSize_; ++i) {
        mark_[touched_[i]] = kUnseen;
    }
    stats_.work += touchedSize_;
    queueSize_ = touchedSize_ = 0;
    dijkstraRunning_ = false;
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
        choiceMin_[c] = kInfinite;
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
            optionCost_[c][o] = optionOk_[c][o] ? cost : kInfinite;
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

// ---------------------------------------------------------------------------
// Search.

void MethodSelector::searchAction() {
    switch (search_) {
        case SearchStep::kNextOption:
            nextOption();
            break;
        case SearchStep::kAddThread:
            threadAction();
            if (thread_ == ThreadState::kDone) {
                thread_ = ThreadState::kIdle;
                search_ = SearchStep::kDescend;
            } else if (thread_ == ThreadState::kFailed) {
                thread_ = ThreadState::kIdle;
                reject(RejectReason::kInconsistent);
                search_ = SearchStep::kNextOption;
            }
            break;
        case SearchStep::kDescend:
            descend();
            break;
        case SearchStep::kSupports:
            supportAction();
            break;
    }
}

void MethodSelector::nextOption() {
    ++stats_.work;
    if (depth_ == 0) {
        finish(best_.hasSelection ? SelectionStatus::kSelected : SelectionStatus::kNoneExists);
        return;
    }
    Level& level = level_[depth_ - 1];
    const std::size_t c = level.choice;
    if (level.applied != kNoOption) {
        // Leave the option tried last: its edges off (pi still meets the
        // rest), the choice undecided, the costs as they were.
        undoThread(group(c, level.applied));
        chosen_.option[c] = kNoOption;
        cost_ = level.costBefore;
        open_ = level.openBefore;
        level.applied = kNoOption;
        return;
    }
    // Options cheapest first (their subtree's cost; unusable ones last).
    // The bound: what is decided, this option's subtree and the other open
    // choices' cheapest. It grows with the rank, so the first option pruned
    // prunes the rest.
    const std::size_t options = plan_->choices[c].optionCount;
    if (level.next < options) {
        const std::uint8_t o = rankedOption_[c][level.next];
        const double cost = level.costBefore + optionOwn_[c][o];
        const double open = level.openBefore - choiceMin_[c] + (optionCost_[c][o] - optionOwn_[c][o]);
        if (!optionOk_[c][o] || (best_.hasSelection && cost + open >= best_.cost)) {
            for (std::size_t r = level.next; r < options; ++r) {
                stats_.prunedByBound += optionOk_[c][rankedOption_[c][r]] ? 1U : 0U;
            }
            level.next = static_cast<std::uint8_t>(options);
            return;
        }
        ++level.next;
        level.applied = o;
        chosen_.option[c] = o;
        cost_ = cost;
        open_ = open;
        ++stats_.nodes;
        beginThread(group(c, o));
        search_ = SearchStep::kAddThread;
        return;
    }
    --depth_;  // this choice is done; its parent's option is left next
}

void MethodSelector::descend() {
    std::size_t p = depth_ == 0 ? 0 : level_[depth_ - 1].pos + 1U;
    ++stats_.work;
    for (; p < choiceCount_; ++p) {
        ++stats_.work;
        const std::uint8_t c = order_[p];
        if (exists(plan_->choices[c].guard, chosen_)) {
            level_[depth_++] = Level{c, static_cast<std::uint8_t>(p), 0, kNoOption, cost_, open_};
            search_ = SearchStep::kNextOption;
            return;
        }
    }
    // Every existing choice is decided: a complete selection.
    search_ = SearchStep::kNextOption;
    if (best_.hasSelection && cost_ >= best_.cost) {
        ++stats_.prunedByBound;  // rounding let it through: no better than the incumbent
        return;
    }
    ++stats_.leaves;
    supportAsker_ = supportAsk_ = 0;
    search_ = SearchStep::kSupports;
}

bool MethodSelector::beginSupportCheck() {
    // The next plan-variable Ask of an existing activity; its candidate
    // supports: the end events of existing activities that Tell an answer.
    ++stats_.work;
    for (std::size_t i = 0; i < candidateCount_; ++i) {
        candidate_[candidateList_[i]] = false;
    }
    stats_.work += candidateCount_;
    candidateCount_ = 0;
    const Tpn& plan = *plan_;
    for (; supportAsker_ < askerCount_; ++supportAsker_, supportAsk_ = 0) {
        const Activity& asker = plan.activities[askers_[supportAsker_]];
        ++stats_.work;
        if (!exists(asker.guard, chosen_)) {
            continue;
        }
        for (; supportAsk_ < asker.askCount; ++supportAsk_) {
            const Condition& ask = asker.asks[supportAsk_];
            if (!ask.planVariable) {
                continue;
            }
            for (std::size_t b = 0; b < plan.activityCount; ++b) {
                const Activity& teller = plan.activities[b];
                stats_.work += 1U + teller.tellCount;
                bool tells = false;
                for (std::size_t k = 0; k < teller.tellCount; ++k) {
                    tells = tells || tellSupports(teller.tells[k], ask);
                }
                if (tells && !candidate_[teller.to] && exists(teller.guard, chosen_)) {
                    candidate_[teller.to] = true;
                    candidateList_[candidateCount_++] = teller.to;
                }
            }
            ++supportAsk_;
            supportFound_ = false;
            candidatesLeft_ = candidateCount_;
            supportSource_ = asker.from;
            if (candidateCount_ > 0) {
                beginDijkstra(asker.from, 0);
            }
            return true;
        }
    }
    return false;
}

void MethodSelector::supportAction() {
    if (!dijkstraRunning_) {
        if (!beginSupportCheck()) {
            // Every Ask supported: a valid selection, better than the incumbent.
            best_.hasSelection = true;
            best_.cost = cost_;
            best_.selection = chosen_;
            ++stats_.incumbents;
            search_ = SearchStep::kNextOption;
        } else if (!dijkstraRunning_) {
            reject(RejectReason::kCausalLinkMissing);  // no existing activity Tells an answer
            search_ = SearchStep::kNextOption;
        }
        return;
    }
    // Distances from the Ask's start: d(s, x) = key(x) - pi(s) + pi(x).
    const std::uint16_t x = popMin();
    if (candidate_[x]) {
        --candidatesLeft_;
        supportFound_ = key_[x] - pi_[supportSource_] + pi_[x] <= 0;
    }
    if (!supportFound_ && candidatesLeft_ > 0) {
        relaxFrom(x, kNoCutoff);
    }
    if (supportFound_ || candidatesLeft_ == 0 || queueSize_ == 0) {
        endDijkstra();
        if (!supportFound_) {
            reject(RejectReason::kCausalLinkMissing);
            search_ = SearchStep::kNextOption;
        }
    }
}

}  // namespace rse::plan_executive

// Method selection: one option for every choice of a plan (tpn.hpp) that
// exists, the cheapest in expected cost among the selections that can run.
// docs/plan_executive.md "Method selection".
//
// Existence. An element (activity, constraint, nested choice) guarded by
// (c, o) exists when choice c exists and takes option o; unguarded ones
// always exist. Event 0 is the start and no event precedes it (a [0, inf)
// bound from event 0 to every other event, here and in loadStn()).
//
// A selection is valid when, over what exists:
//   - every Ask on a component holds in the given states (a failed component
//     makes every option whose activities ask it ok unusable), and no chosen
//     option is deprecated (SelectionInput::deprecated, the executive's word);
//   - every Ask on a plan variable is supported: some existing activity Tells
//     the variable the asked value (for "!=": any other value) and its end
//     event precedes the asking activity's start in every schedule, i.e. the
//     STN distance d(askStart, tellEnd) <= 0;
//   - the STN of the existing activities and constraints is consistent.
// Its expected cost: the sum over existing activities of cost x factor, plus
// the chosen options' own costs (every cost >= 0: start() refuses others).
// The factor (decision-theoretic dispatch) prices what the estimate says:
// x (1 + degradedPenalty) for an activity that asks a component mode
// estimation calls degraded (once, however many it asks), and for a drive
// activity x (1 + drivePenalty x the number of degraded drives).
//
// Search. Depth-first branch and bound over the choices in a fixed order,
// parents before their nested choices (so a choice's existence is known when
// it is reached), each choice's options cheapest first. A node's bound is the
// cost so far plus, for every open choice (existing, undecided), its cheapest
// usable option counting that option's activities and, recursively, the
// cheapest of its nested choices: admissible, since every completion pays at
// least that. A branch whose bound reaches the incumbent is
// pruned, so an exhausted search proves its incumbent optimal (or that none
// exists). Before the search, a presolve tries every option's own thread
// (its activities and constraints) against the unguarded network: an option
// inconsistent there is inconsistent in every selection, so it is dropped
// and the bound no longer counts it. Plan-variable support is checked on
// complete selections (adding bounds only shortens distances, so a partial
// one proves nothing), and statically: an Ask no activity of the plan could
// support rules its option out at once.
//
// Consistency, incrementally. The network is a static edge list (every edge
// the plan could have; an edge is on while its element exists) and a
// potential pi, a schedule meeting every edge that is on. Choosing an option
// turns its thread's edges on one at a time; an edge pi already meets costs
// nothing, else a Dijkstra on reduced costs from its head repairs pi, and
// reaching the edge's tail is a negative cycle (Cotton and Maler 2006).
// Backtracking turns edges off: pi still meets what is left, so nothing is
// restored. A support check is a Dijkstra on the same reduced costs from the
// asking activity's start. Implied edges: an edge a -> b that every usable
// option of a choice has is on, at the loosest of their weights, wherever
// the choice exists, before it is decided (with the unguarded network, or
// with the parent's option). It changes no answer (the chosen option's own
// edge is at least as tight) but an undecided stop then takes at least its
// fastest option's time, so a deadline that the choices made so far break is
// seen at once, not only when the last choice before it is decided.
//
// Limits. The bound knows nothing of time: where several choices compete for
// one deadline's slack (a knapsack), proving the optimum is exponential in
// them, and the budget ends the search with the best selection found
// (kSelectedInBudget; docs/plan_executive.md, bench_plan_executive's tight
// plans).
//
// Bounded and sliceable. No clock is read: work is counted, in units of about
// one elementary operation (an edge looked at, a queue entry scanned, an
// element visited: 1.5 - 4.3 ns on the development host, by its load).
// step(maxUnits)
// runs actions until its work reaches maxUnits; one action is one Dijkstra
// settle, one edge turned on, one option tried, one thread undone or one
// support check's candidates marked, at most kMaxActionWork units, so step()
// overruns by less than that and work() never exceeds the budget by more
// than kMaxActionWork (test_method_selector asserts both on the largest
// plan). start() validates and analyses the plan in time linear in its size
// (quadratic only in a choice's own thread, for its implied edges), not
// counted: under 100 us for kMaxActivities activities (bench_plan_executive).
// The budget ends the search: the best selection so far stands, not proven.
//
// Status. kSelected: the search was exhausted, the selection is optimal.
// kSelectedInBudget: a valid selection, the budget ran out before the proof.
// kNoneExists: proven, no valid selection. kNoneFound: none found within the
// budget. kBadPlan: start() refused the plan (kInvalidArgument).
//
// Memory: sizeof(MethodSelector) = 48 640 B on x86-64 (bench_plan_executive
// prints it): the kMaxEdges edges (tail, head, weight, group, on) and their
// two indexes (by group, by tail), per-event potentials and Dijkstra scratch,
// the option tables, the search stack of kMaxChoices levels, two selections.
// Static storage (a member), never a stack. The plan is read, not copied: it
// must stay unchanged from start() until finished().
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/plan_executive/stn.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

constexpr std::uint8_t kNoOption = 0xFF;  // Selection::option of a choice that does not exist

// The option each choice takes; kNoOption where the choice does not exist.
struct Selection {
    std::uint8_t option[kMaxChoices];
    Selection() {
        for (std::uint8_t& o : option) {
            o = kNoOption;
        }
    }
};

// Whether an element with this guard exists under the selection.
inline bool exists(const Guard& guard, const Selection& s) {
    return !guard.guarded() || (guard.choice < kMaxChoices && s.option[guard.choice] == guard.option);
}

// What selection is made under: the components' states, the options the
// executive has deprecated and, for a plan re-selected mid-execution (a
// regeneration), where execution stands.
//
// Regeneration. Times are ms since the plan's start (event 0, at 0). An event
// already executed is fixed at its time: executedAtMs[e] (kInfiniteMs: not
// executed; executedAtMs[0] is ignored, the start is at 0). Every event not
// yet executed happens at or after notBeforeMs ("now"). In the network the
// start's edge pair to an event is then [executedAtMs, executedAtMs] or
// [notBeforeMs, inf) instead of [0, inf), so an option whose bounds can no
// longer be met from here is ruled out, and executed times that contradict
// the plan give kNoneExists. An option already under way (its activity
// started) is not forced here: the caller forces it by deprecating the
// choice's other options. An activity already started (done, or running
// and not failed) is marked in started[]: its component Asks held when it
// started and are not judged again (a grinder failing after sample 1 leaves
// that sample's option usable; a running activity whose component failed is
// to be reported failed, and not marked, first). An event not executed may
// have a later floor of its own, notBeforeEventMs[e] (the end of a running
// science activity extended by a follow-on cannot come before the extra work
// is done): it happens at or after max(notBeforeMs, notBeforeEventMs[e]).
// Defaults (0, nothing executed or started) change nothing.
// start() refuses (kInvalidArgument) notBeforeMs, an executed time or an
// event's floor outside [0, kMaxBoundMs].
struct SelectionInput {
    ComponentState components[kComponentCount] = {};  // all kOk
    bool deprecated[kMaxChoices][kMaxOptions] = {};
    std::int32_t notBeforeMs = 0;
    std::int32_t executedAtMs[kMaxEvents];         // kInfiniteMs: not executed
    std::int32_t notBeforeEventMs[kMaxEvents] = {};  // an event's own floor when not executed (0: none)
    bool started[kMaxActivities] = {};
    SelectionInput() {
        for (std::int32_t& t : executedAtMs) {
            t = kInfiniteMs;
        }
    }
};

// The expected-cost model's penalties (table-driven later); each >= 0.
struct SelectionParams {
    double degradedPenalty = 0.5;  // an activity asking a degraded component: x (1 + this)
    double drivePenalty = 0.25;    // a drive: x (1 + this x degraded drives)
    // Work units (see above), >= 1. The default: ten deliberative periods of
    // 150 k units (bench_plan_executive's slice).
    std::uint32_t workBudget = 1500000;
};

enum class SelectionStatus : std::uint8_t {
    kRunning = 0,       // start() done, step() under way: the selection is the best so far
    kSelected,          // optimal (search exhausted)
    kSelectedInBudget,  // valid, not proven optimal: the budget ran out
    kNoneExists,        // proven: no valid selection
    kNoneFound,         // none found before the budget ran out
    kBadPlan,           // the plan failed start()'s checks
};
const char* toString(SelectionStatus s);

// Why an option or a branch was rejected. Counted once per option found
// unusable before the search (a failed Ask, a deprecation, an Ask nothing in
// the plan answers, inconsistent on its own in the presolve; the unguarded
// plan counts as one), and once per search branch that failed (inconsistent
// with the choices above it; a complete selection with an unsupported Ask).
enum class RejectReason : std::uint8_t {
    kAskFailed = 0,       // a component Ask does not hold
    kDeprecated,          // the executive deprecated the option
    kCausalLinkMissing,   // a plan-variable Ask has no Tell that surely precedes it
    kInconsistent,        // the STN has a negative cycle
};
constexpr std::size_t kRejectReasonCount = 4;

struct SelectionResult {
    SelectionStatus status = SelectionStatus::kRunning;
    double cost = 0.0;        // the selection's expected cost (meaningless without one)
    bool hasSelection = false;
    Selection selection;
};

struct SelectionStats {
    std::uint64_t work = 0;           // units (see above)
    std::uint32_t nodes = 0;          // options applied in the search
    std::uint32_t leaves = 0;         // complete selections whose supports were checked
    std::uint32_t incumbents = 0;     // improvements of the best selection
    std::uint32_t prunedByBound = 0;  // options not tried: their bound reached the incumbent
    std::uint32_t rejected[kRejectReasonCount] = {};
    double rootBound = 0.0;           // the presolved lower bound on any valid selection's cost
};

// An activity's expected cost under the estimate (see above).
double expectedCost(const Activity& a, const SelectionInput& input, const SelectionParams& params);
// The expected cost of a selection (existing activities and chosen options), valid or not.
double selectionCost(const Tpn& plan, const Selection& s, const SelectionInput& input, const SelectionParams& params);
// The STN of a selection: its existing activities' durations, its existing
// constraints and the start's [0, inf) to every event, added to a reset
// network (not checked). kInvalidArgument for a plan outside the limits.
core::Status loadStn(const Tpn& plan, const Selection& s, Stn* stn);
// The same with where execution stands (SelectionInput "Regeneration"): the
// start's bounds to an event are [executedAtMs, executedAtMs] when executed,
// else [max(notBeforeMs, notBeforeEventMs), inf): the network the selector judged, which the
// dispatcher executes. kInvalidArgument as start() refuses the times.
core::Status loadStn(const Tpn& plan, const Selection& s, const SelectionInput& input, Stn* stn);

class MethodSelector {
public:
    // The network's edges: an activity's or constraint's two (one when ub
    // is infinite), the implied edges (at most one per edge of the choices'
    // options), and each event's bounds from the start: one edge ("not
    // before"), two for an executed event (SelectionInput "Regeneration").
    static constexpr std::size_t kMaxEdges = 4 * (kMaxActivities + kMaxConstraints) + 2 * kMaxEvents;
    static_assert(kMaxEdges < 0xFFFF, "edge indexes are 16 bits");
    // The most one action does. The largest is a Dijkstra settle: the queue
    // scan, one event's edges, then committing and clearing what the
    // Dijkstra touched. The others are smaller: undoing a thread
    // (1 + its edges), marking a support check's candidates
    // (1 + kMaxEvents + kMaxActivities (2 + kMaxTells)), the presolve's
    // costs (about 700).
    static constexpr std::uint64_t kMaxActionWork = 1 + 3 * kMaxEvents + kMaxEdges;

    // Checks and analyses the plan and starts a selection. kInvalidArgument
    // (status kBadPlan, finished) for a plan outside tpn.hpp's limits or
    // rules (indices, guards, nesting cycles, lb > ub, negative or
    // non-finite costs), negative or non-finite penalties, a zero budget or
    // execution times out of range (SelectionInput "Regeneration").
    core::Status start(const Tpn& plan, const SelectionInput& input, const SelectionParams& params);

    // Runs actions until maxUnits work units are done (the last action may
    // pass that by less than kMaxActionWork) or the selection is finished;
    // true when finished (also when this call spent the budget).
    bool step(std::uint32_t maxUnits);
    bool finished() const { return phase_ == Phase::kDone; }

    // The best selection so far; its final status once finished().
    const SelectionResult& result() const { return best_; }
    const SelectionStats& stats() const { return stats_; }
    std::uint64_t work() const { return stats_.work; }

    // start() and step() to the end; the result's status.
    SelectionStatus solve(const Tpn& plan, const SelectionInput& input, const SelectionParams& params,
                          SelectionResult* out);

private:
    enum class Phase : std::uint8_t { kIdle, kBase, kPresolve, kSearch, kDone };
    // Where the search is: trying the top level's next option, turning a
    // thread's edges on, descending to the next choice, checking a complete
    // selection's supports.
    enum class SearchStep : std::uint8_t { kNextOption, kAddThread, kDescend, kSupports };


    struct Level {
        std::uint8_t choice;
        std::uint8_t pos;      // its place in order_
        std::uint8_t next;     // the next rank of rankedOption_ to try
        std::uint8_t applied;  // the option whose thread is on (kNoOption: none)
        double costBefore;
        double openBefore;
    };

    // Threads: group 0 the unguarded network, 1 + c kMaxOptions + o option (c, o)'s.
    static constexpr std::size_t kGroups = 1 + kMaxChoices * kMaxOptions;
    static std::size_t group(std::size_t choice, std::size_t option) { return 1 + choice * kMaxOptions + option; }
    static std::size_t groupOf(const Guard& g) { return g.guarded() ? group(g.choice, g.option) : 0; }
    // The phases (method_selector.cpp).
    void action();
    void finish(SelectionStatus status);
    // Set-up, presolve and costs (method_selector_analysis.cpp).
    bool validate(const Tpn& plan) const;
    void analyse(const SelectionInput& input);
    void analyseActivities(const SelectionInput& input);
    void analyseOptions(const SelectionInput& input);
    void orderChoices();
    void buildNetwork(const SelectionInput& input);
    void addImpliedEdges();
    void addEdge(std::size_t from, std::size_t to, std::int32_t weight, std::size_t g);
    void sortEdgesByGroup();
    // The tightest weight of the group's edges from -> to (kInfiniteMs: none).
    std::int32_t tightestInGroup(std::size_t g, std::size_t from, std::size_t to) const;
    void presolveAction();
    void computeCosts();
    // The incremental network (method_selector_network.cpp).
    void beginThread(std::size_t g);
    void threadAction();  // one edge on, or one repair settle
    void undoThread(std::size_t g);
    // Dijkstra on reduced costs (repair, or distances for a support check).
    void beginDijkstra(std::uint16_t source, std::int64_t key);
    std::uint16_t popMin();
    void relaxFrom(std::uint16_t x, std::int64_t cutoff);
    void endDijkstra();
    // The search (method_selector_search.cpp).
    void searchAction();
    void nextOption();
    void descend();
    void supportAction();
    bool beginSupportCheck();
    void reject(RejectReason r) { ++stats_.rejected[static_cast<std::size_t>(r)]; }

    const Tpn* plan_ = nullptr;
    SelectionParams params_{};
    Phase phase_ = Phase::kIdle;
    std::uint16_t n_ = 0;

    // The network: every edge the plan could have (tail, head, weight: t_head
    // - t_tail <= weight), whether it is on, its group (group 0: unguarded;
    // 1 + c kMaxOptions + o: option (c, o)'s thread); the edges by group and
    // by tail.
    std::uint16_t edgeFrom_[kMaxEdges] = {};
    std::uint16_t edgeTo_[kMaxEdges] = {};
    std::int32_t edgeWeight_[kMaxEdges] = {};
    std::uint16_t edgeGroup_[kMaxEdges] = {};
    bool edgeOn_[kMaxEdges] = {};
    std::size_t edgeCount_ = 0;
    std::uint16_t groupStart_[kGroups + 1] = {};
    std::uint16_t groupEdge_[kMaxEdges] = {};
    std::uint16_t adjacencyStart_[kMaxEvents + 1] = {};
    std::uint16_t adjacency_[kMaxEdges] = {};
    // Nested choices by the group (option) they sit under.
    std::uint8_t childStart_[kGroups + 1] = {};
    std::uint8_t childChoice_[kMaxChoices] = {};

    // Schedule potential and Dijkstra scratch.
    std::int64_t pi_[kMaxEvents] = {};
    std::int64_t key_[kMaxEvents] = {};
    std::uint8_t mark_[kMaxEvents] = {};   // 0 unseen, 1 queued, 2 settled
    std::uint16_t queue_[kMaxEvents] = {};
    std::uint16_t touched_[kMaxEvents] = {};
    std::uint16_t queueSize_ = 0;
    std::uint16_t touchedSize_ = 0;
    bool dijkstraRunning_ = false;

    // The thread being turned on: group, cursor, the edge under repair.
    std::size_t threadGroup_ = 0;
    std::size_t threadPos_ = 0;  // the next of the group's edges
    std::uint16_t repairEdge_ = 0;
    enum class ThreadState : std::uint8_t { kIdle, kRunning, kDone, kFailed };
    ThreadState thread_ = ThreadState::kIdle;

    // Static analysis: per activity ok (and why not), per option its own
    // cost, its subtree cost (kInfinite when unusable) and why unusable.
    bool activityOk_[kMaxActivities] = {};
    RejectReason activityWhy_[kMaxActivities] = {};
    double activityCost_[kMaxActivities] = {};
    double optionOwn_[kMaxChoices][kMaxOptions] = {};
    double optionCost_[kMaxChoices][kMaxOptions] = {};
    bool optionOk_[kMaxChoices][kMaxOptions] = {};
    RejectReason optionWhy_[kMaxChoices][kMaxOptions] = {};
    double choiceMin_[kMaxChoices] = {};
    std::uint8_t rankedOption_[kMaxChoices][kMaxOptions] = {};
    std::uint8_t order_[kMaxChoices] = {};  // parents before nested choices (preorder)
    std::uint8_t choiceCount_ = 0;
    double baseCost_ = 0.0;
    bool baseOk_ = true;
    RejectReason baseWhy_ = RejectReason::kAskFailed;
    // Activities with a plan-variable Ask (support checks at complete selections).
    std::uint16_t askers_[kMaxActivities] = {};
    std::uint16_t askerCount_ = 0;

    // Presolve cursor: the choice (place in order_) and option being tried.
    std::size_t presolvePos_ = 0;
    std::size_t presolveOption_ = 0;

    // Search.
    SearchStep search_ = SearchStep::kNextOption;
    Level level_[kMaxChoices] = {};
    std::size_t depth_ = 0;
    Selection chosen_;
    double cost_ = 0.0;  // decided so far
    double open_ = 0.0;  // the open choices' cheapest subtrees
    // Support check of a complete selection: asker and Ask under check,
    // candidate Tell ends still unsettled.
    std::size_t supportAsker_ = 0;
    std::size_t supportAsk_ = 0;
    std::uint16_t supportSource_ = 0;
    bool candidate_[kMaxEvents] = {};
    std::uint16_t candidateList_[kMaxEvents] = {};
    std::uint16_t candidateCount_ = 0;
    std::uint16_t candidatesLeft_ = 0;
    bool supportFound_ = false;

    SelectionResult best_{};
    SelectionStats stats_{};
};

}  // namespace rse::plan_executive

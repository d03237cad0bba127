// The Simple Temporal Network (STN) of a selected plan: the time points
// (events, event 0 the plan's start) and the bounds between them as a
// distance graph, closed to all-pairs shortest paths (the minimal network).
// docs/plan_executive.md "Simple Temporal Network".
//
// Distances. d(a, b) is the most t_b - t_a may be, in ms; a bound [lb, ub]
// from a to b is d(a, b) <= ub and d(b, a) <= -lb; kInfiniteMs is "no
// bound". The network is consistent (some schedule meets every bound) exactly
// when the distance graph has no negative cycle (Dechter, Meiri and Pearl);
// closed, d(a, b) is then the tightest bound every schedule keeps, an event's
// window is [-d(e, 0), d(0, e)] and the matrix is dispatchable (Muscettola:
// executing events in any order within their windows, each execution
// propagated, never paints a later event into a corner).
//
// Arithmetic. Sums are taken in 64 bits; kInfiniteMs absorbs. A distance
// beyond +-kInfiniteMs (about 24.8 days) cannot be stored: the check counts
// every one it meets (a bound dropped as "none", a negative one stored at
// -kInfiniteMs) and, when it found no negative cycle, reports kOutOfRange
// rather than a consistency it could not establish. A network whose bounds'
// absolute values sum to less than kInfiniteMs / 2 (12.4 days: the check
// adds two path lengths, each at most that sum) never meets it; a larger one
// may be reported kOutOfRange even where its shortest paths fit (the check
// met a long detour first): refused, never wrongly accepted.
//
// Work and slicing. The full check is Floyd-Warshall; one unit of step() is
// one row of one pivot: d(i, j) = min(d(i, j), d(i, k) + d(k, j)) for every
// j, at most kMaxNodes min-adds (a row whose d(i, k) is "none" is skipped at
// once), so a network of n events takes n^2 units and n^3 min-adds (0.5 - 1
// ns each on the development host, by its load: 116 events 0.7 - 2.2 ms,
// bench_plan_executive); it stops at the first negative diagonal entry. No clock is read: the caller slices
// by units. An update after the check (execute(), tighten()) is not sliced:
// O(n^2) min-adds (the edge-decrease update), about 65 k at n = 256
// (bench_plan_executive prints the time).
//
// Memory: the matrix, kMaxNodes^2 int32 = 256 KiB (sizeof(Stn) a few bytes
// more). Static storage (a member of the executive), never a stack.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

// a + b for distances: kInfiniteMs (no bound) absorbs; a finite sum is taken
// in 64 bits and clamped to [-kInfiniteMs, kInfiniteMs] (above: no bound).
std::int32_t addDistances(std::int32_t a, std::int32_t b);

enum class StnState : std::uint8_t {
    kOpen = 0,      // reset(): bounds may be added, nothing checked yet
    kChecking,      // the full check is under way (step())
    kConsistent,    // closed: the minimal network; queries and updates allowed
    kInconsistent,  // a negative cycle: no schedule meets every bound
    kOutOfRange,    // a distance beyond +-kInfiniteMs: consistency not established
};

// What an update after the check did.
enum class [[nodiscard]] StnUpdate : std::uint8_t {
    kApplied = 0,   // tightened (or already implied): still consistent and closed
    kInconsistent,  // it would make a negative cycle: refused, the network is unchanged
    kRejected,      // a bad event or bound, or no consistent network: nothing changed
    kOutOfRange,    // applied, but a distance left the range: state() is now kOutOfRange
};

// When an event may happen, in ms after the plan's start (event 0).
// earliestMs -kInfiniteMs: no lower bound; latestMs kInfiniteMs: no upper bound.
struct Window {
    std::int32_t earliestMs = 0;
    std::int32_t latestMs = kInfiniteMs;
};

class Stn {
public:
    static constexpr std::size_t kMaxNodes = kMaxEvents;

    // n events, no bound between them (d(i, i) = 0, every other "none"); kOpen.
    // kInvalidArgument when n is 0 or above kMaxNodes (nothing changed).
    core::Status reset(std::size_t eventCount);

    // Before the check (kOpen): intersects the bounds on t_to - t_from with
    // [lb, ub]. kInvalidArgument for an event outside the network, lb > ub, a
    // finite bound beyond +-kMaxBoundMs or lb = kInfiniteMs; kNotInitialized
    // once the check has started (use tighten() on a checked network).
    core::Status addBounds(std::size_t from, std::size_t to, Bounds bounds);

    // The full check, sliced: beginCheck() then step() until it returns true.
    // kNotInitialized unless kOpen.
    core::Status beginCheck();
    // At most maxUnits rows (see above); true when the check is over (state()
    // then kConsistent, kInconsistent or kOutOfRange). False at once when no
    // check is under way.
    bool step(std::uint32_t maxUnits);
    // beginCheck() and step() to the end (n^2 units): the state.
    StnState check();
    StnState state() const { return state_; }

    // Execution: event e happened at timeMs after the plan's start. Inside
    // its window: d(0, e) = timeMs and d(e, 0) = -timeMs, propagated to every
    // pair in O(n^2) (kApplied). Outside (early or late): kInconsistent and the
    // network is left as it was: the executive regenerates. kRejected unless
    // kConsistent, for an event outside the network, or |timeMs| = kInfiniteMs.
    StnUpdate execute(std::size_t event, std::int32_t timeMs);
    // t_to - t_from <= maxMs on a consistent network: the edge-decrease update
    // d(i, j) = min(d(i, j), d(i, from) + maxMs + d(to, j)), O(n^2), exact
    // while there is no negative cycle; one is detected first, in O(1), as
    // d(to, from) + maxMs < 0 (kInconsistent, nothing changed). A bound no
    // tighter than d(from, to) changes nothing (kApplied).
    StnUpdate tighten(std::size_t from, std::size_t to, std::int32_t maxMs);

    // Queries (meaningful when kConsistent; on an open network they read the
    // bounds as added). Out of range: the widest window / kInfiniteMs.
    Window window(std::size_t event) const;
    std::int32_t distance(std::size_t from, std::size_t to) const;

    std::size_t size() const { return n_; }
    // Units done since reset(): the check's rows, and n for each update (a row each).
    std::uint64_t work() const { return work_; }
    // Distances the range could not hold (see "Arithmetic"), since reset().
    std::uint32_t rangeLosses() const { return rangeLosses_; }

private:
    bool checkRow();  // one unit: pivot k_, row i_; false on a negative diagonal
    void finishCheck(StnState state);
    void relaxThrough(std::size_t from, std::size_t to, std::int32_t w);
    // row[j] = min(row[j], base + through[j]) for every j, in range (see "Arithmetic").
    void relaxRow(std::int32_t* row, std::int64_t base, const std::int32_t* through);

    std::int32_t d_[kMaxNodes][kMaxNodes] = {};
    std::size_t n_ = 0;
    StnState state_ = StnState::kOpen;
    std::size_t k_ = 0;  // the check's pivot
    std::size_t i_ = 0;  // and row
    std::uint64_t work_ = 0;
    std::uint32_t rangeLosses_ = 0;
};

}  // namespace rse::plan_executive

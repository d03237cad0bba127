// The selector's incremental network (method_selector.hpp "Consistency,
// incrementally"): a thread's edges turned on one per action, an edge the
// schedule potential pi does not meet repaired by a Dijkstra on reduced
// costs from its head (reaching its tail: a negative cycle), a thread's
// edges turned off; the Dijkstra's queue and relaxation, shared with the
// search's support checks.
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/method_selector_detail.hpp"

namespace rse::plan_executive {

using selector_detail::kQueued;
using selector_detail::kSettled;
using selector_detail::kUnseen;

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

}  // namespace rse::plan_executive

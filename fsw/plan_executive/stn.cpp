#include "fsw/plan_executive/stn.hpp"

namespace rse::plan_executive {

namespace {

constexpr std::int64_t kInf64 = kInfiniteMs;

bool validBound(std::int32_t v) { return v >= -kMaxBoundMs && v <= kMaxBoundMs; }

}  // namespace

std::int32_t addDistances(std::int32_t a, std::int32_t b) {
    if (a == kInfiniteMs || b == kInfiniteMs) {
        return kInfiniteMs;
    }
    const std::int64_t s = static_cast<std::int64_t>(a) + b;
    if (s >= kInf64) {
        return kInfiniteMs;
    }
    return s < -kInf64 ? -kInfiniteMs : static_cast<std::int32_t>(s);
}

core::Status Stn::reset(std::size_t eventCount) {
    if (eventCount == 0 || eventCount > kMaxNodes) {
        return core::Status::kInvalidArgument;
    }
    n_ = eventCount;
    for (std::size_t i = 0; i < n_; ++i) {
        for (std::size_t j = 0; j < n_; ++j) {
            d_[i][j] = i == j ? 0 : kInfiniteMs;
        }
    }
    state_ = StnState::kOpen;
    k_ = i_ = 0;
    work_ = 0;
    rangeLosses_ = 0;
    return core::Status::kOk;
}

core::Status Stn::addBounds(std::size_t from, std::size_t to, Bounds bounds) {
    if (state_ != StnState::kOpen) {
        return core::Status::kNotInitialized;
    }
    const bool ubOk = bounds.ubMs == kInfiniteMs || validBound(bounds.ubMs);
    if (from >= n_ || to >= n_ || !validBound(bounds.lbMs) || !ubOk || bounds.lbMs > bounds.ubMs) {
        return core::Status::kInvalidArgument;
    }
    if (bounds.ubMs < d_[from][to]) {
        d_[from][to] = bounds.ubMs;
    }
    if (-bounds.lbMs < d_[to][from]) {
        d_[to][from] = -bounds.lbMs;
    }
    return core::Status::kOk;
}

core::Status Stn::beginCheck() {
    if (state_ != StnState::kOpen) {
        return core::Status::kNotInitialized;
    }
    // A bound from an event to itself may already be negative (lb > 0 on a
    // self loop): that is a negative cycle before any pivot.
    for (std::size_t i = 0; i < n_; ++i) {
        if (d_[i][i] < 0) {
            finishCheck(StnState::kInconsistent);
            return core::Status::kOk;
        }
    }
    state_ = StnState::kChecking;
    k_ = i_ = 0;
    return core::Status::kOk;
}

void Stn::relaxRow(std::int32_t* row, std::int64_t base, const std::int32_t* through) {
    for (std::size_t j = 0; j < n_; ++j) {
        if (through[j] == kInfiniteMs) {
            continue;
        }
        const std::int64_t s = base + through[j];
        if (s < row[j]) {
            if (s < -kInf64) {
                row[j] = -kInfiniteMs;
                ++rangeLosses_;
            } else {
                row[j] = static_cast<std::int32_t>(s);
            }
        } else if (row[j] == kInfiniteMs) {
            ++rangeLosses_;  // a finite path beyond the range: its bound is dropped
        }
    }
}

bool Stn::checkRow() {
    ++work_;
    const std::int32_t dik = d_[i_][k_];
    if (dik != kInfiniteMs) {  // else nothing reaches through k from i
        relaxRow(d_[i_], dik, d_[k_]);
    }
    return d_[i_][i_] >= 0;
}

bool Stn::step(std::uint32_t maxUnits) {
    if (state_ != StnState::kChecking) {
        return false;
    }
    for (std::uint32_t u = 0; u < maxUnits; ++u) {
        if (!checkRow()) {
            finishCheck(StnState::kInconsistent);
            return true;
        }
        if (++i_ == n_) {
            i_ = 0;
            if (++k_ == n_) {
                finishCheck(rangeLosses_ == 0 ? StnState::kConsistent : StnState::kOutOfRange);
                return true;
            }
        }
    }
    return false;
}

StnState Stn::check() {
    if (beginCheck() == core::Status::kOk) {
        (void)step(static_cast<std::uint32_t>(n_ * n_));  // n^2 units: the whole check
    }
    return state_;
}

void Stn::finishCheck(StnState state) {
    state_ = state;
    k_ = i_ = 0;
}

void Stn::relaxThrough(std::size_t from, std::size_t to, std::int32_t w) {
    // No negative cycle through the new edge (checked by the caller), so a
    // shortest path uses it at most once: i -> from, the edge, to -> j. Row
    // `to` and column `from` cannot change (their candidates add
    // w + d(to, from) >= 0), so updating in place reads final values.
    for (std::size_t i = 0; i < n_; ++i) {
        ++work_;
        const std::int32_t dif = d_[i][from];
        if (dif != kInfiniteMs) {
            relaxRow(d_[i], static_cast<std::int64_t>(dif) + w, d_[to]);
        }
    }
}

StnUpdate Stn::tighten(std::size_t from, std::size_t to, std::int32_t maxMs) {
    if (state_ != StnState::kConsistent || from >= n_ || to >= n_ || maxMs == kInfiniteMs || maxMs == -kInfiniteMs) {
        return StnUpdate::kRejected;
    }
    if (maxMs >= d_[from][to]) {
        return StnUpdate::kApplied;  // already implied
    }
    const std::int32_t back = d_[to][from];
    if (back != kInfiniteMs && static_cast<std::int64_t>(back) + maxMs < 0) {
        return StnUpdate::kInconsistent;
    }
    const std::uint32_t lossesBefore = rangeLosses_;
    relaxThrough(from, to, maxMs);
    if (rangeLosses_ != lossesBefore) {
        state_ = StnState::kOutOfRange;
        return StnUpdate::kOutOfRange;
    }
    return StnUpdate::kApplied;
}

StnUpdate Stn::execute(std::size_t event, std::int32_t timeMs) {
    if (state_ != StnState::kConsistent || event >= n_ || timeMs == kInfiniteMs || timeMs == -kInfiniteMs) {
        return StnUpdate::kRejected;
    }
    // Both halves are checked before either is applied, so an early or late
    // event leaves the network as it was. On a closed consistent network
    // "inside the window" is exactly "consistent".
    const Window w = window(event);
    if (timeMs < w.earliestMs || timeMs > w.latestMs) {
        return StnUpdate::kInconsistent;
    }
    const StnUpdate late = tighten(0, event, timeMs);
    if (late != StnUpdate::kApplied) {
        return late;
    }
    return tighten(event, 0, -timeMs);
}

Window Stn::window(std::size_t event) const {
    Window w;
    w.earliestMs = -kInfiniteMs;
    if (event >= n_) {
        return w;
    }
    const std::int32_t back = d_[event][0];
    w.earliestMs = back == kInfiniteMs ? -kInfiniteMs : -back;
    w.latestMs = d_[0][event];
    return w;
}

std::int32_t Stn::distance(std::size_t from, std::size_t to) const {
    return from < n_ && to < n_ ? d_[from][to] : kInfiniteMs;
}

}  // namespace rse::plan_executive

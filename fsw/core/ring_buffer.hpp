// A fixed-capacity FIFO with inline storage.
//
// push() refuses when full (the caller counts the drop); pushOverwrite() drops
// the oldest element instead and says so, for logs where the newest matters most.
#pragma once

#include <array>
#include <cstddef>

#include "fsw/core/status.hpp"

namespace rse::core {

template <typename T, std::size_t Capacity>
class RingBuffer {
    static_assert(Capacity > 0, "RingBuffer needs a capacity of at least one");

public:
    static constexpr std::size_t capacity() { return Capacity; }
    std::size_t size() const { return count_; }
    bool empty() const { return count_ == 0; }
    bool full() const { return count_ == Capacity; }

    Status push(const T& value) {
        if (count_ == Capacity) {
            return Status::kFull;
        }
        items_[(head_ + count_) % Capacity] = value;
        ++count_;
        return Status::kOk;
    }

    // Returns true when the oldest element had to be discarded to make room.
    bool pushOverwrite(const T& value) {
        const bool overwrote = (count_ == Capacity);
        if (overwrote) {
            head_ = (head_ + 1) % Capacity;
            --count_;
        }
        items_[(head_ + count_) % Capacity] = value;
        ++count_;
        return overwrote;
    }

    Status pop(T* out) {
        if (count_ == 0) {
            return Status::kEmpty;
        }
        if (out != nullptr) {
            *out = items_[head_];
        }
        head_ = (head_ + 1) % Capacity;
        --count_;
        return Status::kOk;
    }

    // nullptr when empty.
    const T* peek() const { return count_ == 0 ? nullptr : &items_[head_]; }

    void clear() {
        head_ = 0;
        count_ = 0;
    }

private:
    std::array<T, Capacity> items_{};
    std::size_t head_ = 0;
    std::size_t count_ = 0;
};

}  // namespace rse::core

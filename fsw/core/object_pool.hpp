// A pool of Capacity objects of type T, all constructed at start-up.
//
// acquire() hands out a free slot or nullptr when the pool is exhausted;
// release() rejects pointers that are not from this pool or are already free,
// so a double release is an error code rather than a corrupted free list.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"

namespace rse::core {

template <typename T, std::size_t Capacity>
class ObjectPool {
    static_assert(Capacity > 0, "ObjectPool needs a capacity of at least one");

public:
    ObjectPool() {
        for (std::size_t i = 0; i < Capacity; ++i) {
            freeList_[i] = Capacity - 1 - i;  // hand out slot 0 first
        }
        freeCount_ = Capacity;
    }

    static constexpr std::size_t capacity() { return Capacity; }
    std::size_t available() const { return freeCount_; }
    std::size_t inUse() const { return Capacity - freeCount_; }

    // Returns a default-reset object, or nullptr when none is free.
    T* acquire() {
        if (freeCount_ == 0) {
            return nullptr;
        }
        const std::size_t index = freeList_[--freeCount_];
        used_[index] = true;
        slots_[index] = T{};
        return &slots_[index];
    }

    Status release(const T* object) {
        const std::size_t index = indexOf(object);
        if (index >= Capacity || !used_[index]) {
            return Status::kInvalidArgument;
        }
        used_[index] = false;
        freeList_[freeCount_++] = index;
        return Status::kOk;
    }

private:
    // Capacity when object is not one of our slots.
    std::size_t indexOf(const T* object) const {
        for (std::size_t i = 0; i < Capacity; ++i) {
            if (&slots_[i] == object) {
                return i;
            }
        }
        return Capacity;
    }

    std::array<T, Capacity> slots_{};
    std::array<bool, Capacity> used_{};
    std::array<std::size_t, Capacity> freeList_{};
    std::size_t freeCount_ = 0;
};

}  // namespace rse::core

// A vector with its capacity fixed at compile time and its storage inline.
//
// Out-of-range access and overflow return errors (nullptr / Status) instead of
// undefined behaviour, so a bad index computed from hostile input cannot corrupt
// memory. T must be default-constructible and copyable; slots past size() hold
// default-constructed values.
#pragma once

#include <array>
#include <cstddef>

#include "fsw/core/status.hpp"

namespace rse::core {

template <typename T, std::size_t Capacity>
class StaticVector {
    static_assert(Capacity > 0, "StaticVector needs a capacity of at least one");

public:
    static constexpr std::size_t capacity() { return Capacity; }
    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    bool full() const { return size_ == Capacity; }

    Status push_back(const T& value) {
        if (size_ == Capacity) {
            return Status::kFull;
        }
        items_[size_++] = value;
        return Status::kOk;
    }

    Status pop_back(T* out) {
        if (size_ == 0) {
            return Status::kEmpty;
        }
        --size_;
        if (out != nullptr) {
            *out = items_[size_];
        }
        items_[size_] = T{};
        return Status::kOk;
    }

    // Removes the element at index, keeping the order of the rest.
    Status erase(std::size_t index) {
        if (index >= size_) {
            return Status::kInvalidArgument;
        }
        for (std::size_t i = index; i + 1 < size_; ++i) {
            items_[i] = items_[i + 1];
        }
        --size_;
        items_[size_] = T{};
        return Status::kOk;
    }

    void clear() {
        for (std::size_t i = 0; i < size_; ++i) {
            items_[i] = T{};
        }
        size_ = 0;
    }

    // nullptr when index >= size().
    T* at(std::size_t index) { return index < size_ ? &items_[index] : nullptr; }
    const T* at(std::size_t index) const { return index < size_ ? &items_[index] : nullptr; }

    T* begin() { return items_.data(); }
    T* end() { return items_.data() + size_; }
    const T* begin() const { return items_.data(); }
    const T* end() const { return items_.data() + size_; }

private:
    std::array<T, Capacity> items_{};
    std::size_t size_ = 0;
};

}  // namespace rse::core

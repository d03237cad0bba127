// A fixed FIFO of whole packets: Depth slots of up to MaxBytes each, inline
// storage, no heap. The building block of the in-memory link's two directions and
// of the ISO-TP ground link's transmit queue.
//
// A packet is copied in whole by push() and read in place with front() until
// pop(), so the reader never needs a second MaxBytes buffer of its own. The queue
// only refuses (kFull, kTooLarge, kInvalidArgument); its owner counts and events.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fsw/core/status.hpp"

namespace rse::hal {

template <std::size_t Depth, std::size_t MaxBytes>
class PacketQueue {
    static_assert(Depth > 0 && MaxBytes > 0, "PacketQueue needs at least one slot of at least one byte");

public:
    static constexpr std::size_t depth() { return Depth; }
    static constexpr std::size_t maxBytes() { return MaxBytes; }
    std::size_t size() const { return count_; }
    bool empty() const { return count_ == 0; }
    bool full() const { return count_ == Depth; }

    // Copies length bytes in as the newest packet. kInvalidArgument for an empty
    // packet or null data, kTooLarge beyond MaxBytes, kFull when every slot is taken.
    core::Status push(const std::uint8_t* data, std::size_t length) {
        if (data == nullptr || length == 0) {
            return core::Status::kInvalidArgument;
        }
        if (length > MaxBytes) {
            return core::Status::kTooLarge;
        }
        if (count_ == Depth) {
            return core::Status::kFull;
        }
        Slot& slot = slots_[(head_ + count_) % Depth];
        std::memcpy(slot.bytes, data, length);
        slot.length = length;
        ++count_;
        return core::Status::kOk;
    }

    // The oldest packet, valid until pop(); nullptr (and *length 0) when empty.
    const std::uint8_t* front(std::size_t* length) const {
        if (count_ == 0) {
            *length = 0;
            return nullptr;
        }
        *length = slots_[head_].length;
        return slots_[head_].bytes;
    }

    // Discards the oldest packet (nothing when empty).
    void pop() {
        if (count_ != 0) {
            head_ = (head_ + 1) % Depth;
            --count_;
        }
    }

    void clear() {
        head_ = 0;
        count_ = 0;
    }

private:
    struct Slot {
        std::size_t length = 0;
        std::uint8_t bytes[MaxBytes] = {};
    };

    Slot slots_[Depth] = {};
    std::size_t head_ = 0;
    std::size_t count_ = 0;
};

}  // namespace rse::hal

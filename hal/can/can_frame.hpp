// A classic CAN 2.0 frame (up to 8 data bytes), independent of any driver.
#pragma once

#include <cstdint>

#include "fsw/core/clock.hpp"

namespace rse::hal {

constexpr std::uint32_t kCanMaxStandardId = 0x7FF;
constexpr std::uint32_t kCanMaxExtendedId = 0x1FFFFFFF;
constexpr std::uint8_t kCanMaxDlc = 8;

struct CanFrame {
    static constexpr std::uint8_t kExtended = 0x01;  // 29-bit identifier
    static constexpr std::uint8_t kRemote = 0x02;    // remote transmission request

    std::uint32_t id = 0;
    std::uint8_t dlc = 0;
    std::uint8_t flags = 0;
    std::uint8_t data[kCanMaxDlc] = {};
    core::TimeNs timestamp = 0;  // receive time, CLOCK_MONOTONIC domain (or virtual)

    bool extended() const { return (flags & kExtended) != 0; }
    bool remote() const { return (flags & kRemote) != 0; }
};

// A frame a controller could put on the wire: id within its format, dlc <= 8.
inline bool isValidFrame(const CanFrame& frame) {
    const std::uint32_t maxId = frame.extended() ? kCanMaxExtendedId : kCanMaxStandardId;
    return frame.id <= maxId && frame.dlc <= kCanMaxDlc;
}

// Acceptance filter: a frame passes when (frame.id & mask) == (id & mask), and its
// format (standard/extended) matches `extended`.
struct CanFilter {
    std::uint32_t id = 0;
    std::uint32_t mask = 0;
    bool extended = false;
};

inline bool passesFilter(const CanFilter& filter, const CanFrame& frame) {
    return frame.extended() == filter.extended && (frame.id & filter.mask) == (filter.id & filter.mask);
}

}  // namespace rse::hal

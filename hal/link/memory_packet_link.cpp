#include "hal/link/memory_packet_link.hpp"

#include <cstring>

namespace rse::hal {

using core::Status;

Status MemoryPacketLink::receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) {
    if (length == nullptr || (out == nullptr && capacity > 0)) {
        return Status::kInvalidArgument;
    }
    std::size_t size = 0;
    const std::uint8_t* packet = uplink_.front(&size);
    if (packet == nullptr) {
        *length = 0;
        return Status::kEmpty;
    }
    *length = size;
    if (size > capacity) {
        uplink_.pop();
        ++stats_.rxDropped;
        return Status::kTooLarge;
    }
    std::memcpy(out, packet, size);
    uplink_.pop();
    ++stats_.rxPackets;
    return Status::kOk;
}

Status MemoryPacketLink::send(const std::uint8_t* data, std::size_t length) {
    const Status s = downlink_.push(data, length);
    if (core::isOk(s)) {
        ++stats_.txPackets;
    } else {
        ++stats_.txDropped;
    }
    return s;
}

Status MemoryPacketLink::groundSend(const std::uint8_t* data, std::size_t length) {
    const Status s = uplink_.push(data, length);
    if (!core::isOk(s)) {
        ++stats_.rxDropped;
    }
    return s;
}

Status MemoryPacketLink::groundReceive(std::uint8_t* out, std::size_t capacity, std::size_t* length) {
    if (length == nullptr || (out == nullptr && capacity > 0)) {
        return Status::kInvalidArgument;
    }
    std::size_t size = 0;
    const std::uint8_t* packet = downlink_.front(&size);
    *length = size;
    if (packet == nullptr) {
        return Status::kEmpty;
    }
    if (size > capacity) {
        return Status::kTooLarge;
    }
    std::memcpy(out, packet, size);
    downlink_.pop();
    return Status::kOk;
}

}  // namespace rse::hal

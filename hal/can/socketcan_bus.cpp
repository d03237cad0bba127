#include "hal/can/socketcan_bus.hpp"

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

namespace rse::hal {

using core::Status;

namespace {

// A frame of ours as the kernel's struct can_frame.
can_frame toKernel(const CanFrame& frame) {
    can_frame k{};
    k.can_id = frame.id;
    if (frame.extended()) {
        k.can_id |= CAN_EFF_FLAG;
    }
    if (frame.remote()) {
        k.can_id |= CAN_RTR_FLAG;
    }
    k.can_dlc = frame.dlc;
    std::memcpy(k.data, frame.data, frame.dlc);
    return k;
}

core::TimeNs monotonicNow() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<core::TimeNs>(ts.tv_sec) * core::kNsPerSec + ts.tv_nsec;
}

// The kernel stamps frames on CLOCK_REALTIME; shift onto CLOCK_MONOTONIC so the
// stamp compares with the executive's clock (exact up to a concurrent time step).
core::TimeNs realtimeToMonotonic(const timespec& stamp) {
    timespec realNow{};
    clock_gettime(CLOCK_REALTIME, &realNow);
    const core::TimeNs real = static_cast<core::TimeNs>(realNow.tv_sec) * core::kNsPerSec + realNow.tv_nsec;
    const core::TimeNs stampNs = static_cast<core::TimeNs>(stamp.tv_sec) * core::kNsPerSec + stamp.tv_nsec;
    return monotonicNow() - (real - stampNs);
}

}  // namespace

SocketCanBus::~SocketCanBus() { close(); }

Status SocketCanBus::open(const char* interfaceName) {
    close();
    if (interfaceName == nullptr || interfaceName[0] == '\0' ||
        std::strlen(interfaceName) >= kCanInterfaceNameSize) {
        return Status::kInvalidArgument;
    }
    std::strncpy(name_, interfaceName, sizeof name_ - 1);

    const int fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (fd < 0) {
        lastErrno_ = errno;  // EAFNOSUPPORT: this kernel has no CAN
        return Status::kUnavailable;
    }
    const unsigned ifindex = if_nametoindex(interfaceName);
    if (ifindex == 0) {
        lastErrno_ = errno;  // ENODEV: no such interface
        ::close(fd);
        return Status::kUnavailable;
    }
    const can_err_mask_t errorMask = CAN_ERR_MASK;  // every error class
    const int on = 1;
    if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &errorMask, sizeof errorMask) != 0 ||
        setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) != 0 ||
        setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0) {
        lastErrno_ = errno;
        ::close(fd);
        return Status::kUnavailable;
    }
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(ifindex);
    if (bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
        lastErrno_ = errno;
        ::close(fd);
        return Status::kUnavailable;
    }
    fd_ = fd;
    lastErrno_ = 0;
    kernelDropsSeen_ = 0;
    state_ = CanBusState::kErrorActive;
    return Status::kOk;
}

void SocketCanBus::close() {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    state_ = CanBusState::kDown;
}

Status SocketCanBus::send(const CanFrame& frame) {
    if (!isValidFrame(frame)) {
        ++stats_.txInvalid;
        return Status::kInvalidArgument;
    }
    if (fd_ < 0 || state_ == CanBusState::kBusOff) {
        ++stats_.txUnavailable;
        return Status::kUnavailable;
    }
    const can_frame k = toKernel(frame);
    const ssize_t n = ::write(fd_, &k, sizeof k);
    if (n == static_cast<ssize_t>(sizeof k)) {
        ++stats_.txFrames;
        return Status::kOk;
    }
    lastErrno_ = errno;
    if (errno == EAGAIN || errno == ENOBUFS) {
        ++stats_.txBufferFull;
        return Status::kFull;
    }
    ++stats_.txUnavailable;  // ENETDOWN and friends: the interface went away
    return Status::kUnavailable;
}

void SocketCanBus::handleErrorFrame(std::uint32_t canId, const std::uint8_t* data, std::uint8_t dlc) {
    ++stats_.errorFrames;
    if ((canId & CAN_ERR_BUSOFF) != 0) {
        if (state_ != CanBusState::kBusOff) {
            ++stats_.busOffCount;
        }
        state_ = CanBusState::kBusOff;
        return;
    }
    if ((canId & CAN_ERR_RESTARTED) != 0) {
        state_ = CanBusState::kErrorActive;
        return;
    }
    if ((canId & CAN_ERR_CRTL) != 0 && dlc > 1) {
        const std::uint8_t ctrl = data[1];
        if ((ctrl & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) != 0) {
            state_ = CanBusState::kErrorPassive;
        } else if ((ctrl & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) != 0) {
            state_ = CanBusState::kErrorWarning;
        } else if ((ctrl & CAN_ERR_CRTL_ACTIVE) != 0) {
            state_ = CanBusState::kErrorActive;
        }
    }
}

Status SocketCanBus::receive(CanFrame* out) {
    if (out == nullptr) {
        return Status::kInvalidArgument;
    }
    if (fd_ < 0) {
        return Status::kUnavailable;
    }
    // Bounded: error frames are consumed and the loop goes on to the next frame,
    // at most this many per call.
    for (int attempt = 0; attempt < 64; ++attempt) {
        can_frame k{};
        iovec iov{&k, sizeof k};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t))];
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        msg.msg_control = control;
        msg.msg_controllen = sizeof control;
        const ssize_t n = recvmsg(fd_, &msg, MSG_DONTWAIT);
        if (n < 0) {
            if (errno == EAGAIN || errno == EWOULDBLOCK) {
                return Status::kEmpty;
            }
            lastErrno_ = errno;
            state_ = CanBusState::kDown;
            return Status::kUnavailable;
        }
        if (n != static_cast<ssize_t>(sizeof k)) {
            continue;  // not a classic CAN frame (CAN FD is not enabled)
        }
        core::TimeNs stamp = monotonicNow();
        for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
            if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMPNS) {
                timespec ts{};
                std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
                stamp = realtimeToMonotonic(ts);
            } else if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
                std::uint32_t drops = 0;
                std::memcpy(&drops, CMSG_DATA(c), sizeof drops);
                stats_.rxOverruns += drops - kernelDropsSeen_;
                kernelDropsSeen_ = drops;
            }
        }
        if ((k.can_id & CAN_ERR_FLAG) != 0) {
            handleErrorFrame(k.can_id & CAN_ERR_MASK, k.data, k.can_dlc);
            continue;
        }
        *out = CanFrame{};
        out->flags = static_cast<std::uint8_t>(((k.can_id & CAN_EFF_FLAG) != 0 ? CanFrame::kExtended : 0) |
                                               ((k.can_id & CAN_RTR_FLAG) != 0 ? CanFrame::kRemote : 0));
        out->id = k.can_id & (out->extended() ? CAN_EFF_MASK : CAN_SFF_MASK);
        out->dlc = k.can_dlc > kCanMaxDlc ? kCanMaxDlc : k.can_dlc;
        std::memcpy(out->data, k.data, out->dlc);
        out->timestamp = stamp;
        ++stats_.rxFrames;
        return Status::kOk;
    }
    return Status::kEmpty;
}

Status SocketCanBus::setFilters(const CanFilter* filters, std::size_t count) {
    if (count > kCanMaxFilters) {
        return Status::kNoCapacity;
    }
    if (filters == nullptr && count != 0) {
        return Status::kInvalidArgument;
    }
    if (fd_ < 0) {
        return Status::kUnavailable;
    }
    can_filter kernel[kCanMaxFilters];
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t formatBit = filters[i].extended ? CAN_EFF_FLAG : 0U;
        kernel[i].can_id = filters[i].id | formatBit;
        // Match the format bit too, and never let RTR frames through by accident.
        kernel[i].can_mask = filters[i].mask | CAN_EFF_FLAG | CAN_RTR_FLAG;
    }
    // No filters: accept everything (the kernel's default is one match-all filter).
    can_filter all{0, 0};
    const void* table = count == 0 ? static_cast<const void*>(&all) : static_cast<const void*>(kernel);
    const socklen_t bytes = static_cast<socklen_t>((count == 0 ? 1 : count) * sizeof(can_filter));
    if (setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, table, bytes) != 0) {
        lastErrno_ = errno;
        return Status::kInvalidArgument;
    }
    return Status::kOk;
}

}  // namespace rse::hal

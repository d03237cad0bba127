#include "sim_stub/drives/sdo_server.hpp"

#include "sim_stub/drives/canopen_le.hpp"

namespace rse::sim {

namespace {

constexpr std::uint32_t kSdoResponseBase = 0x580;
constexpr std::size_t kSdoFrameBytes = 8;

// Client command specifiers (byte 0, bits 7-5).
constexpr std::uint8_t kCcsDownloadSegment = 0;
constexpr std::uint8_t kCcsDownloadInitiate = 1;
constexpr std::uint8_t kCcsUploadInitiate = 2;
constexpr std::uint8_t kCcsUploadSegment = 3;
constexpr std::uint8_t kCcsAbort = 4;

// Server command specifiers, already shifted into bits 7-5.
constexpr std::uint8_t kScsUploadSegment = 0x00;
constexpr std::uint8_t kScsDownloadSegment = 0x20;
constexpr std::uint8_t kScsUploadInitiate = 0x40;
constexpr std::uint8_t kScsDownloadInitiate = 0x60;
constexpr std::uint8_t kAbort = 0x80;

constexpr std::uint8_t kToggleBit = 0x10;
constexpr std::uint8_t kExpeditedBit = 0x02;
constexpr std::uint8_t kSizeBit = 0x01;
constexpr std::uint8_t kLastSegmentBit = 0x01;

constexpr std::size_t kSegmentBytes = 7;

}  // namespace

void SdoServer::reset() {
    phase_ = Phase::kIdle;
    toggle_ = 0;
    offset_ = 0;
    size_ = 0;
}

void SdoServer::respond(const std::uint8_t (&bytes)[8]) {
    hal::CanFrame f;
    f.id = kSdoResponseBase + nodeId_;
    f.dlc = static_cast<std::uint8_t>(kSdoFrameBytes);
    for (std::size_t i = 0; i < kSdoFrameBytes; ++i) {
        f.data[i] = bytes[i];
    }
    if (core::isOk(bus_.send(f))) {
        if ((bytes[0] & 0xE0U) == kAbort) {
            ++stats_.abortsSent;
        } else {
            ++stats_.responses;
        }
    } else {
        ++stats_.sendFailures;
    }
}

void SdoServer::abort(std::uint16_t index, std::uint8_t subIndex, std::uint32_t code) {
    std::uint8_t b[8] = {};
    b[0] = kAbort;
    le::put16(&b[1], index);
    b[3] = subIndex;
    le::put32(&b[4], code);
    lastAbortCode_ = code;
    reset();
    respond(b);
}

void SdoServer::onRequest(const hal::CanFrame& frame, core::TimeNs now) {
    if (frame.dlc != kSdoFrameBytes || frame.remote() || frame.extended()) {
        ++stats_.malformed;  // CiA 301: an SDO is always 8 bytes; anything else is not one
        return;
    }
    ++stats_.requests;
    const std::uint8_t* r = frame.data;
    const std::uint8_t ccs = static_cast<std::uint8_t>(r[0] >> 5U);
    switch (ccs) {
        case kCcsUploadInitiate:  // a new initiate silently replaces any transfer in progress
            reset();
            uploadInitiate(le::u16(&r[1]), r[3], now);
            return;
        case kCcsDownloadInitiate:
            reset();
            downloadInitiate(r, now);
            return;
        case kCcsUploadSegment:
            if (phase_ != Phase::kUploading) {
                // Segment request with no upload running: invalid here. Bytes 1-3 of a
                // segment request are not a multiplexer, so report the transfer's own.
                abort(phase_ == Phase::kIdle ? 0 : index_, phase_ == Phase::kIdle ? 0 : subIndex_,
                      sdo_abort::kInvalidCommand);
                return;
            }
            uploadSegment(r, now);
            return;
        case kCcsDownloadSegment:
            if (phase_ != Phase::kDownloading) {
                abort(phase_ == Phase::kIdle ? 0 : index_, phase_ == Phase::kIdle ? 0 : subIndex_,
                      sdo_abort::kInvalidCommand);
                return;
            }
            downloadSegment(r, now);
            return;
        case kCcsAbort:
            ++stats_.abortsReceived;  // the client ends the transfer; no answer
            reset();
            return;
        default:  // 5 block upload, 6 block download (unsupported), 7 undefined
            if (phase_ != Phase::kIdle) {
                abort(index_, subIndex_, sdo_abort::kInvalidCommand);
            } else {
                abort(le::u16(&r[1]), r[3], sdo_abort::kInvalidCommand);
            }
            return;
    }
}

void SdoServer::uploadInitiate(std::uint16_t index, std::uint8_t subIndex, core::TimeNs now) {
    SdoObjectInfo info;
    std::uint32_t code = dictionary_.describe(index, subIndex, &info);
    if (code == sdo_abort::kNone && !info.readable) {
        code = sdo_abort::kReadOfWriteOnly;
    }
    if (code == sdo_abort::kNone && info.size > kSdoServerMaxObject) {
        code = sdo_abort::kGeneralError;  // larger than this server can move: a build error, not a request error
    }
    if (code == sdo_abort::kNone) {
        code = dictionary_.read(index, subIndex, buffer_, sizeof buffer_);  // a snapshot for every segment
    }
    if (code != sdo_abort::kNone) {
        abort(index, subIndex, code);
        return;
    }
    std::uint8_t b[8] = {};
    le::put16(&b[1], index);
    b[3] = subIndex;
    if (info.size <= 4) {
        // Expedited, size indicated: n = bytes of 4-7 that carry no data.
        b[0] = static_cast<std::uint8_t>(kScsUploadInitiate | ((4U - info.size) << 2U) | kExpeditedBit | kSizeBit);
        for (std::size_t i = 0; i < info.size; ++i) {
            b[4 + i] = buffer_[i];
        }
        respond(b);
        return;
    }
    // Segmented, size indicated in bytes 4-7.
    b[0] = static_cast<std::uint8_t>(kScsUploadInitiate | kSizeBit);
    le::put32(&b[4], static_cast<std::uint32_t>(info.size));
    phase_ = Phase::kUploading;
    index_ = index;
    subIndex_ = subIndex;
    size_ = info.size;
    offset_ = 0;
    toggle_ = 0;
    deadline_ = now + timeout_;
    respond(b);
}

void SdoServer::uploadSegment(const std::uint8_t* r, core::TimeNs now) {
    const std::uint8_t toggle = static_cast<std::uint8_t>(r[0] & kToggleBit);
    if (toggle != toggle_) {
        abort(index_, subIndex_, sdo_abort::kToggleNotAlternated);
        return;
    }
    const std::size_t remaining = size_ - offset_;
    const std::size_t n = remaining < kSegmentBytes ? remaining : kSegmentBytes;
    const bool last = offset_ + n >= size_;
    std::uint8_t b[8] = {};
    b[0] = static_cast<std::uint8_t>(kScsUploadSegment | toggle_ | ((kSegmentBytes - n) << 1U) |
                                     (last ? kLastSegmentBit : 0U));
    for (std::size_t i = 0; i < n; ++i) {
        b[1 + i] = buffer_[offset_ + i];
    }
    offset_ += n;
    toggle_ = static_cast<std::uint8_t>(toggle_ ^ kToggleBit);
    deadline_ = now + timeout_;
    if (last) {
        reset();
    }
    respond(b);
}

void SdoServer::downloadInitiate(const std::uint8_t* r, core::TimeNs now) {
    const std::uint16_t index = le::u16(&r[1]);
    const std::uint8_t subIndex = r[3];
    SdoObjectInfo info;
    std::uint32_t code = dictionary_.describe(index, subIndex, &info);
    if (code == sdo_abort::kNone && !info.writable) {
        code = sdo_abort::kWriteToReadOnly;
    }
    if (code != sdo_abort::kNone) {
        abort(index, subIndex, code);
        return;
    }
    const bool expedited = (r[0] & kExpeditedBit) != 0;
    const bool sizeIndicated = (r[0] & kSizeBit) != 0;
    if (expedited) {
        // s = 0: "unspecified number of bytes": take the object's own size.
        const std::size_t size = sizeIndicated ? 4U - ((r[0] >> 2U) & 0x03U) : info.size;
        if (size != info.size) {
            abort(index, subIndex, sdo_abort::kLengthMismatch);
            return;
        }
        code = dictionary_.write(index, subIndex, &r[4], size, now);
        if (code != sdo_abort::kNone) {
            abort(index, subIndex, code);
            return;
        }
        std::uint8_t b[8] = {kScsDownloadInitiate};
        le::put16(&b[1], index);
        b[3] = subIndex;
        respond(b);
        return;
    }
    // Segmented download: the announced size (if any) must be the object's.
    if ((sizeIndicated && le::u32(&r[4]) != info.size) || info.size > kSdoServerMaxObject) {
        abort(index, subIndex, sdo_abort::kLengthMismatch);
        return;
    }
    phase_ = Phase::kDownloading;
    index_ = index;
    subIndex_ = subIndex;
    size_ = info.size;
    offset_ = 0;
    toggle_ = 0;
    deadline_ = now + timeout_;
    std::uint8_t b[8] = {kScsDownloadInitiate};
    le::put16(&b[1], index);
    b[3] = subIndex;
    respond(b);
}

void SdoServer::downloadSegment(const std::uint8_t* r, core::TimeNs now) {
    const std::uint8_t toggle = static_cast<std::uint8_t>(r[0] & kToggleBit);
    if (toggle != toggle_) {
        abort(index_, subIndex_, sdo_abort::kToggleNotAlternated);
        return;
    }
    const std::size_t n = kSegmentBytes - ((r[0] >> 1U) & 0x07U);
    const bool last = (r[0] & kLastSegmentBit) != 0;
    if (offset_ + n > size_ || (last && offset_ + n != size_)) {
        abort(index_, subIndex_, sdo_abort::kLengthMismatch);
        return;
    }
    for (std::size_t i = 0; i < n; ++i) {
        buffer_[offset_ + i] = r[1 + i];
    }
    offset_ += n;
    std::uint8_t b[8] = {};
    b[0] = static_cast<std::uint8_t>(kScsDownloadSegment | toggle_);
    toggle_ = static_cast<std::uint8_t>(toggle_ ^ kToggleBit);
    deadline_ = now + timeout_;
    if (last) {
        const std::uint32_t code = dictionary_.write(index_, subIndex_, buffer_, size_, now);
        if (code != sdo_abort::kNone) {
            abort(index_, subIndex_, code);
            return;
        }
        reset();
    }
    respond(b);
}

void SdoServer::poll(core::TimeNs now) {
    if (phase_ == Phase::kIdle || now <= deadline_) {
        return;
    }
    ++stats_.timeouts;
    abort(index_, subIndex_, sdo_abort::kTimeout);
}

}  // namespace rse::sim

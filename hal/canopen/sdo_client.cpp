#include "hal/canopen/sdo_client.hpp"

#include <cstring>

#include "hal/canopen/canopen_events.hpp"
#include "hal/canopen/canopen_ids.hpp"
#include "hal/canopen/le_codec.hpp"

namespace rse::hal::canopen {

using core::Severity;
using core::Status;

namespace {
// Command specifiers (upper 3 bits of byte 0).
constexpr std::uint8_t kCcsDownloadInitiate = 1;
constexpr std::uint8_t kCcsUploadInitiate = 2;
constexpr std::uint8_t kCcsUploadSegment = 3;
constexpr std::uint8_t kCsAbort = 4;
constexpr std::uint8_t kScsUploadSegment = 0;
constexpr std::uint8_t kScsUploadInitiate = 2;
constexpr std::uint8_t kScsDownloadInitiate = 3;

std::uint8_t commandOf(std::uint8_t byte0) { return static_cast<std::uint8_t>(byte0 >> 5); }
}  // namespace

const char* toString(SdoResult result) {
    switch (result) {
        case SdoResult::kIdle: return "idle";
        case SdoResult::kInProgress: return "in-progress";
        case SdoResult::kDone: return "done";
        case SdoResult::kAborted: return "aborted";
        case SdoResult::kTimeout: return "timeout";
        case SdoResult::kProtocolError: return "protocol-error";
    }
    return "?";
}

void SdoClient::configure(std::uint8_t nodeId, core::TimeNs timeout) {
    nodeId_ = nodeId;
    timeout_ = timeout;
}

void SdoClient::clear() {
    phase_ = Phase::kNone;
    result_ = SdoResult::kIdle;
}

Status SdoClient::request(const std::uint8_t (&bytes)[8], core::TimeNs now) {
    CanFrame f;
    f.id = kSdoRequest + nodeId_;
    f.dlc = 8;
    std::memcpy(f.data, bytes, 8);
    const Status s = bus_.send(f);
    if (core::isOk(s)) {
        deadline_ = now + timeout_;
    }
    return s;
}

Status SdoClient::download(std::uint16_t index, std::uint8_t subIndex, std::uint32_t value, std::uint8_t size,
                           core::TimeNs now) {
    if (result_ == SdoResult::kInProgress) {
        return Status::kBusy;
    }
    if (size < 1 || size > 4) {
        return Status::kInvalidArgument;
    }
    // Expedited (e = 1), size indicated (s = 1), n = 4 - size unused bytes.
    std::uint8_t b[8] = {};
    b[0] = static_cast<std::uint8_t>((kCcsDownloadInitiate << 5) | ((4 - size) << 2) | 0x03);
    le::putU16(&b[1], index);
    b[3] = subIndex;
    le::putU32(&b[4], value);
    const Status s = request(b, now);
    if (!core::isOk(s)) {
        return s;
    }
    phase_ = Phase::kDownload;
    result_ = SdoResult::kInProgress;
    index_ = index;
    subIndex_ = subIndex;
    // A download reads nothing back: what an earlier transfer left must not be
    // taken for this one's result (event 431 prints these).
    value_ = 0;
    length_ = 0;
    abortCode_ = 0;
    return Status::kOk;
}

Status SdoClient::upload(std::uint16_t index, std::uint8_t subIndex, core::TimeNs now) {
    if (result_ == SdoResult::kInProgress) {
        return Status::kBusy;
    }
    std::uint8_t b[8] = {};
    b[0] = static_cast<std::uint8_t>(kCcsUploadInitiate << 5);
    le::putU16(&b[1], index);
    b[3] = subIndex;
    const Status s = request(b, now);
    if (!core::isOk(s)) {
        return s;
    }
    phase_ = Phase::kUploadInitiate;
    result_ = SdoResult::kInProgress;
    index_ = index;
    subIndex_ = subIndex;
    value_ = 0;
    length_ = 0;
    abortCode_ = 0;
    announced_ = 0;
    return Status::kOk;
}

void SdoClient::sendAbort(std::uint32_t code) {
    std::uint8_t b[8] = {};
    b[0] = static_cast<std::uint8_t>(kCsAbort << 5);
    le::putU16(&b[1], index_);
    b[3] = subIndex_;
    le::putU32(&b[4], code);
    CanFrame f;
    f.id = kSdoRequest + nodeId_;
    f.dlc = 8;
    std::memcpy(f.data, b, 8);
    (void)bus_.send(f);  // best effort: the transfer ends either way
}

void SdoClient::finishProtocolError(const char* why, core::TimeNs) {
    ++stats_.protocolErrors;
    result_ = SdoResult::kProtocolError;
    phase_ = Phase::kNone;
    events_.report(events::kSdoProtocolError, Severity::kError, "sdo: node %u 0x%04X:%u %s",
                   static_cast<unsigned>(nodeId_), static_cast<unsigned>(index_),
                   static_cast<unsigned>(subIndex_), why);
}

void SdoClient::handleUploadInitiate(const CanFrame& f, core::TimeNs now) {
    const std::uint8_t b0 = f.data[0];
    const bool expedited = (b0 & 0x02) != 0;
    const bool sizeIndicated = (b0 & 0x01) != 0;
    if (expedited) {
        const std::size_t size = sizeIndicated ? 4U - ((b0 >> 2) & 0x03U) : 4U;
        std::memcpy(data_, &f.data[4], size);
        length_ = size;
        std::uint8_t padded[4] = {};
        std::memcpy(padded, &f.data[4], size);
        value_ = le::getU32(padded);
        result_ = SdoResult::kDone;
        phase_ = Phase::kNone;
        ++stats_.completed;
        return;
    }
    // Segmented: bytes 4-7 may announce the size.
    announced_ = sizeIndicated ? le::getU32(&f.data[4]) : 0;
    if (announced_ > kSdoMaxUpload) {
        sendAbort(sdo_abort::kOutOfMemory);
        finishProtocolError("segmented upload larger than the client buffer", now);
        return;
    }
    toggle_ = 0;
    std::uint8_t b[8] = {};
    b[0] = static_cast<std::uint8_t>(kCcsUploadSegment << 5);
    if (!core::isOk(request(b, now))) {
        finishProtocolError("could not request the first segment", now);
        return;
    }
    phase_ = Phase::kUploadSegment;
}

void SdoClient::handleUploadSegment(const CanFrame& f, core::TimeNs now) {
    const std::uint8_t b0 = f.data[0];
    const std::uint8_t toggle = static_cast<std::uint8_t>((b0 >> 4) & 0x01);
    if (toggle != toggle_) {
        sendAbort(sdo_abort::kToggleNotAlternated);
        finishProtocolError("toggle bit not alternated", now);
        return;
    }
    const std::size_t bytes = 7U - ((b0 >> 1) & 0x07U);
    const bool last = (b0 & 0x01) != 0;
    if (length_ + bytes > kSdoMaxUpload) {
        sendAbort(sdo_abort::kOutOfMemory);
        finishProtocolError("segmented upload overflows the client buffer", now);
        return;
    }
    std::memcpy(&data_[length_], &f.data[1], bytes);
    length_ += bytes;
    if (!last) {
        toggle_ ^= 1U;
        std::uint8_t b[8] = {};
        b[0] = static_cast<std::uint8_t>((kCcsUploadSegment << 5) | (toggle_ << 4));
        if (!core::isOk(request(b, now))) {
            finishProtocolError("could not request the next segment", now);
        }
        return;
    }
    if (announced_ != 0 && announced_ != length_) {
        finishProtocolError("segmented upload length differs from the announced size", now);
        return;
    }
    std::uint8_t padded[4] = {};
    std::memcpy(padded, data_, length_ < 4 ? length_ : 4);
    value_ = le::getU32(padded);
    result_ = SdoResult::kDone;
    phase_ = Phase::kNone;
    ++stats_.completed;
}

void SdoClient::onFrame(const CanFrame& f, core::TimeNs now) {
    if (result_ != SdoResult::kInProgress) {
        ++stats_.unexpected;
        return;
    }
    if (f.dlc != 8) {
        sendAbort(sdo_abort::kGeneralError);
        finishProtocolError("response with DLC other than 8", now);
        return;
    }
    const std::uint8_t scs = commandOf(f.data[0]);
    if (scs == kCsAbort) {
        abortCode_ = le::getU32(&f.data[4]);
        ++stats_.abortedByServer;
        result_ = SdoResult::kAborted;
        phase_ = Phase::kNone;
        events_.report(events::kSdoAborted, Severity::kWarning, "sdo: node %u aborted 0x%04X:%u, code 0x%08X",
                       static_cast<unsigned>(nodeId_), static_cast<unsigned>(index_),
                       static_cast<unsigned>(subIndex_), static_cast<unsigned>(abortCode_));
        return;
    }
    const bool initiateAnswer = phase_ == Phase::kDownload || phase_ == Phase::kUploadInitiate;
    if (initiateAnswer && (le::getU16(&f.data[1]) != index_ || f.data[3] != subIndex_)) {
        sendAbort(sdo_abort::kGeneralError);
        finishProtocolError("response for another object", now);
        return;
    }
    switch (phase_) {
        case Phase::kDownload:
            if (scs != kScsDownloadInitiate) {
                sendAbort(sdo_abort::kInvalidCommand);
                finishProtocolError("unexpected command specifier to a download", now);
                return;
            }
            result_ = SdoResult::kDone;
            phase_ = Phase::kNone;
            ++stats_.completed;
            return;
        case Phase::kUploadInitiate:
            if (scs != kScsUploadInitiate) {
                sendAbort(sdo_abort::kInvalidCommand);
                finishProtocolError("unexpected command specifier to an upload", now);
                return;
            }
            handleUploadInitiate(f, now);
            return;
        case Phase::kUploadSegment:
            if (scs != kScsUploadSegment) {
                sendAbort(sdo_abort::kInvalidCommand);
                finishProtocolError("unexpected command specifier to a segment request", now);
                return;
            }
            handleUploadSegment(f, now);
            return;
        case Phase::kNone:
            break;
    }
    ++stats_.unexpected;
}

void SdoClient::poll(core::TimeNs now) {
    if (result_ != SdoResult::kInProgress || now <= deadline_) {
        return;
    }
    sendAbort(sdo_abort::kTimeout);
    ++stats_.timeouts;
    result_ = SdoResult::kTimeout;
    phase_ = Phase::kNone;
    events_.report(events::kSdoTimeout, Severity::kWarning, "sdo: node %u 0x%04X:%u no answer in %lld ms",
                   static_cast<unsigned>(nodeId_), static_cast<unsigned>(index_),
                   static_cast<unsigned>(subIndex_), static_cast<long long>(timeout_ / core::kNsPerMs));
}

}  // namespace rse::hal::canopen

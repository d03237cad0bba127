// CiA 301 SDO client for one server node: expedited download and upload, and
// segmented upload (for objects longer than 4 bytes, toggle bit checked on every
// segment). One transfer at a time; poll-driven, never blocks. Every way a
// transfer can end badly is its own result, counter and event: aborted by the
// server (its abort code kept), timed out (we send abort 0x05040000), or a
// response that breaks the protocol (we send abort and say why).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/canopen/sdo_abort_codes.hpp"

namespace rse::hal::canopen {

constexpr std::size_t kSdoMaxUpload = 64;  // bytes a segmented upload may bring back
constexpr core::TimeNs kSdoDefaultTimeout = 100 * core::kNsPerMs;


enum class SdoResult : std::uint8_t { kIdle, kInProgress, kDone, kAborted, kTimeout, kProtocolError };
const char* toString(SdoResult result);

struct SdoStats {
    std::uint32_t completed = 0;
    std::uint32_t abortedByServer = 0;
    std::uint32_t timeouts = 0;
    std::uint32_t protocolErrors = 0;
    std::uint32_t unexpected = 0;  // responses with no transfer in progress, ignored
};

class SdoClient {
public:
    SdoClient(CanBus& bus, core::EventLog& events, std::uint8_t nodeId,
              core::TimeNs timeout = kSdoDefaultTimeout)
        : bus_(bus), events_(events), nodeId_(nodeId), timeout_(timeout) {}

    // kBusy while a transfer is in progress; kInvalidArgument for size not 1..4;
    // kUnavailable (etc.) when the request could not be sent.
    core::Status download(std::uint16_t index, std::uint8_t subIndex, std::uint32_t value,
                          std::uint8_t size, core::TimeNs now);
    core::Status upload(std::uint16_t index, std::uint8_t subIndex, core::TimeNs now);

    void onFrame(const CanFrame& frame, core::TimeNs now);  // 0x580 + node
    void poll(core::TimeNs now);                            // timeouts

    SdoResult result() const { return result_; }
    // After kDone of an upload: the value (expedited or first 4 bytes, little-endian)
    // and the raw bytes.
    std::uint32_t value() const { return value_; }
    const std::uint8_t* data() const { return data_; }
    std::size_t dataLength() const { return length_; }
    std::uint32_t abortCode() const { return abortCode_; }
    // Back to idle so the next transfer can start (after reading the result).
    void clear();
    // Start-up only (no transfer in progress): the server's node id and the
    // answer timeout come from tables the owner reads after construction.
    void configure(std::uint8_t nodeId, core::TimeNs timeout);

    const SdoStats& stats() const { return stats_; }
    std::uint8_t nodeId() const { return nodeId_; }

private:
    enum class Phase : std::uint8_t { kNone, kDownload, kUploadInitiate, kUploadSegment };

    core::Status request(const std::uint8_t (&bytes)[8], core::TimeNs now);
    void finishProtocolError(const char* why, core::TimeNs now);
    void sendAbort(std::uint32_t code);
    void handleUploadInitiate(const CanFrame& frame, core::TimeNs now);
    void handleUploadSegment(const CanFrame& frame, core::TimeNs now);

    CanBus& bus_;
    core::EventLog& events_;
    std::uint8_t nodeId_;
    core::TimeNs timeout_;
    Phase phase_ = Phase::kNone;
    SdoResult result_ = SdoResult::kIdle;
    std::uint16_t index_ = 0;
    std::uint8_t subIndex_ = 0;
    core::TimeNs deadline_ = 0;
    std::uint8_t toggle_ = 0;
    std::uint32_t value_ = 0;
    std::uint32_t abortCode_ = 0;
    std::uint8_t data_[kSdoMaxUpload] = {};
    std::size_t length_ = 0;
    std::size_t announced_ = 0;  // segmented upload size from the server, 0 if not given
    SdoStats stats_;
};

}  // namespace rse::hal::canopen

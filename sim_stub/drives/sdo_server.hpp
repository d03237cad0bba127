// CiA 301 SDO server for the simulator's CANopen devices (docs/icd.md §1.4).
//
// One server channel: requests on 0x600+n, responses on 0x580+n. Supports what a
// small real device supports: expedited upload and download, segmented upload
// (objects longer than 4 bytes, e.g. a device name) and segmented download, with
// the toggle bit checked on every segment. Block transfer is not supported and is
// answered with abort 0x05040001, as real devices without it do. The protocol
// engine knows nothing of the device: objects are reached through the
// ObjectDictionary interface the device implements.
//
// Fixed storage only; nothing is allocated; nothing throws.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/canopen/sdo_abort_codes.hpp"

namespace rse::sim {

// CiA 301 SDO abort codes: the one table in hal/canopen.
namespace sdo_abort = hal::canopen::sdo_abort;

// Largest object value the server moves (segmented transfers buffer it whole).
constexpr std::size_t kSdoServerMaxObject = 32;
constexpr core::TimeNs kSdoServerDefaultTimeout = 1 * core::kNsPerSec;

struct SdoObjectInfo {
    std::size_t size = 0;  // bytes of the value (strings: their length)
    bool readable = false;
    bool writable = false;
};

// The device side of the SDO server. Every call returns 0 or a CiA 301 abort code.
class SdoObjectDictionary {
public:
    // kObjectDoesNotExist or kSubIndexDoesNotExist when the entry is not there.
    virtual std::uint32_t describe(std::uint16_t index, std::uint8_t subIndex, SdoObjectInfo* info) const = 0;
    // The value's info.size bytes, little-endian, into out (capacity >= that size).
    virtual std::uint32_t read(std::uint16_t index, std::uint8_t subIndex, std::uint8_t* out,
                               std::size_t capacity) = 0;
    // Called with existence, access and length already checked: the device checks the
    // value's range and applies it (at time now).
    virtual std::uint32_t write(std::uint16_t index, std::uint8_t subIndex, const std::uint8_t* data,
                                std::size_t size, core::TimeNs now) = 0;

protected:
    ~SdoObjectDictionary() = default;
};

struct SdoServerStats {
    std::uint32_t requests = 0;        // well-formed requests handled (DLC 8)
    std::uint32_t responses = 0;       // non-abort answers sent
    std::uint32_t abortsSent = 0;      // aborts we sent (each also kept in lastAbortCode)
    std::uint32_t abortsReceived = 0;  // client aborted a transfer
    std::uint32_t malformed = 0;       // requests with DLC != 8 (or RTR/extended): ignored
    std::uint32_t timeouts = 0;        // segmented transfers the client abandoned
    std::uint32_t sendFailures = 0;    // answers the bus refused
};

class SdoServer {
public:
    SdoServer(hal::CanBus& bus, SdoObjectDictionary& dictionary, std::uint8_t nodeId,
              core::TimeNs timeout = kSdoServerDefaultTimeout)
        : bus_(bus), dictionary_(dictionary), nodeId_(nodeId), timeout_(timeout) {}

    // A frame addressed to 0x600 + node id (any DLC: malformed ones are counted).
    void onRequest(const hal::CanFrame& frame, core::TimeNs now);
    // A segmented transfer with no request for `timeout` is aborted (0x05040000).
    void poll(core::TimeNs now);
    // Ends any transfer without a word (NMT reset, stopped, power loss).
    void reset();

    bool transferInProgress() const { return phase_ != Phase::kIdle; }
    std::uint32_t lastAbortCode() const { return lastAbortCode_; }
    const SdoServerStats& stats() const { return stats_; }

private:
    enum class Phase : std::uint8_t { kIdle, kUploading, kDownloading };

    void uploadInitiate(std::uint16_t index, std::uint8_t subIndex, core::TimeNs now);
    void uploadSegment(const std::uint8_t* request, core::TimeNs now);
    void downloadInitiate(const std::uint8_t* request, core::TimeNs now);
    void downloadSegment(const std::uint8_t* request, core::TimeNs now);
    void abort(std::uint16_t index, std::uint8_t subIndex, std::uint32_t code);
    void respond(const std::uint8_t (&bytes)[8]);

    hal::CanBus& bus_;
    SdoObjectDictionary& dictionary_;
    std::uint8_t nodeId_;
    core::TimeNs timeout_;

    Phase phase_ = Phase::kIdle;
    std::uint16_t index_ = 0;
    std::uint8_t subIndex_ = 0;
    std::uint8_t toggle_ = 0;        // toggle expected in the next segment request
    std::size_t size_ = 0;           // object size (upload: bytes to send; download: expected)
    std::size_t offset_ = 0;         // bytes moved so far
    core::TimeNs deadline_ = 0;
    std::uint8_t buffer_[kSdoServerMaxObject] = {};
    std::uint32_t lastAbortCode_ = 0;
    SdoServerStats stats_;
};

}  // namespace rse::sim

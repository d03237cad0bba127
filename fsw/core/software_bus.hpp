// Publish/subscribe by message id with all storage reserved at construction.
//
// A publisher copies its payload into the queue of every pipe subscribed to the
// id. Each pipe has its own fixed depth: a full pipe drops that message for that
// pipe only (counted per pipe and in total, evented), so a slow consumer never
// blocks a cyclic task or starves the others. Payloads above kBusMaxPayload are
// rejected. Queue slots for all pipes come from one fixed array, carved out when
// the pipe is created at start-up.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/status.hpp"

namespace rse::core {

using MsgId = std::uint16_t;
using PipeId = std::uint8_t;

// Documented capacities (docs/architecture.md, "Software bus").
constexpr std::size_t kBusMaxPayload = 1024;   // bytes per message
constexpr std::size_t kBusMaxPipes = 32;       // subscribers (pipes)
constexpr std::size_t kBusMaxRoutes = 64;      // distinct subscribed message ids
constexpr std::size_t kBusTotalQueueSlots = 264;  // sum of all pipe depths: the flight's 216, and 48 for a test's probes
constexpr std::size_t kPipeNameSize = 16;

struct MessageHeader {
    MsgId id = 0;
    std::uint16_t length = 0;    // payload bytes
    std::uint32_t sequence = 0;  // per message id, counts every publish
    TimeNs time = 0;             // publish time on the executive clock
};

struct Message {
    MessageHeader header;
    alignas(8) std::uint8_t payload[kBusMaxPayload] = {};

    // Copies the payload out as T, checking id and size.
    template <typename T>
    Status decode(T* out) const {
        static_assert(std::is_trivially_copyable<T>::value, "bus messages are plain data");
        if (header.id != T::kMsgId) {
            return Status::kWrongType;
        }
        if (header.length != sizeof(T)) {
            return Status::kWrongType;
        }
        std::memcpy(out, payload, sizeof(T));
        return Status::kOk;
    }
};

struct PipeStats {
    std::uint32_t delivered = 0;   // enqueued on this pipe
    std::uint32_t received = 0;    // taken out by the subscriber
    std::uint32_t dropped = 0;     // lost because this pipe was full
    std::uint16_t depth = 0;
    std::uint16_t highWater = 0;   // most messages queued at once
};

struct BusStats {
    std::uint32_t published = 0;        // accepted publish calls
    std::uint32_t delivered = 0;        // copies enqueued over all pipes
    std::uint32_t dropped = 0;          // copies lost to full pipes
    std::uint32_t rejectedTooLarge = 0;
    std::uint32_t rejectedInvalid = 0;  // null payload with a non-zero length
    std::uint32_t noSubscribers = 0;    // accepted, but nobody listens to the id
    std::uint32_t configRejected = 0;   // createPipe / subscribe refused
};

class SoftwareBus {
public:
    SoftwareBus(const Clock& clock, EventLog& events) : clock_(clock), events_(events) {}

    // Start-up configuration.
    Status createPipe(const char* name, std::uint16_t depth, PipeId* out);
    Status subscribe(PipeId pipe, MsgId id);

    // Never blocks. kTooLarge for oversized payloads; kOk even when some pipes
    // were full (their drops are counted and evented).
    Status publish(MsgId id, const void* payload, std::size_t length);

    template <typename T>
    Status publish(const T& message) {
        static_assert(std::is_trivially_copyable<T>::value, "bus messages are plain data");
        static_assert(sizeof(T) <= kBusMaxPayload, "message larger than kBusMaxPayload");
        return publish(T::kMsgId, &message, sizeof(T));
    }

    // Oldest queued message of the pipe; kEmpty when none, kNotFound for a bad
    // pipe, kInvalidArgument for a null out.
    Status receive(PipeId pipe, Message* out);

    const BusStats& stats() const { return stats_; }
    const PipeStats* pipeStats(PipeId pipe) const;
    const char* pipeName(PipeId pipe) const;
    std::size_t pipeCount() const { return pipeCount_; }
    void resetCounters();

private:
    struct Pipe {
        char name[kPipeNameSize] = {};
        std::uint16_t firstSlot = 0;
        std::uint16_t head = 0;
        std::uint16_t count = 0;
        PipeStats stats;
    };
    struct Route {
        MsgId id = 0;
        std::uint32_t pipeMask = 0;  // bit p set: pipe p subscribes
        std::uint32_t sequence = 0;
    };
    static_assert(kBusMaxPipes <= 32, "pipeMask holds one bit per pipe");

    Route* findRoute(MsgId id);
    Status rejectConfig(const char* what, Status status);
    void enqueue(PipeId pipe, const MessageHeader& header, const void* payload);

    const Clock& clock_;
    EventLog& events_;
    Pipe pipes_[kBusMaxPipes];
    std::size_t pipeCount_ = 0;
    Route routes_[kBusMaxRoutes];
    std::size_t routeCount_ = 0;
    std::size_t slotsUsed_ = 0;
    BusStats stats_;
    Message slots_[kBusTotalQueueSlots];
};

}  // namespace rse::core

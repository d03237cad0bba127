// One task's input from the software bus: its pipe, and for each message id it
// takes, the handler that takes it. A run drains the pipe (at most its depth of
// messages, so the loop is bounded), decodes each message as the type its
// handler takes and calls the handler; a message that does not decode (wrong id
// or size), that no handler takes, or whose handler refuses its content, is
// counted and evented: the 1st, 2nd, 4th, 8th ... time (core::isReportableOccurrence),
// with the task's own event id. The previous good input stays where the task
// keeps it: a refused message changes nothing but the counters.
//
// Every task used to write this loop out itself (receive, switch on the id,
// decode, count the malformed, throttle the event); this is that loop once.
//
//   class MyTask {
//       core::Status init() {
//           core::Status s = pipe_.create();
//           if (core::isOk(s)) s = pipe_.route<&MyTask::takePose>(this);
//           ...
//       }
//       void takePose(const msg::PoseEstimateMsg& pose);          // always takes it
//       core::Status takeHazards(const msg::KnownHazardsMsg& m);  // kOk, or refuses it
//       void run(...) { pipe_.drain(); ... }
//   };
//
// Several routes may take one id (each gets the message, in the order they were
// routed: the telemetry task's packers share one pipe). Decoding uses storage
// inside the pipe, not the stack, so a 1 KiB message costs no stack. No heap:
// routes are a fixed array (kMaxInputRoutes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>

#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/core/status.hpp"

namespace rse::core {

// The longest refusal detail a handler may give (explain()), with its NUL.
constexpr std::size_t kRefusalDetailSize = 64;

// Handlers one pipe can hold (the telemetry task's packers take 15 ids in 16 routes: DriveStatusMsg twice).
constexpr std::size_t kMaxInputRoutes = 24;

namespace input_pipe_detail {
template <typename Handler>
struct HandlerTraits;
template <typename O, typename M>
struct HandlerTraits<void (O::*)(const M&)> {
    using Owner = O;
    using Msg = M;
    static constexpr bool kReturnsStatus = false;
};
template <typename O, typename M>
struct HandlerTraits<Status (O::*)(const M&)> {
    using Owner = O;
    using Msg = M;
    static constexpr bool kReturnsStatus = true;
};
}  // namespace input_pipe_detail

struct InputPipeConfig {
    const char* name;          // the pipe's name on the bus (at most kPipeNameSize - 1 characters)
    std::uint16_t depth;       // messages it holds; one drain() takes at most this many
    EventId malformedEvent;    // the owner's event for a message it could not take
    const char* owner;         // the event text's first word ("estimator", "telemetry", ...)
    // The event's severity: the owner's, as its hand-written loop reported it
    // (the health task's is a warning).
    Severity severity = Severity::kError;
};

class InputPipe {
public:
    InputPipe(SoftwareBus& bus, EventLog& events, const InputPipeConfig& config)
        : bus_(bus), events_(events), config_(config) {}

    // Start-up: the pipe on the bus. kAlreadyExists when called twice; the
    // bus's refusal (capacity, zero depth) as it is.
    Status create();

    // Start-up, after create(): messages of Handler's message type go to
    // owner->*Handler. Handler is `void (Owner::*)(const M&)` or
    // `Status (Owner::*)(const M&)` (anything but kOk refuses the message: it
    // is counted and evented as malformed). The first route of an id
    // subscribes the pipe to it. kNotInitialized before create(), kNoCapacity
    // past kMaxInputRoutes, kInvalidArgument for a null owner.
    template <auto Handler, typename Owner>
    Status route(Owner* owner) {
        using Traits = input_pipe_detail::HandlerTraits<decltype(Handler)>;
        using M = typename Traits::Msg;
        static_assert(std::is_same<Owner, typename Traits::Owner>::value ||
                          std::is_base_of<typename Traits::Owner, Owner>::value,
                      "the handler is not a member of the owner's class");
        static_assert(std::is_trivially_copyable<M>::value, "bus messages are plain data");
        static_assert(sizeof(M) <= kBusMaxPayload, "message larger than the bus carries");
        static_assert(alignof(M) <= alignof(std::max_align_t), "message over-aligned for the decode storage");
        return addRoute(M::kMsgId, static_cast<typename Traits::Owner*>(owner), &deliver<Handler, nullptr>);
    }

    // Start-up, as route<Handler>(), for an owner that counts a message of this
    // id that does not decode with its own refusals of the type rather than as
    // malformed input (the trajectory follower: a trajectory that does not
    // decode is a refused trajectory, like one whose points it refuses).
    // OnUndecodable is `void (Owner::*)(const Message&)`, a member of Handler's
    // class: it gets the message as it came, and the pipe counts nothing.
    template <auto Handler, auto OnUndecodable, typename Owner>
    Status route(Owner* owner) {
        using Traits = input_pipe_detail::HandlerTraits<decltype(Handler)>;
        static_assert(std::is_same<decltype(OnUndecodable), void (Traits::Owner::*)(const Message&)>::value,
                      "OnUndecodable is void (Owner::*)(const Message&) of the handler's class");
        const Status status = route<Handler>(owner);
        if (isOk(status)) {
            routes_[routeCount_ - 1].deliver = &deliver<Handler, OnUndecodable>;
        }
        return status;
    }

    // Every run: takes the queued messages (at most the depth) and hands each
    // to its routes. Returns how many it took.
    std::uint16_t drain();

    // Messages refused (did not decode, no route, or a handler refused them).
    std::uint32_t malformed() const { return malformed_; }
    // Messages taken off the pipe.
    std::uint32_t taken() const { return taken_; }
    bool ready() const { return created_; }
    PipeId pipe() const { return pipe_; }
    std::size_t routeCount() const { return routeCount_; }
    // The header of the message being handled (its publish time, sequence):
    // valid inside a handler.
    const MessageHeader& current() const { return inbox_.header; }
    // Inside a handler that refuses its message: what is wrong with it, in the
    // refusal event's text instead of the status's name (e.g. "wheel 2 (ML)
    // health 9 is not a drive state"), so a rejection says specifically why.
    // At most kRefusalDetailSize - 1 characters; cleared for every message.
    void explain(const char* format, ...) __attribute__((format(printf, 2, 3)));
    void resetCounters() { malformed_ = 0; taken_ = 0; }

private:
    using Deliver = Status (*)(void* owner, const Message& message, void* storage);
    struct Route {
        MsgId id = 0;
        void* owner = nullptr;
        Deliver deliver = nullptr;
    };

    // OnUndecodable: nullptr (the pipe refuses what does not decode) or the
    // owner's handler for it (see the second route()).
    template <auto Handler, auto OnUndecodable>
    static Status deliver(void* owner, const Message& message, void* storage) {
        using Traits = input_pipe_detail::HandlerTraits<decltype(Handler)>;
        using M = typename Traits::Msg;
        auto* o = static_cast<typename Traits::Owner*>(owner);
        // Placement new only constructs in the pipe's own storage: no
        // allocation. Default-initialised, not zeroed: decode() copies every
        // byte of M (its length is checked to be sizeof(M)) before a handler
        // sees it, and a message that does not decode is never read.
        M* decoded = ::new (storage) M;
        const Status status = message.decode(decoded);
        if (!isOk(status)) {
            if constexpr (std::is_null_pointer<decltype(OnUndecodable)>::value) {
                return status;
            } else {
                (o->*OnUndecodable)(message);
                return Status::kOk;
            }
        }
        if constexpr (Traits::kReturnsStatus) {
            return (o->*Handler)(*decoded);
        } else {
            (o->*Handler)(*decoded);
            return Status::kOk;
        }
    }

    Status addRoute(MsgId id, void* owner, Deliver deliver);
    Status dispatch();
    void refuse(Status why);

    SoftwareBus& bus_;
    EventLog& events_;
    InputPipeConfig config_;
    PipeId pipe_ = 0;
    bool created_ = false;
    Route routes_[kMaxInputRoutes] = {};
    std::size_t routeCount_ = 0;
    std::uint32_t malformed_ = 0;
    std::uint32_t taken_ = 0;
    Message inbox_{};
    char detail_[kRefusalDetailSize] = {};  // explain()'s text for the message being handled
    alignas(std::max_align_t) std::uint8_t storage_[kBusMaxPayload] = {};
};

}  // namespace rse::core

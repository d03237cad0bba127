// Status codes returned by every fallible call in flight code.
//
// Flight code is built without exceptions; a failure is a Status value that the
// caller must look at ([[nodiscard]]). Each module also raises an event and bumps
// a counter where the failure matters to an operator.
#pragma once

#include <cstdint>

namespace rse::core {

enum class [[nodiscard]] Status : std::uint8_t {
    kOk = 0,
    kFull,             // fixed-capacity container or queue has no room
    kEmpty,            // nothing to read
    kTooLarge,         // a message or record exceeds its fixed maximum size
    kInvalidArgument,  // argument outside its documented range
    kNotFound,         // unknown id or handle
    kNoCapacity,       // configuration exceeds a documented compile-time limit
    kWrongType,        // a message decoded as a type it does not hold
    kNotInitialized,   // call before a successful init()
    kAlreadyExists,    // duplicate registration (e.g. same subscription twice)
    kUnavailable,      // the device or link cannot be used now (down, bus-off, not opened)
    kBusy,             // a transfer is already in progress
    kTimeout,          // a protocol peer did not answer in time
    kProtocolError,    // a peer's frame broke the protocol (sequence, toggle, size, abort)
};

// Short, stable name for logs and events.
const char* toString(Status status);

inline bool isOk(Status status) { return status == Status::kOk; }

}  // namespace rse::core

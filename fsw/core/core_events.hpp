// Event ids raised by fsw/core (range 100-199). Documented in docs/architecture.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::core::events {

// Software bus
constexpr EventId kBusQueueOverflow = 101;    // a subscriber's queue was full; message dropped for it
constexpr EventId kBusMessageTooLarge = 102;  // publish of a payload above kBusMaxPayload rejected
constexpr EventId kBusConfigRejected = 103;   // createPipe/subscribe beyond a capacity or bad argument
constexpr EventId kBusPublishInvalid = 104;   // publish with a null payload and non-zero length

// Executive
constexpr EventId kExecConfigRejected = 110;  // rate-group table invalid; executive not started
constexpr EventId kExecFrameOverrun = 111;    // a minor frame ran past the start of the next
constexpr EventId kExecFramesSkipped = 112;   // whole minor frames were lost to an overrun
constexpr EventId kExecTaskOverBudget = 113;  // a task ran longer than its budget
constexpr EventId kExecStarted = 114;
constexpr EventId kExecStopped = 115;
constexpr EventId kExecTaskEnabled = 116;     // a rate-group row was enabled or disabled (maintenance, tests)

// Process posture
constexpr EventId kRealtimeDegraded = 120;  // mlockall or SCHED_FIFO refused by the OS

}  // namespace rse::core::events

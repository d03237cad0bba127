// Event ids raised by fault protection (range 930-949). Texts start with
// "fault protection: ". Documented in docs/fault_protection.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::fault_protection::events {

constexpr core::EventId kResponseStarted = 930;   // WARN: class, fault id or wheel, the response taken
constexpr core::EventId kDriveAction = 931;       // WARN: wheel, fault reset / reset node, attempt k of n
constexpr core::EventId kRecovered = 932;         // INFO: class, fault id or wheel cleared after k attempts, how long
constexpr core::EventId kGaveUp = 933;            // CRIT: attempts used: calling home, or a drive declared failed
constexpr core::EventId kHoldChanged = 934;       // WARN/INFO: mission hold reasons set, or released (resume n)
constexpr core::EventId kTaskRestart = 935;       // WARN: rate-group row restarted, attempt k of n
constexpr core::EventId kInterlockReset = 936;    // INFO: every drive healthy again: interlock reset asked for
constexpr core::EventId kConflictingReport = 937; // WARN: a drive reported healthy and faulted in one cycle: fault taken (throttled)
constexpr core::EventId kMalformedInput = 938;    // ERROR: a bus message that does not decode, or a drive status with a health outside DriveHealth (throttled)
constexpr core::EventId kInitFailed = 939;        // ERROR: pipe creation or subscription refused at init
constexpr core::EventId kPublishFailed = 940;     // ERROR: the bus refused a hold, action or status (throttled)
constexpr core::EventId kCallHome = 941;          // CRIT: safe request sent (reason: the class that gave up)
constexpr core::EventId kReplanRequested = 942;   // WARN: off the map: waypoint cancelled, replan from the pose asked, attempt k of n

}  // namespace rse::fault_protection::events

// Event ids raised by the health monitor (fsw/estimator/health_*; range 720-759).
// Every fault class has a raise event (ERROR; CRIT for the battery) and a clear
// event (INFO), each naming the fault id, what failed and the measured value.
// Raise and clear events are edges and are not rate limited: the detection
// rules (fsw/estimator/persistence_filter.hpp, the heartbeat consumer's timeout,
// the task-stall periods) keep a fault from changing state on every frame.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::estimator::events {

constexpr core::EventId kHealthDriveHeartbeatLost = 720;      // faults 1..6: drive node declared lost (silence, timeout)
constexpr core::EventId kHealthDriveHeartbeatRestored = 721;  // its heartbeat is back (time it was lost)
constexpr core::EventId kHealthDeviceHeartbeatLost = 722;     // faults 7..10: device node declared lost
constexpr core::EventId kHealthDeviceHeartbeatRestored = 723;
constexpr core::EventId kHealthDriveOvercurrent = 724;        // faults 11..16: |motor current| above the limit, held
constexpr core::EventId kHealthDriveOvercurrentCleared = 725;
constexpr core::EventId kHealthBatteryLow = 726;              // fault 17: bus voltage below battery_low_v, held (CRIT)
constexpr core::EventId kHealthBatteryLowCleared = 727;
constexpr core::EventId kHealthBusOvercurrent = 728;          // fault 18: bus current above overcurrent_a, held
constexpr core::EventId kHealthBusOvercurrentCleared = 729;
constexpr core::EventId kHealthPoseUncertain = 730;           // fault 19: position sigma too large, or no fix in time
constexpr core::EventId kHealthPoseUncertainCleared = 731;
constexpr core::EventId kHealthTaskStalled = 732;             // faults 20..35: a rate-group task stopped running
constexpr core::EventId kHealthTaskStalledCleared = 733;
constexpr core::EventId kHealthDriveOvertemp = 736;           // faults 40..45: motor temperature above drive_overtemp_c, held
constexpr core::EventId kHealthDriveOvertempCleared = 737;    // cooled drive_overtemp_c - 5 degC, held
constexpr core::EventId kHealthSensorStale = 734;             // faults 36..39: no data from a device for its stale time
constexpr core::EventId kHealthSensorStaleCleared = 735;      // its data arrives again (time it was silent)
constexpr core::EventId kHealthOffMap = 738;                  // fault 46: the pose lies outside the site (COARSE_MAP bounds)
constexpr core::EventId kHealthOffMapCleared = 739;           // back on the map, kOffMapClearMarginM inside
constexpr core::EventId kHealthInputRejected = 740;           // malformed bus message or non-finite value (throttled)

}  // namespace rse::estimator::events

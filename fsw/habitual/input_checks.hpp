// What the habitual task takes from the bus: the checks each input passes
// before it counts. A message that fails them is refused whole (the task's
// InputPipe counts and events it, 813) and changes nothing; a leg that fails
// them is answered with a one-off report (kIdle + kBadLeg, event 801).
// Pure functions: no bus, no state.
#pragma once

#include <cstdint>

#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

// A power factor beyond this is no estimate (the drive would be far over its
// current limit): the message is refused as malformed.
constexpr float kLargestPowerFactor = 100.0F;

// Position, heading, speed and yaw rate finite (initialised or not).
bool poseFinite(const msg::PoseEstimateMsg& pose);
// A known mode.
bool modeUsable(const msg::ModeMsg& mode);
// No more sightings than the message holds (each sighting is checked when it
// is remembered: map_builder.hpp).
bool hazardsUsable(const msg::HazardMsg& hazards);
// Every drive's power factor finite, in [0, kLargestPowerFactor], its declared mode known.
bool driveModesUsable(const msg::DriveModesMsg& modes);
// A known follower state and reason.
bool followerStatusUsable(const msg::FollowerStatusMsg& status);
// A contact at a finite pose within 10^6 m of the site origin, driving forwards or backwards (+-1).
bool contactUsable(const msg::ContactMsg& contact);
// (A mission hold: msg::holdUsable, only known reasons.)

// Why a leg (legId not 0: 0 cancels) is refused, or nullptr when it is taken:
// the mode, a new id (currentLegId: the leg last taken), a finite goal on the
// coarse map, positive finite length and energy bounds, a finite power bound
// not negative (0: none), an arrival radius in [0, kMaxGoalRadiusM].
const char* legRefusal(const msg::LegCommandMsg& leg, bool autonomous, std::uint32_t currentLegId,
                       const tables::CoarseMapTable& coarse);

}  // namespace rse::habitual

// The simulated world: terrain, rover kinematics, wheel loads and power.
//
// advance(now, ...) integrates from the previous time to now in fixed sub-steps
// (default 1 ms; the last one shortened to land exactly on now), with the wheel
// speeds and currents held over the interval. Per sub-step:
//   1. body rates from the wheel speeds (skidSteerRates), times slip factors
//      (1 + slipSigma * N(0,1), redrawn every 100 ms of world time from the seed);
//   2. candidate pose by the exact unicycle solution;
//   3. collision check: the footprint disc (rover radius) against every obstacle
//      and the map boundary. If the candidate disc touches any, the translation is
//      refused (the rover is stopped at contact; it may still turn in place or
//      back away) and each obstacle touched that was not touched the sub-step
//      before counts one collision in the truth record. Contact with an obstacle
//      ends only once the disc is kContactReleaseM clear of it, so pausing at
//      the rock and pushing again is still the same collision.
// Then the battery integrates the interval and the load torques for the next
// interval are computed (wheelLoadTorques). Nothing allocates after construction.
#pragma once

#include <cstdint>
#include <vector>

#include "fsw/core/clock.hpp"
#include "sim_stub/world/kinematics.hpp"
#include "sim_stub/world/power.hpp"
#include "sim_stub/world/random.hpp"
#include "sim_stub/world/terrain.hpp"
#include "sim_stub/world/truth.hpp"

namespace rse::sim {

constexpr core::TimeNs kDefaultSubStepNs = core::kNsPerMs;
constexpr core::TimeNs kSlipRedrawNs = 100 * core::kNsPerMs;
constexpr double kContactReleaseM = 0.02;
// Sites of more obstacles than this are checked through the terrain's index
// (terrain.hpp), within kClearanceWatchM beyond the contact release.
constexpr std::size_t kWholeScanObstacles = 64;
constexpr double kClearanceWatchM = 5.0;

struct WorldConfig {
    RoverParams rover;
    BatteryParams battery;
    SolarParams solar;
    MapBounds map;
    Pose2 start;
    std::vector<Obstacle> obstacles;
    std::uint64_t seed = 1;
    core::TimeNs subStepNs = kDefaultSubStepNs;
    core::TimeNs startTime = 0;
};

class World {
public:
    explicit World(const WorldConfig& config);

    // Advances to now (no-op when now is not after the current time).
    void advance(core::TimeNs now, const WheelArray& wheelSpeedsRadS, const WheelArray& motorCurrentsA);

    // Load torque for each wheel from the last advance (0 before the first).
    double loadTorqueNm(std::size_t wheel) const { return wheel < kWheelCount ? loads_[wheel] : 0.0; }
    // Of loadTorqueNm, the share from pushing against an obstacle (blocked).
    double blockTorqueNm(std::size_t wheel) const { return wheel < kWheelCount ? blockLoads_[wheel] : 0.0; }
    const WheelArray& loadTorques() const { return loads_; }

    const TruthRecord& truth() const { return truth_; }
    const Terrain& terrain() const { return terrain_; }
    const RoverParams& rover() const { return rover_; }
    core::TimeNs time() const { return time_; }

    // Test harness: moves the rover (no collision check; contact state cleared).
    void placeRover(const Pose2& pose);
    // The ground gives way (a slide down a sandy slope): from the current time
    // the rover is carried offsetM towards bearingRad (map frame, CCW from +x)
    // at a constant rate over durationS, on top of its own motion, with the
    // usual contact checks (a rock or the world's edge stops the slide). The
    // wheels and the IMU feel nothing of it; only position fixes see it.
    void startSlide(double offsetM, double bearingRad, double durationS);
    bool sliding() const { return slideUntil_ > time_; }

private:
    void subStep(double dtS, const BodyRates& commanded);
    bool checkContacts(Vec2 centre);

    RoverParams rover_;
    Terrain terrain_;
    Battery battery_;
    SimRng slipRng_;
    core::TimeNs subStepNs_;
    core::TimeNs time_;
    core::TimeNs nextSlipDraw_;
    double slipV_ = 1.0;
    double slipW_ = 1.0;
    core::TimeNs slideUntil_ = 0;
    double slideVx_ = 0.0;  // m/s while sliding
    double slideVy_ = 0.0;
    std::vector<std::uint8_t> contact_;  // per obstacle: touched in the last sub-step
    std::vector<std::size_t> near_;      // checkContacts' obstacles near the rover (large sites)
    bool edgeContact_ = false;
    WheelArray loads_{};
    WheelArray blockLoads_{};  // of loads_, the blocked rover's slide friction
    TruthRecord truth_;
};

}  // namespace rse::sim

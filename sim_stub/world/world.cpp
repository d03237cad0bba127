#include "sim_stub/world/world.hpp"

#include <algorithm>
#include <cmath>

namespace rse::sim {

World::World(const WorldConfig& config)
    : rover_(config.rover),
      terrain_(config.map, config.obstacles),
      battery_(config.battery, config.solar),
      slipRng_(config.seed, RngStream::kWheelSlip),
      subStepNs_(config.subStepNs > 0 ? config.subStepNs : kDefaultSubStepNs),
      time_(config.startTime),
      nextSlipDraw_(config.startTime),
      contact_(config.obstacles.size(), 0) {
    near_.reserve(config.obstacles.size());   // checkContacts allocates nothing
    truth_.time = time_;
    truth_.pose = config.start;
    truth_.pose.theta = wrapAngle(config.start.theta);
    truth_.stateOfCharge = battery_.stateOfCharge();
    truth_.busVoltageV = battery_.voltageV();
    truth_.busCurrentA = battery_.busCurrentA();
    truth_.baseLoadCurrentA = battery_.baseCurrentA();
    truth_.solarCurrentA = battery_.solarCurrentA();
}

void World::placeRover(const Pose2& pose) {
    truth_.pose = pose;
    truth_.pose.theta = wrapAngle(pose.theta);
    for (std::uint8_t& c : contact_) {
        c = 0;
    }
    edgeContact_ = false;
    truth_.inContact = false;
    truth_.atMapEdge = false;
    truth_.blocked = false;
}

void World::startSlide(double offsetM, double bearingRad, double durationS) {
    if (!(offsetM > 0.0) || !(durationS > 0.0) || !std::isfinite(bearingRad)) {
        return;  // the scenario parser refuses such a slide; nothing to do
    }
    slideVx_ = offsetM / durationS * std::cos(bearingRad);
    slideVy_ = offsetM / durationS * std::sin(bearingRad);
    slideUntil_ = time_ + static_cast<core::TimeNs>(durationS * 1e9);
}

bool World::checkContacts(Vec2 centre) {
    bool overlapping = false;
    bool anyContact = false;
    // A small site is scanned whole (its least clearance exact whatever the
    // distance); a large one through the terrain's index, out to the contact
    // release and kClearanceWatchM beyond (the least clearance is then the
    // least within that: farther never matters to a contact).
    const bool whole = terrain_.obstacleCount() <= kWholeScanObstacles;
    if (!whole) {
        terrain_.near(centre, rover_.radiusM + kContactReleaseM + kClearanceWatchM, &near_);
    }
    const std::size_t visits = whole ? terrain_.obstacleCount() : near_.size();
    for (std::size_t k = 0; k < visits; ++k) {
        const std::size_t i = whole ? k : near_[k];
        const Obstacle& o = terrain_.obstacle(i);
        const double d = distanceToPolygon(centre, o.shape);
        truth_.leastClearanceM = std::min(truth_.leastClearanceM, d - rover_.radiusM);
        if (d <= rover_.radiusM) {
            overlapping = true;
            if (contact_[i] == 0) {
                ++truth_.collisions;
                truth_.lastCollisionObstacle = o.id;
            }
            contact_[i] = 1;
        } else if (d > rover_.radiusM + kContactReleaseM) {
            contact_[i] = 0;  // clearly away: a later touch is a new collision
        }
        anyContact = anyContact || contact_[i] != 0;
    }
    truth_.inContact = anyContact;
    const bool edge = !terrain_.bounds().containsDisc(centre, rover_.radiusM);
    if (edge && !edgeContact_) {
        // The map's edge is where the site's knowledge ends (a cliff, a crater
        // rim, the edge of the orbital survey): touching it is a collision.
        ++truth_.mapEdgeHits;
        ++truth_.collisions;
    }
    edgeContact_ = edge;
    truth_.atMapEdge = edge;
    return overlapping || edge;
}

void World::subStep(double dtS, const BodyRates& commanded) {
    if (rover_.slipSigma > 0.0 && time_ >= nextSlipDraw_) {
        slipV_ = 1.0 + rover_.slipSigma * slipRng_.gaussian();
        slipW_ = 1.0 + rover_.slipSigma * slipRng_.gaussian();
        nextSlipDraw_ += kSlipRedrawNs;
    }
    const double v = commanded.speedMS * slipV_;
    const double w = commanded.yawRateRadS * slipW_;
    Pose2 candidate = integrateUnicycle(truth_.pose, v, w, dtS);
    if (time_ < slideUntil_) {
        candidate.x += slideVx_ * dtS;
        candidate.y += slideVy_ * dtS;
    }
    const bool blocked = checkContacts({candidate.x, candidate.y});
    if (blocked) {
        truth_.pose.theta = candidate.theta;  // turning on the spot never moves the disc
        truth_.speedMS = 0.0;
    } else {
        truth_.pose = candidate;
        truth_.speedMS = v;
        truth_.distanceM += std::fabs(v) * dtS;
    }
    truth_.yawRateRadS = w;
    truth_.blocked = blocked;
}

void World::advance(core::TimeNs now, const WheelArray& wheelSpeedsRadS, const WheelArray& motorCurrentsA) {
    if (now <= time_) {
        return;
    }
    const core::TimeNs from = time_;
    const BodyRates commanded = skidSteerRates(wheelSpeedsRadS, rover_);
    truth_.commandedSpeedMS = commanded.speedMS;
    truth_.commandedYawRateRadS = commanded.yawRateRadS;
    while (time_ < now) {
        const core::TimeNs dt = (now - time_) < subStepNs_ ? (now - time_) : subStepNs_;
        subStep(static_cast<double>(dt) * 1e-9, commanded);
        time_ += dt;
    }
    double motorSum = 0.0;
    for (double current : motorCurrentsA) {
        motorSum += std::fabs(current);
    }
    battery_.step(static_cast<double>(now - from) * 1e-9, static_cast<double>(now) * 1e-9, motorSum);
    wheelLoadTorques(rover_, wheelSpeedsRadS, truth_.yawRateRadS, truth_.blocked, &loads_);
    // The blocked share: what wheelLoadTorques adds to every turning wheel when blocked.
    const double push = truth_.blocked ? rover_.slideFriction * rover_.wheelNormalLoadN() * rover_.wheelRadiusM : 0.0;
    for (std::size_t i = 0; i < kWheelCount; ++i) {
        blockLoads_[i] = loads_[i] > 0.0 ? push : (loads_[i] < 0.0 ? -push : 0.0);
    }

    truth_.time = now;
    for (std::size_t i = 0; i < kWheelCount; ++i) {
        truth_.wheels[i].speedRadS = wheelSpeedsRadS[i];
        truth_.wheels[i].currentA = motorCurrentsA[i];
        truth_.wheels[i].loadTorqueNm = loads_[i];
    }
    truth_.stateOfCharge = battery_.stateOfCharge();
    truth_.busVoltageV = battery_.voltageV();
    truth_.busCurrentA = battery_.busCurrentA();
    truth_.motorCurrentA = battery_.motorCurrentA();
    truth_.baseLoadCurrentA = battery_.baseCurrentA();
    truth_.solarCurrentA = battery_.solarCurrentA();
    truth_.energyDrawnWh = battery_.energyDrawnWh();
}

}  // namespace rse::sim

#include "sim_stub/lockstep/mission_recorder.hpp"

#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"

namespace rse::sim {

namespace {

double seconds(core::TimeNs t) { return static_cast<double>(t) * 1e-9; }

}  // namespace

MissionRecorder::MissionRecorder(LockstepRig& rig, std::FILE* out)
    : rig_(rig),
      out_(out),
      tracker_(rig.fsw().tables().coarseMap(), geometry::clearanceRadiusM(rig.fsw().tables().roverGeometry())) {
    truth_.reserve(2048);
    estimate_.reserve(2048);
}

void MissionRecorder::onMessage(const core::Message& message) {
    // Plan status and events of one frame (the call home) are read together:
    // the bus first, so the status's reason is in before the event.
    app::FswApp& fsw = rig_.fsw();
    msg::PoseEstimateMsg pose{};
    msg::PlanStatusMsg plan{};
    msg::RouteChunkMsg chunk{};
    if (message.header.id == msg::ids::kRouteChunk && core::isOk(message.decode(&chunk))) {
        // A route's chunks come in order, chunk 0 first: a first chunk starts a route.
        if (chunk.chunkIndex == 0 || routes_.empty()) {
            routes_.emplace_back();
        }
        for (std::size_t k = 0; k < chunk.count && k < msg::kRouteChunkPoints; ++k) {
            routes_.back().push_back(geometry::Point2{chunk.x[k], chunk.y[k]});
        }
    } else if (message.header.id == msg::ids::kPoseEstimate && core::isOk(message.decode(&pose))) {
        if (pose.initialised != 0) {
            const double t = seconds(pose.timeNs);
            tracker_.onPose(t, pose.xM, pose.yM);
            if (t >= nextEstimateS_) {
                estimate_.push_back(ground::TrackPoint{t, pose.xM, pose.yM});
                nextEstimateS_ = t + kTrackSampleS;
            }
        }
    } else if (message.header.id == msg::ids::kPlanStatus && core::isOk(message.decode(&plan))) {
        tracker_.onCallHomeReason(static_cast<std::uint8_t>(plan.callHome));
        if (plan.plansMade != plansMade_) {
            // A plan was found in the frame just run: the deliberative layer
            // still holds it and its problem.
            plansMade_ = plan.plansMade;
            plans_.push_back(ground::PlanDrawing{seconds(plan.timeNs), fsw.deliberative().problem(),
                                                 fsw.deliberative().plan()});
        }
    }
}

void MissionRecorder::frame() {
    app::FswApp& fsw = rig_.fsw();
    tracker_.setMap(fsw.tables().coarseMap());  // the one in force (the runner uplinks the scenario's)
    core::Event e;
    while (core::isOk(fsw.events().read(&cursor_, &e))) {
        tracker_.onEvent(
            ground::FlightEvent{seconds(e.time), e.id, static_cast<std::uint8_t>(e.severity), e.text, e.data});
    }
    const double now = seconds(rig_.clock().now());
    if (now >= nextTruthS_) {
        const TruthRecord& truth = rig_.rover().truth();
        truth_.push_back(ground::TrackPoint{now, truth.pose.x, truth.pose.y});
        nextTruthS_ = now + kTrackSampleS;
    }
    for (const ground::MissionPoint& p : tracker_.takeNew()) {
        if (out_ != nullptr) {
            std::fprintf(out_, "%s\n", ground::TenPointTracker::formatPoint(p).c_str());
            std::fflush(out_);
        }
    }
}

ground::MissionRecord MissionRecorder::record() const {
    ground::MissionRecord r;
    app::FswApp& fsw = rig_.fsw();
    tracker_.fill(&r);
    r.map = fsw.tables().coarseMap();
    r.footprintRadiusM = geometry::clearanceRadiusM(fsw.tables().roverGeometry());
    for (const Obstacle& ob : rig_.scenario().obstacles) {
        if (!ob.known) {
            std::vector<geometry::Point2> rock;
            for (std::size_t i = 0; i < ob.shape.n; ++i) {
                rock.push_back(geometry::Point2{ob.shape.v[i].x, ob.shape.v[i].y});
            }
            r.hiddenRocks.push_back(rock);
        }
    }
    r.plans = plans_;
    r.routes = routes_;
    const site_map::SiteMap& site = fsw.siteMap().map();
    for (std::size_t i = 0; i < site.rockCount(); ++i) {
        const site_map::Rock& rock = site.rock(i);
        std::vector<geometry::Point2> polygon;
        for (std::size_t v = 0; v < rock.count; ++v) {
            polygon.push_back(geometry::Point2{rock.x[v], rock.y[v]});
        }
        r.siteRocks.push_back(polygon);
    }
    r.truthTrack = truth_;
    const TruthRecord& truth = rig_.rover().truth();
    r.truthTrack.push_back(ground::TrackPoint{seconds(rig_.clock().now()), truth.pose.x, truth.pose.y});
    r.estimatedTrack = estimate_;
    r.energyWh = truth.energyDrawnWh;
    r.drivenM = truth.distanceM;
    r.collisions = truth.collisions;
    r.leastClearanceM = truth.leastClearanceM;
    const core::Executive& exec = fsw.executive();
    for (std::size_t i = 0; i < exec.taskCount(); ++i) {
        const core::TaskStats* st = exec.taskStats(i);
        const core::RateGroupEntry* entry = exec.entry(i);
        if (st == nullptr || entry == nullptr) {
            continue;
        }
        ground::TaskTimingRow row;
        row.name = entry->name;
        row.runs = st->runs;
        row.overBudget = st->overBudget;
        row.budgetUs = static_cast<double>(entry->budgetUs);
        row.meanUs = static_cast<double>(st->mean()) / 1000.0;
        row.maxUs = static_cast<double>(st->max) / 1000.0;
        row.hostMeanUs = static_cast<double>(st->hostMean()) / 1000.0;
        row.hostMaxUs = static_cast<double>(st->hostMax) / 1000.0;
        r.timing.push_back(row);
    }
    return r;
}

}  // namespace rse::sim

// rse-demo's recorder of the ten points (ground/mission_points.hpp) and of
// the mission record (ground/mission_record.hpp): once a frame it reads what
// an operator would see of the flight software - its events (a reader of its
// own on the event log), its plan status and its pose estimate (handed over
// by rse-demo's watch of the software bus) - feeds the ten-point tracker and
// prints each point as it is seen. At the end it adds what only the test side knows (the simulator's
// truth: the driven track, the hidden rocks; the plans the deliberative layer
// made, with their covariances, which no telemetry carries; the executive's
// per-task timing) and hands the record to the report and map writers.
// The flight software knows nothing of it.
//
// Host side (sim_stub/); rse-fsw never links it.
#pragma once

#include <cstdio>
#include <string>

#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "ground/mission_points.hpp"
#include "ground/mission_record.hpp"

namespace rse::sim {

class LockstepRig;

constexpr double kTrackSampleS = 0.5;  // one track point per half second of simulated time

class MissionRecorder {
public:
    // out: where the POINT lines go as they are seen (nullptr: nowhere).
    MissionRecorder(LockstepRig& rig, std::FILE* out);
    // A message read from the flight software's bus (plan status, pose
    // estimate; others are ignored), in the order read.
    void onMessage(const core::Message& message);
    // After every frame, once its messages are in: read the events, sample
    // the tracks, print the points seen.
    void frame();
    const ground::TenPointTracker& tracker() const { return tracker_; }
    // The record so far, with the truth and the timing added.
    ground::MissionRecord record() const;

private:
    LockstepRig& rig_;
    std::FILE* out_;
    ground::TenPointTracker tracker_;
    core::EventLog::Cursor cursor_{};
    std::uint32_t plansMade_ = 0;
    std::vector<ground::PlanDrawing> plans_;
    std::vector<std::vector<geometry::Point2>> routes_;   // site mode: ROUTE chunks assembled
    std::vector<ground::TrackPoint> truth_;
    std::vector<ground::TrackPoint> estimate_;
    double nextTruthS_ = 0.0;
    double nextEstimateS_ = 0.0;
};

}  // namespace rse::sim

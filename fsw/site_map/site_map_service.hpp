// The site map service (docs/site_map.md): the map in force (SiteMap) and its
// upload (SiteMapUpload), as the commands of APID 0x186 drive them
// (site_map_commands.hpp). It owns what it decides: a chunk or a commit
// refused is counted and evented here (events 590-594), and the last refusal
// is kept for SITE_MAP. A committed image replaces the map only when it passes
// its check whole; else the map in force is kept.
//
// MAP_COMMIT is sliced (docs/site_map.md, "A commit in slices"): commit()
// checks what it can at once (an upload open and intact, its length) and
// starts; serviceCommit(), once a command-task run, then does one slice of
// the CRC-32, the image's check, or its load into the map's slot not in force
// (kCommitCrcBytes, kCommitCheckRecords, kCommitStageUnits a slice, each
// under about 0.35 ms here on a quiet host), and puts the new map in force in the run that
// finishes it. The map in force is the one every reader uses until then.
//
// Static: the map's two slots (kSiteMapBytes) and the upload buffer
// (kMaxSiteMapImageSize) are members.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/site_map/site_map.hpp"
#include "fsw/site_map/site_map_upload.hpp"

namespace rse::site_map {

// What a commit is doing (SITE_MAP.commit_phase).
enum class CommitPhase : std::uint8_t {
    kNone = 0,    // no commit under way
    kCrc = 1,     // the image's CRC-32
    kCheck = 2,   // the image's check, record by record
    kStage = 3,   // decoded and indexed into the slot not in force
};

// A commit slice's work (one command-task run): CRC-32 bytes, records
// checked, or staging work units (site_map.hpp). Sized from bench_global_route's
// "MAP_COMMIT slices" line (each slice kind under about 0.35 ms on the
// development host when quiet, 0.48 ms when busy). Halving the check's and
// the load's was tried: it moves the GOTO after a map upload a few frames
// later, and Snowdrift's 3 700 s mission then takes another route (11
// horizon ends, not 15): see test_lockstep_snowdrift_host.cpp., so a commit's run stays inside the command task's 2 ms
// with a flood being drained.
constexpr std::size_t kCommitCrcBytes = 131072;
constexpr std::size_t kCommitCheckRecords = 2048;
constexpr std::size_t kCommitStageUnits = 8192;

struct SiteMapCounters {
    std::uint32_t chunksTaken = 0;
    std::uint32_t chunksRefused = 0;
    std::uint32_t mapsLoaded = 0;
    std::uint32_t commitsRefused = 0;
    std::uint32_t uploadsAborted = 0;
    std::uint32_t abortsRefused = 0;   // MAP_ABORT with no upload open
};

class SiteMapService {
public:
    explicit SiteMapService(core::EventLog& events) : events_(events) {}

    // MAP_LOAD: kNone when taken, else the refusal (event 591, counted).
    UploadRefusal loadChunk(std::uint32_t offset, const std::uint8_t* data, std::size_t length);
    // MAP_COMMIT: kNone when the commit started (commitPhase() kCrc), else
    // the refusal at once (nothing uploaded, spoiled, bad length, a commit
    // under way: event 592, counted).
    UploadRefusal commit(std::uint32_t length, std::uint32_t crc);
    // One slice of the commit under way (nothing when none): true when the
    // commit ended in it, the image in force (event 590) or refused (bad CRC,
    // the image's reason, or driving: the rover in AUTONOMOUS or MANUAL; event
    // 592, counted; an image's reason names its rock or zone in
    // lastRefusalItem()), the map in force kept.
    bool serviceCommit(bool driving);
    // MAP_ABORT: kNone and event 593 when an upload was open (a commit under
    // way is cancelled, the map in force kept); else kNothingUploaded (event
    // 594, counted).
    UploadRefusal abort();
    void resetCounters() { counters_ = SiteMapCounters{}; }

    const SiteMap& map() const { return map_; }
    const SiteMapUpload& upload() const { return upload_; }
    const SiteMapCounters& counters() const { return counters_; }
    UploadRefusal lastRefusal() const { return lastRefusal_; }
    std::uint32_t lastRefusalItem() const { return lastRefusalItem_; }
    std::uint32_t mapCrc() const { return mapCrc_; }
    std::uint32_t mapBytes() const { return mapBytes_; }
    CommitPhase commitPhase() const { return phase_; }
    // Command-task runs the commit under way has taken so far, or the last one took.
    std::uint32_t commitRuns() const { return commitRuns_; }
    // Since start, never zeroed (RESET_COUNTERS leaves them): the ground
    // tells a commit's end by them. Each commit started ends loaded, refused
    // or cancelled.
    std::uint32_t commitsStarted() const { return commitsStarted_; }
    std::uint32_t commitsCancelled() const { return commitsCancelled_; }

private:
    UploadRefusal refuse(UploadRefusal why, std::uint32_t item);
    // A commit refused (at once or in a slice): counted and evented.
    UploadRefusal refuseCommit(UploadRefusal why, const SiteMapCheck* check);
    void putInForce();

    core::EventLog& events_;
    SiteMap map_;
    SiteMapUpload upload_;
    SiteMapCounters counters_{};
    UploadRefusal lastRefusal_ = UploadRefusal::kNone;
    std::uint32_t lastRefusalItem_ = 0;
    std::uint32_t mapCrc_ = 0;     // CRC-32 of the image in force (0: none loaded)
    std::uint32_t mapBytes_ = 0;
    // The commit under way.
    CommitPhase phase_ = CommitPhase::kNone;
    SiteMapImageCheck check_;
    std::uint32_t commitLength_ = 0;
    std::uint32_t commitCrc_ = 0;     // the CRC-32 the commit named
    std::uint32_t crcSoFar_ = 0;
    std::size_t crcDone_ = 0;         // bytes of the image CRC'd so far
    std::uint32_t commitRuns_ = 0;
    std::uint32_t commitsStarted_ = 0;
    std::uint32_t commitsCancelled_ = 0;
};

}  // namespace rse::site_map

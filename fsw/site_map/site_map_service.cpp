#include "fsw/site_map/site_map_service.hpp"

#include "fsw/core/crc32.hpp"
#include "fsw/site_map/site_map_events.hpp"

namespace rse::site_map {

UploadRefusal SiteMapService::refuse(UploadRefusal why, std::uint32_t item) {
    lastRefusal_ = why;
    lastRefusalItem_ = item;
    return why;
}

UploadRefusal SiteMapService::loadChunk(std::uint32_t offset, const std::uint8_t* data, std::size_t length) {
    // The commit under way reads the upload buffer: no chunk may change it.
    const UploadRefusal why =
        phase_ != CommitPhase::kNone ? UploadRefusal::kCommitUnderWay : upload_.takeChunk(offset, data, length);
    if (why == UploadRefusal::kNone) {
        ++counters_.chunksTaken;
        return why;
    }
    ++counters_.chunksRefused;
    events_.report(events::kChunkRefused, core::Severity::kWarning,
                   "site_map: MAP_LOAD at %u (%u bytes) refused: %s (image so far %u bytes)",
                   static_cast<unsigned>(offset), static_cast<unsigned>(length), toString(why),
                   static_cast<unsigned>(upload_.length()));
    return refuse(why, 0);
}

UploadRefusal SiteMapService::refuseCommit(UploadRefusal why, const SiteMapCheck* check) {
    ++counters_.commitsRefused;
    if (check != nullptr) {
        events_.report(events::kCommitRefused, core::Severity::kWarning,
                       "site_map: MAP_COMMIT refused: %s (%s %u): the map in force is kept", toString(why),
                       check->keepOut ? "zone" : "rock", static_cast<unsigned>(check->item));
        return refuse(why, check->item);
    }
    events_.report(events::kCommitRefused, core::Severity::kWarning,
                   "site_map: MAP_COMMIT refused: %s: the map in force is kept", toString(why));
    return refuse(why, 0);
}

UploadRefusal SiteMapService::commit(std::uint32_t length, std::uint32_t crc) {
    const UploadRefusal why = phase_ != CommitPhase::kNone ? UploadRefusal::kCommitUnderWay : upload_.checkCommit(length);
    if (why != UploadRefusal::kNone) {
        return refuseCommit(why, nullptr);
    }
    ++commitsStarted_;
    phase_ = CommitPhase::kCrc;
    commitLength_ = length;
    commitCrc_ = crc;
    crcSoFar_ = 0;
    crcDone_ = 0;
    commitRuns_ = 0;
    return UploadRefusal::kNone;
}

bool SiteMapService::serviceCommit(bool driving) {
    if (phase_ == CommitPhase::kNone) {
        return false;
    }
    if (driving) {
        // The mode was checked when MAP_COMMIT was taken; the rover has been
        // put in AUTONOMOUS or MANUAL since, and does not change maps while
        // driving. The upload is open again, as it was (the buffer is
        // untouched): back in SAFE or STANDBY the same commit may be sent.
        phase_ = CommitPhase::kNone;
        map_.dropStaged();
        upload_.reopen();
        ++commitRuns_;
        (void)refuseCommit(UploadRefusal::kDriving, nullptr);
        return true;
    }
    switch (phase_) {
        case CommitPhase::kNone:  // handled above
            break;
        case CommitPhase::kCrc: {
            const std::size_t n = commitLength_ - crcDone_ < kCommitCrcBytes ? commitLength_ - crcDone_ : kCommitCrcBytes;
            crcSoFar_ = core::crc32(upload_.image() + crcDone_, n, crcSoFar_);
            crcDone_ += n;
            if (crcDone_ == commitLength_) {
                if (crcSoFar_ != commitCrc_) {
                    phase_ = CommitPhase::kNone;  // the upload stays open: the right CRC may be committed
                    (void)refuseCommit(UploadRefusal::kBadCrc, nullptr);
                    break;
                }
                upload_.close();
                check_.begin(upload_.image(), commitLength_);
                phase_ = CommitPhase::kCheck;
            }
            break;
        }
        case CommitPhase::kCheck:
            if (check_.step(kCommitCheckRecords)) {
                if (!check_.result().ok()) {
                    phase_ = CommitPhase::kNone;
                    (void)refuseCommit(static_cast<UploadRefusal>(refusalCode(check_.result().reason)), &check_.result());
                    break;
                }
                map_.beginStaging(upload_.image(), commitLength_);
                phase_ = CommitPhase::kStage;
            }
            break;
        case CommitPhase::kStage:
            if (map_.stage(kCommitStageUnits)) {
                putInForce();
            }
            break;
    }
    ++commitRuns_;
    return phase_ == CommitPhase::kNone;
}

void SiteMapService::putInForce() {
    (void)map_.putStagedInForce();
    phase_ = CommitPhase::kNone;
    ++counters_.mapsLoaded;
    mapCrc_ = commitCrc_;
    mapBytes_ = commitLength_;
    events_.report(events::kMapLoaded, core::Severity::kInfo,
                   "site_map: map %u in force: %u rocks, %u zones, %u bytes, CRC %08x",
                   static_cast<unsigned>(map_.revision()), static_cast<unsigned>(map_.rockCount()),
                   static_cast<unsigned>(map_.keepOutCount()), static_cast<unsigned>(commitLength_),
                   static_cast<unsigned>(commitCrc_));
    lastRefusal_ = UploadRefusal::kNone;
    lastRefusalItem_ = 0;
}

UploadRefusal SiteMapService::abort() {
    const std::size_t dropped = upload_.length();
    const bool cancelled = phase_ != CommitPhase::kNone;
    if (cancelled) {
        phase_ = CommitPhase::kNone;
        map_.dropStaged();
        ++commitsCancelled_;
    }
    if (!upload_.abort() && !cancelled) {
        ++counters_.abortsRefused;
        events_.report(events::kAbortRefused, core::Severity::kWarning, "site_map: MAP_ABORT refused: no upload open");
        return refuse(UploadRefusal::kNothingUploaded, 0);
    }
    ++counters_.uploadsAborted;
    events_.report(events::kUploadAborted, core::Severity::kInfo, "site_map: upload aborted (%u bytes dropped)%s",
                   static_cast<unsigned>(dropped), cancelled ? ": the commit under way cancelled, the map in force kept" : "");
    return UploadRefusal::kNone;
}

}  // namespace rse::site_map

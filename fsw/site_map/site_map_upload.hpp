// The site map upload (docs/site_map.md, "Uplink"): MAP_LOAD chunks assembled
// into a buffer of the largest image (kMaxSiteMapImageSize), and MAP_COMMIT's
// check of the assembled image against the length and CRC-32 it names, as
// PLAN_LOAD and PLAN_START do for plan text.
//
// Offset 0 starts a new upload. A chunk must start at or before the end of the
// image so far (else gap) and end within the buffer (else overflow); either
// spoils the upload until offset 0 again: later chunks and the commit are
// refused with the reason that spoiled it. A commit is refused with nothing
// uploaded, a spoiled upload or a length other than the image's; the service
// then checks the CRC-32 (in slices) and closes the upload when it matches:
// one commit per upload. No bus, no events: the service reports what this
// decides. The buffer is a member (static storage).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/site_map/site_map_image.hpp"

namespace rse::site_map {

// Why a chunk or a commit was refused (SITE_MAP.last_refusal, CMD_ACK.detail).
// Codes from kImage on are an image's: kImage + SiteMapReject.
enum class UploadRefusal : std::uint8_t {
    kNone = 0,
    kGap = 1,              // a chunk starting beyond the image so far
    kOverflow = 2,         // a chunk ending past kMaxSiteMapImageSize
    kSpoiled = 3,          // the upload was spoiled by a gap or an overflow (until offset 0)
    kNothingUploaded = 4,  // a commit with no upload open
    kBadLength = 5,        // the commit's length is not the image's
    kBadCrc = 6,           // the image's CRC-32 is not the commit's
    kCommitUnderWay = 7,   // MAP_LOAD or MAP_COMMIT while a commit is being checked and loaded
    kDriving = 8,          // a commit under way when the rover was put in AUTONOMOUS or MANUAL
    kImage = 16,           // + SiteMapReject: the image failed its check
};
const char* toString(UploadRefusal refusal);
constexpr std::uint8_t refusalCode(SiteMapReject reason) {
    return static_cast<std::uint8_t>(static_cast<std::uint8_t>(UploadRefusal::kImage) + static_cast<std::uint8_t>(reason));
}

class SiteMapUpload {
public:
    // A chunk of length bytes at offset: kNone when taken.
    UploadRefusal takeChunk(std::uint32_t offset, const std::uint8_t* data, std::size_t length);
    // The commit of an image length bytes long: kNone when an intact upload
    // of that length is open; else the reason, the upload left as it was (a
    // wrong length, or a CRC the service finds wrong, may be committed again
    // with the right one).
    UploadRefusal checkCommit(std::uint32_t length) const;
    // The commit's CRC matched: the upload closes (image() is it, and a new
    // upload starts at offset 0 whatever the image's own check then says).
    void close() { open_ = false; }
    // A closed commit that did not end in force for a reason not the image's
    // (the rover put in AUTONOMOUS or MANUAL): the upload open again as it was.
    void reopen() { open_ = length_ > 0 && spoiled_ == UploadRefusal::kNone; }
    // Drops the upload (MAP_ABORT); false when none was open.
    bool abort();

    const std::uint8_t* image() const { return buffer_; }
    std::size_t length() const { return length_; }
    bool open() const { return open_; }
    UploadRefusal spoiled() const { return spoiled_; }

private:
    std::uint8_t buffer_[kMaxSiteMapImageSize] = {};
    std::size_t length_ = 0;   // the end of the furthest chunk since offset 0
    bool open_ = false;
    UploadRefusal spoiled_ = UploadRefusal::kNone;
};

}  // namespace rse::site_map

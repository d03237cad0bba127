#include "fsw/site_map/site_map_upload.hpp"

#include <cstring>


namespace rse::site_map {

const char* toString(UploadRefusal refusal) {
    switch (refusal) {
        case UploadRefusal::kNone: return "none";
        case UploadRefusal::kGap: return "gap";
        case UploadRefusal::kOverflow: return "overflow";
        case UploadRefusal::kSpoiled: return "upload spoiled";
        case UploadRefusal::kNothingUploaded: return "nothing uploaded";
        case UploadRefusal::kBadLength: return "bad length";
        case UploadRefusal::kBadCrc: return "bad CRC";
        case UploadRefusal::kCommitUnderWay: return "a commit is under way";
        case UploadRefusal::kDriving: return "the rover was put in AUTONOMOUS or MANUAL during the commit";
        case UploadRefusal::kImage: break;
    }
    const int image = static_cast<int>(refusal) - static_cast<int>(UploadRefusal::kImage);
    if (image >= 0 && image <= static_cast<int>(SiteMapReject::kBadHeader)) {
        return toString(static_cast<SiteMapReject>(image));
    }
    return "?";
}

UploadRefusal SiteMapUpload::takeChunk(std::uint32_t offset, const std::uint8_t* data, std::size_t length) {
    if (offset == 0) {
        open_ = true;
        length_ = 0;
        spoiled_ = UploadRefusal::kNone;
    }
    if (!open_) {
        return UploadRefusal::kNothingUploaded;
    }
    if (spoiled_ != UploadRefusal::kNone) {
        return UploadRefusal::kSpoiled;
    }
    if (offset > length_) {
        spoiled_ = UploadRefusal::kGap;
        return spoiled_;
    }
    if (length > kMaxSiteMapImageSize || offset > kMaxSiteMapImageSize - length) {
        spoiled_ = UploadRefusal::kOverflow;
        return spoiled_;
    }
    if (length > 0) {
        std::memcpy(buffer_ + offset, data, length);
    }
    const std::size_t end = static_cast<std::size_t>(offset) + length;
    length_ = end > length_ ? end : length_;
    return UploadRefusal::kNone;
}

UploadRefusal SiteMapUpload::checkCommit(std::uint32_t length) const {
    if (!open_) {
        return UploadRefusal::kNothingUploaded;
    }
    if (spoiled_ != UploadRefusal::kNone) {
        return UploadRefusal::kSpoiled;
    }
    if (length != length_) {
        return UploadRefusal::kBadLength;
    }
    return UploadRefusal::kNone;
}

bool SiteMapUpload::abort() {
    const bool was = open_;
    open_ = false;
    length_ = 0;
    spoiled_ = UploadRefusal::kNone;
    return was;
}

}  // namespace rse::site_map

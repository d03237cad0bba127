#include "fsw/plan_executive/plan_upload.hpp"

#include <cstdio>
#include <cstring>

#include "fsw/core/crc32.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

namespace {

UploadVerdict refused(msg::PlanRefusal why, const char* detail) {
    UploadVerdict v;
    v.refusal = why;
    std::snprintf(v.detail, sizeof v.detail, "%s", detail);
    return v;
}

// PLAN_START's length or CRC (what) is not the text's.
UploadVerdict mismatch(msg::PlanRefusal why, const char* what, std::uint32_t said, std::uint32_t found) {
    UploadVerdict v;
    v.refusal = why;
    std::snprintf(v.detail, sizeof v.detail, "PLAN_START's %s %u, the text's %u", what, static_cast<unsigned>(said),
                  static_cast<unsigned>(found));
    return v;
}

}  // namespace

UploadVerdict PlanUpload::takeChunk(const msg::PlanCommandMsg& m) {
    if (m.offset == 0) {
        length_ = 0;
        open_ = true;
        spoiled_ = msg::PlanRefusal::kNone;
    }
    if (spoiled_ != msg::PlanRefusal::kNone) {
        return refused(spoiled_, "chunk of an upload already spoiled (send offset 0 again)");
    }
    if (!open_ || m.offset > length_) {
        spoiled_ = msg::PlanRefusal::kGap;
        return refused(spoiled_, "chunk beyond the text assembled so far");
    }
    if (static_cast<std::size_t>(m.offset) + m.length > kMaxPlanText) {
        spoiled_ = msg::PlanRefusal::kOverflow;
        return refused(spoiled_, "chunk past the 16384-byte plan buffer");
    }
    std::memcpy(text_ + m.offset, m.data, m.length);
    const std::size_t end = static_cast<std::size_t>(m.offset) + m.length;
    length_ = end > length_ ? end : length_;
    events_.report(events::kChunkAccepted, core::Severity::kDebug, "plan_exec: chunk at %u, %u B: %u B of plan text",
                   static_cast<unsigned>(m.offset), static_cast<unsigned>(m.length), static_cast<unsigned>(length_));
    return UploadVerdict{};
}

UploadVerdict PlanUpload::checkStart(const msg::PlanCommandMsg& m) {
    if (!open_ || length_ == 0) {
        return refused(msg::PlanRefusal::kNoUpload, "no plan text uploaded since the last start");
    }
    if (spoiled_ != msg::PlanRefusal::kNone) {
        return refused(spoiled_, "the upload was spoiled by a chunk refused");
    }
    if (m.textLength != length_) {
        return mismatch(msg::PlanRefusal::kBadLength, "length", m.textLength, static_cast<std::uint32_t>(length_));
    }
    const std::uint32_t crc = core::crc32(text_, length_);
    if (crc != m.crc32) {
        return mismatch(msg::PlanRefusal::kBadCrc, "CRC-32", m.crc32, crc);
    }
    open_ = false;  // one start per upload
    return UploadVerdict{};
}

}  // namespace rse::plan_executive

// The plan upload (docs/plan_executive.md "The task", Uplink): PLAN_LOAD
// chunks assembled into a kMaxPlanText (16 KiB) text buffer, and PLAN_START's
// check of the assembled text against the length and CRC-32 it names.
//
// Offset 0 starts a new upload. A chunk must start at or before the end of
// the text so far (else gap) and end within the buffer (else overflow);
// either spoils the upload until offset 0 again: later chunks and the start
// are refused with the same reason. A start is refused with nothing uploaded
// since the last start, with the spoiling reason, on a bad length or a bad
// CRC; one start per upload. An accepted chunk is evented here (951, DEBUG);
// a refusal is returned for the caller to report, which counts it with the
// plans refused. No bus; the buffer is a member (static storage).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

// A chunk's or a start's fate: taken, or refused with a reason and a detail
// for the refusal's event.
struct UploadVerdict {
    msg::PlanRefusal refusal = msg::PlanRefusal::kNone;
    char detail[80] = {};
    bool taken() const { return refusal == msg::PlanRefusal::kNone; }
};

class PlanUpload {
public:
    explicit PlanUpload(core::EventLog& events) : events_(events) {}

    // A PLAN_LOAD chunk: m.offset, m.length (<= msg::kPlanChunkBytes), m.data.
    UploadVerdict takeChunk(const msg::PlanCommandMsg& m);
    // PLAN_START: the upload complete, unspoiled, m.textLength long with
    // CRC-32 m.crc32. Taken: the upload closes, text() is the plan.
    UploadVerdict checkStart(const msg::PlanCommandMsg& m);

    const char* text() const { return text_; }
    // The text assembled so far (the end of the furthest chunk).
    std::size_t length() const { return length_; }

private:
    core::EventLog& events_;
    // text_[0 .. length_), open since a chunk at offset 0, spoiled by a gap
    // or an overflow until the next offset 0.
    char text_[kMaxPlanText] = {};
    std::size_t length_ = 0;
    bool open_ = false;
    msg::PlanRefusal spoiled_ = msg::PlanRefusal::kNone;
};

}  // namespace rse::plan_executive

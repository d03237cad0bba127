// The plan upload (plan_upload.hpp): PLAN_LOAD chunks assembled (each evented,
// 951), an overlap rewritten, a gap and an overflow refused and spoiling the
// upload until offset 0 again; PLAN_START taken with the text's length and
// CRC-32 (once per upload), refused with nothing uploaded, a spoiled upload,
// a bad length or a bad CRC, with the numbers in its detail.
#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/crc32.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "fsw/plan_executive/plan_upload.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using msg::PlanRefusal;
using plan_executive::PlanUpload;
using plan_executive::UploadVerdict;
namespace ev = plan_executive::events;

namespace {

constexpr const char* kText = "plan quick;event e;activity w wait start e [1, 2] cost 1;end";

msg::PlanCommandMsg chunk(const char* data, std::size_t length, std::uint32_t offset) {
    msg::PlanCommandMsg m{};
    m.kind = msg::PlanCommandKind::kChunk;
    m.offset = offset;
    m.length = static_cast<std::uint16_t>(length);
    std::memcpy(m.data, data, length);
    return m;
}

msg::PlanCommandMsg start(std::size_t length, std::uint32_t crc) {
    msg::PlanCommandMsg m{};
    m.kind = msg::PlanCommandKind::kStart;
    m.textLength = static_cast<std::uint32_t>(length);
    m.crc32 = crc;
    return m;
}

}  // namespace

TEST_GROUP(PlanUpload) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    PlanUpload* upload = nullptr;  // 16 KiB: not on the stack
    const std::size_t n = std::strlen(kText);

    void setup() override { upload = new PlanUpload(events); }
    void teardown() override { delete upload; }

    void refusedWith(const UploadVerdict& v, PlanRefusal why) {
        CHECK_FALSE(v.taken());
        LONGS_EQUAL(static_cast<long>(why), static_cast<long>(v.refusal));
    }
};

TEST(PlanUpload, ChunksAssembleTheTextAndOneStartWithItsLengthAndCrcTakesIt) {
    CHECK_TRUE(upload->takeChunk(chunk(kText, 20, 0)).taken());
    CHECK_TRUE(upload->takeChunk(chunk(kText + 20, 20, 20)).taken());
    CHECK_TRUE(upload->takeChunk(chunk(kText + 40, n - 40, 40)).taken());
    LONGS_EQUAL(3, test::drainEventsWithId(events, ev::kChunkAccepted));
    LONGS_EQUAL(n, upload->length());
    MEMCMP_EQUAL(kText, upload->text(), n);
    CHECK_TRUE(upload->checkStart(start(n, core::crc32(kText, n))).taken());
    // One start per upload: the next needs a new upload.
    refusedWith(upload->checkStart(start(n, core::crc32(kText, n))), PlanRefusal::kNoUpload);
    STRCMP_EQUAL("no plan text uploaded since the last start", upload->checkStart(start(n, 0)).detail);
}

TEST(PlanUpload, AChunkMayRewriteWhatIsThereAndAGapSpoilsTheUploadUntilOffsetZero) {
    CHECK_TRUE(upload->takeChunk(chunk(kText, 10, 0)).taken());
    CHECK_TRUE(upload->takeChunk(chunk(kText + 5, 10, 5)).taken());  // overlaps: rewritten
    LONGS_EQUAL(15, upload->length());
    const UploadVerdict gap = upload->takeChunk(chunk(kText + 20, 10, 20));
    refusedWith(gap, PlanRefusal::kGap);
    STRCMP_EQUAL("chunk beyond the text assembled so far", gap.detail);
    // The missing chunk comes too late: the upload is spoiled, and so is its start.
    const UploadVerdict late = upload->takeChunk(chunk(kText + 15, 5, 15));
    refusedWith(late, PlanRefusal::kGap);
    STRCMP_EQUAL("chunk of an upload already spoiled (send offset 0 again)", late.detail);
    refusedWith(upload->checkStart(start(15, core::crc32(kText, 15))), PlanRefusal::kGap);
    LONGS_EQUAL(2, test::drainEventsWithId(events, ev::kChunkAccepted));  // refusals are the caller's to event
    // Offset 0 starts over.
    CHECK_TRUE(upload->takeChunk(chunk(kText, n, 0)).taken());
    CHECK_TRUE(upload->checkStart(start(n, core::crc32(kText, n))).taken());
}

TEST(PlanUpload, AChunkBeforeAnyOffsetZeroIsAGap) {
    refusedWith(upload->takeChunk(chunk(kText, 10, 10)), PlanRefusal::kGap);
    refusedWith(upload->checkStart(start(10, 0)), PlanRefusal::kNoUpload);
}

TEST(PlanUpload, AChunkPastTheBufferIsAnOverflowAndSpoilsTheUpload) {
    static char filler[200];
    std::memset(filler, '#', sizeof filler);
    std::uint32_t at = 0;
    for (; at + sizeof filler <= plan_executive::kMaxPlanText; at += sizeof filler) {
        CHECK_TRUE(upload->takeChunk(chunk(filler, sizeof filler, at)).taken());
    }
    const UploadVerdict v = upload->takeChunk(chunk(filler, sizeof filler, at));
    refusedWith(v, PlanRefusal::kOverflow);
    STRCMP_EQUAL("chunk past the 16384-byte plan buffer", v.detail);
    LONGS_EQUAL(at, upload->length());
    refusedWith(upload->checkStart(start(at, core::crc32(upload->text(), at))), PlanRefusal::kOverflow);
    STRCMP_EQUAL("the upload was spoiled by a chunk refused", upload->checkStart(start(at, 0)).detail);
}

TEST(PlanUpload, ABadLengthOrCrcIsRefusedWithBothNumbersAndTheUploadStaysOpen) {
    CHECK_TRUE(upload->takeChunk(chunk(kText, n, 0)).taken());
    const UploadVerdict length = upload->checkStart(start(n + 1, core::crc32(kText, n)));
    refusedWith(length, PlanRefusal::kBadLength);
    char expected[80];
    std::snprintf(expected, sizeof expected, "PLAN_START's length %u, the text's %u", static_cast<unsigned>(n + 1),
                  static_cast<unsigned>(n));
    STRCMP_EQUAL(expected, length.detail);
    const std::uint32_t crc = core::crc32(kText, n);
    const UploadVerdict bad = upload->checkStart(start(n, crc ^ 1U));
    refusedWith(bad, PlanRefusal::kBadCrc);
    std::snprintf(expected, sizeof expected, "PLAN_START's CRC-32 %u, the text's %u", static_cast<unsigned>(crc ^ 1U),
                  static_cast<unsigned>(crc));
    STRCMP_EQUAL(expected, bad.detail);
    CHECK_TRUE(upload->checkStart(start(n, crc)).taken());
}

#include "hal/canopen/canopen_events.hpp"
#include "hal/canopen/le_codec.hpp"
#include "hal/canopen/sdo_client.hpp"
#include "unit_test/hal/canopen/canopen_test_rig.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal::canopen;
using core::Status;

TEST_GROUP(SdoClient) {
    test::CanRig rig;
    SdoClient sdo{*rig.flight, rig.events, 5};

    // The server's answer, delivered to the client.
    void answer(std::initializer_list<std::uint8_t> bytes, core::TimeNs at = 0) {
        rig.peerSends(0x585, bytes);
        hal::CanFrame f;
        CHECK(rig.flightReceives(&f));
        sdo.onFrame(f, at);
    }
    hal::CanFrame lastRequest() {
        auto frames = rig.sent();
        CHECK(frames.size() >= 1);
        return *frames.at(frames.size() - 1);
    }
};

TEST(SdoClient, ExpeditedDownloadHasTheStandardBytes) {
    CHECK(Status::kOk == sdo.download(0x1017, 0, 100, 2, 0));
    const hal::CanFrame req = lastRequest();
    LONGS_EQUAL(0x605, req.id);
    LONGS_EQUAL(8, req.dlc);
    const std::uint8_t expected[8] = {0x2B, 0x17, 0x10, 0x00, 100, 0, 0, 0};
    MEMCMP_EQUAL(expected, req.data, 8);
    CHECK(Status::kBusy == sdo.upload(0x1000, 0, 0));
    answer({0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    CHECK(SdoResult::kDone == sdo.result());
    LONGS_EQUAL(1, sdo.stats().completed);
}

TEST(SdoClient, ExpeditedUploadsOfEachSize) {
    CHECK(Status::kOk == sdo.upload(0x6061, 0, 0));
    LONGS_EQUAL(0x40, lastRequest().data[0]);
    answer({0x4F, 0x61, 0x60, 0x00, 0x03, 0xAA, 0xAA, 0xAA});  // 1 byte, rest ignored
    CHECK(SdoResult::kDone == sdo.result());
    LONGS_EQUAL(3, sdo.value());
    LONGS_EQUAL(1, sdo.dataLength());
    sdo.clear();
    CHECK(Status::kOk == sdo.upload(0x1000, 0, 0));
    answer({0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00});  // 4 bytes
    LONGS_EQUAL(0x00020192, sdo.value());
}

TEST(SdoClient, SegmentedUploadFollowsTheToggle) {
    CHECK(Status::kOk == sdo.upload(0x1008, 0, 0));
    answer({0x41, 0x08, 0x10, 0x00, 10, 0, 0, 0});  // segmented, 10 bytes announced
    LONGS_EQUAL(0x60, lastRequest().data[0]);      // first segment request, toggle 0
    answer({0x00, 'R', 'S', 'E', '-', 'S', 'I', 'M'});
    LONGS_EQUAL(0x70, lastRequest().data[0]);      // toggle 1
    answer({0x10 | (4 << 1) | 1, ' ', 'W', 'D', 0, 0, 0, 0});  // 3 bytes, last
    CHECK(SdoResult::kDone == sdo.result());
    LONGS_EQUAL(10, sdo.dataLength());
    MEMCMP_EQUAL("RSE-SIM WD", sdo.data(), 10);
}

TEST(SdoClient, WrongToggleAbortsWithItsCodeAndEvent) {
    CHECK(Status::kOk == sdo.upload(0x1008, 0, 0));
    answer({0x41, 0x08, 0x10, 0x00, 20, 0, 0, 0});
    (void)rig.sent();
    answer({0x10, 'x', 'x', 'x', 'x', 'x', 'x', 'x'});  // toggle 1 where 0 was due
    CHECK(SdoResult::kProtocolError == sdo.result());
    const hal::CanFrame abort = lastRequest();
    LONGS_EQUAL(0x80, abort.data[0]);
    LONGS_EQUAL(0x05030000, hal::le::getU32(&abort.data[4]));
    LONGS_EQUAL(1, sdo.stats().protocolErrors);
    LONGS_EQUAL(1, test::drainEventsWithId(rig.events, hal::events::kSdoProtocolError));
}

TEST(SdoClient, ServerAbortKeepsItsCode) {
    CHECK(Status::kOk == sdo.download(0x6060, 0, 9, 1, 0));
    answer({0x80, 0x60, 0x60, 0x00, 0x30, 0x00, 0x09, 0x06});
    CHECK(SdoResult::kAborted == sdo.result());
    LONGS_EQUAL(0x06090030, sdo.abortCode());
    LONGS_EQUAL(1, sdo.stats().abortedByServer);
    LONGS_EQUAL(1, test::drainEventsWithId(rig.events, hal::events::kSdoAborted));
}

TEST(SdoClient, SilenceTimesOutAndTheClientAborts) {
    CHECK(Status::kOk == sdo.upload(0x1000, 0, 0));
    (void)rig.sent();
    sdo.poll(kSdoDefaultTimeout);
    CHECK(SdoResult::kInProgress == sdo.result());
    sdo.poll(kSdoDefaultTimeout + 1);
    CHECK(SdoResult::kTimeout == sdo.result());
    const hal::CanFrame abort = lastRequest();
    LONGS_EQUAL(0x05040000, hal::le::getU32(&abort.data[4]));
    LONGS_EQUAL(1, test::drainEventsWithId(rig.events, hal::events::kSdoTimeout));
    sdo.clear();
    CHECK(Status::kOk == sdo.upload(0x1000, 0, 0));  // usable again
}

TEST(SdoClient, HostileResponsesAreProtocolErrorsOrIgnored) {
    answer({0x60, 0, 0, 0, 0, 0, 0, 0});  // nothing in progress
    LONGS_EQUAL(1, sdo.stats().unexpected);
    CHECK(Status::kOk == sdo.download(0x1017, 0, 100, 2, 0));
    answer({0x60, 0x17, 0x10});  // DLC 3
    CHECK(SdoResult::kProtocolError == sdo.result());
    sdo.clear();
    CHECK(Status::kOk == sdo.download(0x1017, 0, 100, 2, 0));
    answer({0x60, 0x18, 0x10, 0x00, 0, 0, 0, 0});  // answer for another object
    CHECK(SdoResult::kProtocolError == sdo.result());
    sdo.clear();
    CHECK(Status::kOk == sdo.upload(0x1000, 0, 0));
    answer({0x60, 0x00, 0x10, 0x00, 0, 0, 0, 0});  // download answer to an upload
    CHECK(SdoResult::kProtocolError == sdo.result());
    LONGS_EQUAL(3, sdo.stats().protocolErrors);
    CHECK(Status::kInvalidArgument == sdo.download(0x1017, 0, 1, 5, 0));
}

TEST(SdoClient, ANewTransferForgetsTheLastOnesValueAndAbortCode) {
    CHECK(Status::kOk == sdo.upload(0x1000, 0, 0));
    answer({0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00});
    LONGS_EQUAL(0x00020192, sdo.value());
    sdo.clear();
    CHECK(Status::kOk == sdo.download(0x1017, 0, 100, 2, 0));
    LONGS_EQUAL(0, sdo.value());  // a download reads nothing back
    answer({0x80, 0x17, 0x10, 0x00, 0x02, 0x00, 0x01, 0x06});
    LONGS_EQUAL(0x06010002, sdo.abortCode());
    sdo.clear();
    CHECK(Status::kOk == sdo.upload(0x6061, 0, 0));
    LONGS_EQUAL(0, sdo.abortCode());
    sdo.poll(kSdoDefaultTimeout + 1);
    CHECK(SdoResult::kTimeout == sdo.result());
    LONGS_EQUAL(0, sdo.abortCode());
    LONGS_EQUAL(0, sdo.value());
}

TEST(SdoClient, TheTimeoutAndNodeComeFromConfigure) {
    sdo.configure(7, 30 * core::kNsPerMs);
    CHECK(Status::kOk == sdo.upload(0x1000, 0, 0));
    LONGS_EQUAL(0x607, lastRequest().id);
    sdo.poll(30 * core::kNsPerMs);
    CHECK(SdoResult::kInProgress == sdo.result());
    sdo.poll(30 * core::kNsPerMs + 1);
    CHECK(SdoResult::kTimeout == sdo.result());
}

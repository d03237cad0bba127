// CiA 402 drive emulator: SDO server, the ICD's start-up configuration and the
// abort codes (docs/icd.md §1.4).
#include <cstring>

#include "unit_test/sim_stub/drives/drive_test_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using rse::test::DriveRig;
using rse::test::kNode;

namespace {

void checkBytes(const std::uint8_t (&expected)[8], const hal::CanFrame& f) {
    LONGS_EQUAL(0x580 + kNode, f.id);
    LONGS_EQUAL(8, f.dlc);
    for (int i = 0; i < 8; ++i) {
        LONGS_EQUAL(expected[i], f.data[i]);
    }
}

}  // namespace

TEST_GROUP(DriveSdo) {
    DriveRig rig;
    hal::CanFrame r;
    void setup() override {
        rig.boot();
        rig.advance(test::kCycle);  // past "not ready to switch on"
    }

    std::uint32_t abortOf(const std::uint8_t (&request)[8]) {
        CHECK(rig.sdo(request, &r));
        return DriveRig::abortCode(r);
    }
};

TEST(DriveSdo, IcdStartUpConfigurationStepByStep) {
    // 1: upload 0x1000 -> expedited, 4 bytes: 43 00 10 00 | 92 01 02 00 (CiA 402 servo drive).
    CHECK(rig.sdoUpload(0x1000, 0, &r));
    checkBytes({0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00}, r);

    // 2: download 0x1017 = 100 (u16) -> 60 17 10 00 00 00 00 00.
    CHECK(rig.sdoDownload(0x1017, 0, 100, 2, &r));
    checkBytes({0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0}, r);
    LONGS_EQUAL(100, rig.drive.heartbeatPeriodMs());

    // 3: download 0x6060 = 3 (i8) -> 60 60 60 00 ...
    CHECK(rig.sdoDownload(0x6060, 0, 3, 1, &r));
    checkBytes({0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0}, r);

    // 4: upload 0x6061 -> 4F 61 60 00 03 (1 byte).
    CHECK(rig.sdoUpload(0x6061, 0, &r));
    checkBytes({0x4F, 0x61, 0x60, 0x00, 0x03, 0, 0, 0}, r);

    // 5, 6, 7: the PDO mapping and transmission type.
    LONGS_EQUAL(2, rig.uploadValue(0x1600, 0));
    LONGS_EQUAL(0x60400010, rig.uploadValue(0x1600, 1));
    LONGS_EQUAL(0x60FF0020, rig.uploadValue(0x1600, 2));
    CHECK(rig.sdoUpload(0x1A00, 0, &r));
    checkBytes({0x4F, 0x00, 0x1A, 0x00, 0x03, 0, 0, 0}, r);
    LONGS_EQUAL(0x60410010, rig.uploadValue(0x1A00, 1));
    LONGS_EQUAL(0x606C0020, rig.uploadValue(0x1A00, 2));
    CHECK(rig.sdoUpload(0x1A00, 3, &r));
    checkBytes({0x43, 0x00, 0x1A, 0x03, 0x10, 0x00, 0x78, 0x60}, r);
    LONGS_EQUAL(1, rig.uploadValue(0x1800, 2));

    // The other objects the master may read.
    LONGS_EQUAL(0, rig.uploadValue(0x1001, 0));
    LONGS_EQUAL(0x0240, rig.uploadValue(0x6041, 0));  // switch on disabled, remote
    LONGS_EQUAL(0, rig.uploadValue(0x606C, 0));
    LONGS_EQUAL(0, rig.uploadValue(0x6078, 0));
    LONGS_EQUAL(0x185, rig.uploadValue(0x1800, 1));
    CHECK(rig.sdoUpload(0x6041, 0, &r));
    LONGS_EQUAL(0x4B, r.data[0]);  // 2 bytes
    LONGS_EQUAL(18, rig.drive.sdoStats().responses);  // every request above answered, no abort
    LONGS_EQUAL(0, rig.drive.sdoStats().abortsSent);
}

TEST(DriveSdo, ControlwordAndTargetVelocityAreWritableBySdo) {
    CHECK(rig.sdoDownload(0x60FF, 0, static_cast<std::uint32_t>(-1234), 4, &r));
    LONGS_EQUAL(0x60, r.data[0]);
    LONGS_EQUAL(static_cast<std::uint32_t>(-1234), rig.uploadValue(0x60FF, 0));
    CHECK(rig.sdoDownload(0x6040, 0, 0x0006, 2, &r));
    LONGS_EQUAL(0x60, r.data[0]);
    CHECK(sim::PowerState::kReadyToSwitchOn == rig.drive.powerState());
    LONGS_EQUAL(0x0006, rig.uploadValue(0x6040, 0));
    LONGS_EQUAL(0x0221, rig.uploadValue(0x6041, 0));
}

TEST(DriveSdo, DeviceNameBySegmentedUploadWithToggle) {
    CHECK(rig.sdoUpload(0x1008, 0, &r));
    // Segmented (e = 0), size indicated (s = 1): 41 08 10 00 | 19 bytes.
    checkBytes({0x41, 0x08, 0x10, 0x00, 19, 0, 0, 0}, r);
    char name[32] = {};
    std::size_t length = 0;
    std::uint8_t toggle = 0;
    bool last = false;
    for (int segment = 0; segment < 10 && !last; ++segment) {
        const std::uint8_t request[8] = {static_cast<std::uint8_t>(0x60 | toggle), 0, 0, 0, 0, 0, 0, 0};
        CHECK(rig.sdo(request, &r));
        LONGS_EQUAL(toggle, r.data[0] & 0x10);  // the answer carries the same toggle
        LONGS_EQUAL(0, r.data[0] & 0xE0);       // scs 0: upload segment
        const std::size_t n = 7U - ((r.data[0] >> 1) & 0x07U);
        std::memcpy(&name[length], &r.data[1], n);
        length += n;
        last = (r.data[0] & 0x01) != 0;
        toggle ^= 0x10;
    }
    CHECK(last);
    LONGS_EQUAL(19, length);
    STRCMP_EQUAL("RSE-SIM wheel drive", name);
    // Three segments: 7 + 7 + 5 bytes; the last is 0x05 (toggle 0, n = 2, c = 1).
    LONGS_EQUAL(0x05, r.data[0]);
    LONGS_EQUAL(0, r.data[6]);
    // The transfer is over: another segment request is a protocol error.
    const std::uint8_t again[8] = {0x60, 0, 0, 0, 0, 0, 0, 0};
    LONGS_EQUAL(0x05040001, abortOf(again));
}

TEST(DriveSdo, WrongToggleAbortsTheSegmentedUpload) {
    CHECK(rig.sdoUpload(0x1008, 0, &r));
    const std::uint8_t first[8] = {0x60, 0, 0, 0, 0, 0, 0, 0};
    CHECK(rig.sdo(first, &r));
    LONGS_EQUAL(0x00, r.data[0]);
    // The second request must carry toggle 1; it repeats toggle 0.
    CHECK(rig.sdo(first, &r));
    checkBytes({0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x03, 0x05}, r);  // abort 0x05030000 for 0x1008:00
    CHECK_FALSE(rig.drive.sdoStats().abortsSent == 0);
    // The server is idle again and answers the next transfer.
    LONGS_EQUAL(0x00020192, rig.uploadValue(0x1000, 0));
}

TEST(DriveSdo, AbortCodesForBadRequests) {
    const std::uint8_t noObject[8] = {0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0};  // upload 0x2000
    CHECK(rig.sdo(noObject, &r));
    checkBytes({0x80, 0x00, 0x20, 0x00, 0x00, 0x00, 0x02, 0x06}, r);
    LONGS_EQUAL(0x06020000, DriveRig::abortCode(r));

    const std::uint8_t noSub[8] = {0x40, 0x17, 0x10, 0x01, 0, 0, 0, 0};  // upload 0x1017:01
    LONGS_EQUAL(0x06090011, abortOf(noSub));
    const std::uint8_t noMapping3[8] = {0x40, 0x00, 0x16, 0x03, 0, 0, 0, 0};  // 0x1600:03
    LONGS_EQUAL(0x06090011, abortOf(noMapping3));

    const std::uint8_t readOnly[8] = {0x23, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00};  // write 0x1000
    LONGS_EQUAL(0x06010002, abortOf(readOnly));
    const std::uint8_t mapping[8] = {0x2F, 0x00, 0x16, 0x00, 0x00, 0, 0, 0};  // write 0x1600:00 (static)
    LONGS_EQUAL(0x06010002, abortOf(mapping));
    const std::uint8_t name[8] = {0x23, 0x08, 0x10, 0x00, 'R', 'S', 'E', '!'};
    LONGS_EQUAL(0x06010002, abortOf(name));

    const std::uint8_t heartbeatOneByte[8] = {0x2F, 0x17, 0x10, 0x00, 100, 0, 0, 0};  // 0x1017 is u16
    LONGS_EQUAL(0x06070010, abortOf(heartbeatOneByte));
    const std::uint8_t modeFourBytes[8] = {0x23, 0x60, 0x60, 0x00, 3, 0, 0, 0};  // 0x6060 is i8
    LONGS_EQUAL(0x06070010, abortOf(modeFourBytes));
    LONGS_EQUAL(0, rig.drive.modeOfOperation());

    const std::uint8_t modeOne[8] = {0x2F, 0x60, 0x60, 0x00, 1, 0, 0, 0};  // profile position: unsupported
    LONGS_EQUAL(0x06090030, abortOf(modeOne));
    const std::uint8_t typeEventDriven[8] = {0x2F, 0x00, 0x18, 0x02, 0xFF, 0, 0, 0};
    LONGS_EQUAL(0x06090030, abortOf(typeEventDriven));

    const std::uint8_t ccs7[8] = {0xE0, 0x00, 0x10, 0x00, 0, 0, 0, 0};
    LONGS_EQUAL(0x05040001, abortOf(ccs7));
    const std::uint8_t blockUpload[8] = {0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0};
    LONGS_EQUAL(0x05040001, abortOf(blockUpload));
    LONGS_EQUAL(0x08, r.data[1]);  // the abort names the object the request named
    const std::uint8_t segmentWithoutTransfer[8] = {0x00, 1, 2, 3, 4, 5, 6, 7};
    LONGS_EQUAL(0x05040001, abortOf(segmentWithoutTransfer));

    LONGS_EQUAL(13, rig.drive.sdoStats().abortsSent);
    LONGS_EQUAL(0x05040001, rig.drive.lastSdoAbortCode());
    // Nothing was harmed: the server still works.
    LONGS_EQUAL(0x00020192, rig.uploadValue(0x1000, 0));
}

TEST(DriveSdo, ExpeditedDownloadWithoutSizeTakesTheObjectSize) {
    const std::uint8_t noSize[8] = {0x22, 0x17, 0x10, 0x00, 50, 0, 0xAA, 0xBB};  // e = 1, s = 0
    CHECK(rig.sdo(noSize, &r));
    LONGS_EQUAL(0x60, r.data[0]);
    LONGS_EQUAL(50, rig.drive.heartbeatPeriodMs());
}

TEST(DriveSdo, SegmentedDownloadWithToggle) {
    // Target velocity 0x60FF = 0x00012345 sent as one segment of 4 bytes.
    const std::uint8_t initiate[8] = {0x21, 0xFF, 0x60, 0x00, 4, 0, 0, 0};
    CHECK(rig.sdo(initiate, &r));
    checkBytes({0x60, 0xFF, 0x60, 0x00, 0, 0, 0, 0}, r);
    const std::uint8_t segment[8] = {static_cast<std::uint8_t>(0x00 | (3 << 1) | 0x01), 0x45, 0x23, 0x01, 0x00, 0, 0, 0};
    CHECK(rig.sdo(segment, &r));
    checkBytes({0x20, 0, 0, 0, 0, 0, 0, 0}, r);
    LONGS_EQUAL(0x12345, rig.drive.targetVelocityMradS());

    // Wrong toggle on a download segment.
    CHECK(rig.sdo(initiate, &r));
    const std::uint8_t toggled[8] = {static_cast<std::uint8_t>(0x10 | (3 << 1) | 0x01), 1, 0, 0, 0, 0, 0, 0};
    LONGS_EQUAL(0x05030000, abortOf(toggled));
    LONGS_EQUAL(0x12345, rig.drive.targetVelocityMradS());

    // Announced size different from the object's.
    const std::uint8_t wrongSize[8] = {0x21, 0xFF, 0x60, 0x00, 6, 0, 0, 0};
    LONGS_EQUAL(0x06070010, abortOf(wrongSize));
}

TEST(DriveSdo, ClientAbortAndServerTimeoutEndATransfer) {
    CHECK(rig.sdoUpload(0x1008, 0, &r));
    const std::uint8_t clientAbort[8] = {0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x04, 0x05};
    rig.send(0x600 + kNode, 8, clientAbort);
    rig.step();
    CHECK_FALSE(rig.receive(&r));  // no answer to an abort
    LONGS_EQUAL(1, rig.drive.sdoStats().abortsReceived);
    LONGS_EQUAL(0, rig.drive.sdoStats().abortsSent);

    // A client that goes quiet in mid-transfer: the server gives up after 1 s.
    CHECK(rig.sdoUpload(0x1008, 0, &r));
    rig.idle(900 * core::kNsPerMs);
    CHECK_FALSE(rig.receiveId(0x585, &r));
    rig.idle(200 * core::kNsPerMs);
    CHECK(rig.receiveId(0x585, &r));
    LONGS_EQUAL(0x05040000, DriveRig::abortCode(r));
    LONGS_EQUAL(1, rig.drive.sdoStats().timeouts);
}

TEST(DriveSdo, MalformedRequestsAreIgnoredAndCounted) {
    const std::uint8_t upload[8] = {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0};
    rig.send(0x600 + kNode, 4, upload);
    rig.send(0x600 + kNode, 0, upload);
    rig.step();
    CHECK_FALSE(rig.receive(&r));
    LONGS_EQUAL(2, rig.drive.sdoStats().malformed);
    // Requests to another node are not ours (filtered by the controller).
    rig.send(0x606, 8, upload);
    rig.step();
    CHECK_FALSE(rig.receive(&r));
    LONGS_EQUAL(0x00020192, rig.uploadValue(0x1000, 0));
}

TEST(DriveSdo, WorksInOperationalToo) {
    rig.nmt(0x01, kNode);
    rig.step();
    CHECK(sim::NmtState::kOperational == rig.drive.nmtState());
    LONGS_EQUAL(0x00020192, rig.uploadValue(0x1000, 0));
    CHECK(rig.sdoDownload(0x1800, 2, 2, 1, &r));
    LONGS_EQUAL(0x60, r.data[0]);
    LONGS_EQUAL(2, rig.drive.tpdoTransmissionType());
}

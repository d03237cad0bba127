// The CAN-ID plan (docs/icd.md §1.2): the ISO-TP ground link's ids lie outside
// every CiA 301 restricted range (issue 14 item 7: 0x6F0/0x6F1 were in
// 0x6E0-0x6FF, which an independent CANopen stack flags) and collide with no id
// a CANopen node of any node id or an RSE device uses. The range list lives in
// one header (hal/canopen/canopen_ids.hpp) and is written out in docs/icd.md.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "fsw/io/can_ground_link.hpp"
#include "ground/ground_link.hpp"
#include "hal/can/ground_link_ids.hpp"
#include "hal/canopen/canopen_ids.hpp"
#include "hal/devices/instrument_protocol.hpp"
#include "hal/devices/rse_device_ids.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal::canopen;

TEST_GROUP(CanIdPlan){};

TEST(CanIdPlan, RestrictedRangesAreCia301s) {
    const std::uint32_t restricted[] = {0x000, 0x001, 0x07F, 0x101, 0x17F, 0x180, 0x581, 0x5FF, 0x601,
                                        0x67F, 0x6E0, 0x6F0, 0x6F1, 0x6FF, 0x701, 0x77F, 0x780, 0x7E4, 0x7FF};
    for (const std::uint32_t id : restricted) {
        CHECK_TEXT(isCia301Restricted(id), std::to_string(id).c_str());
    }
    const std::uint32_t free[] = {0x080, 0x081, 0x0FF, 0x100, 0x181, 0x4FF, 0x500, 0x57F, 0x580,
                                  0x600, 0x680, 0x6A0, 0x6C0, 0x6DF, 0x700};
    for (const std::uint32_t id : free) {
        CHECK_TEXT(!isCia301Restricted(id), std::to_string(id).c_str());
    }
}

TEST(CanIdPlan, GroundLinkIdsAreOutsideEveryRestrictedRange) {
    const std::uint32_t ids[] = {hal::kGroundUplinkCanId, hal::kGroundDownlinkCanId, io::kGroundUplinkCobId,
                                 io::kGroundDownlinkCobId, ground::kGroundIsoTpTxId, ground::kGroundIsoTpRxId};
    for (const std::uint32_t id : ids) {
        CHECK_TEXT(id <= 0x7FF, std::to_string(id).c_str());
        for (const CanIdRange& r : kCia301RestrictedIds) {
            CHECK_TEXT(id < r.first || id > r.last, std::to_string(id).c_str());
        }
    }
    // Rover and ground agree: the ground sends where the rover listens.
    LONGS_EQUAL(io::kGroundUplinkCobId, ground::kGroundIsoTpTxId);
    LONGS_EQUAL(io::kGroundDownlinkCobId, ground::kGroundIsoTpRxId);
    CHECK(hal::kGroundUplinkCanId != hal::kGroundDownlinkCanId);
}

TEST(CanIdPlan, GroundLinkIdsCollideWithNoNodeOrDeviceId) {
    // Every predefined-connection-set object of every node id 1..127.
    const std::uint32_t functions[] = {kEmcy,  kTpdo1, kRpdo1, kTpdo2, 0x300,       0x380,       0x400,
                                       0x480, 0x500,  kSdoResponse, kSdoRequest, kHeartbeat};
    const std::uint32_t device[] = {hal::device_ids::kImuRates, hal::device_ids::kPower, hal::device_ids::kHazard,
                                    hal::device_ids::kFixX, hal::device_ids::kFixY};
    for (const std::uint32_t id : {hal::kGroundUplinkCanId, hal::kGroundDownlinkCanId}) {
        CHECK(id != kNmt && id != kSync);
        for (const std::uint32_t f : functions) {
            for (std::uint32_t node = 1; node <= kMaxNodeId; ++node) {
                CHECK_TEXT(id != f + node, std::to_string(f + node).c_str());
            }
        }
        for (const std::uint32_t d : device) {
            CHECK(id != d);
        }
    }
}

// docs/icd.md lists the restricted ranges (the same list as the header) and the ids.
TEST(CanIdPlan, IcdListsTheRestrictedRangesAndTheGroundLinkIds) {
    std::ifstream in("docs/icd.md");
    CHECK_TEXT(in.good(), "docs/icd.md (tests run from the repository root)");
    std::stringstream text;
    text << in.rdbuf();
    const std::string icd = text.str();
    for (const CanIdRange& r : kCia301RestrictedIds) {
        char entry[32];
        if (r.first == r.last) {
            std::snprintf(entry, sizeof entry, "| 0x%03X |", static_cast<unsigned>(r.first));
        } else {
            std::snprintf(entry, sizeof entry, "| 0x%03X–0x%03X |", static_cast<unsigned>(r.first),
                          static_cast<unsigned>(r.last));
        }
        CHECK_TEXT(icd.find(entry) != std::string::npos, entry);
    }
    CHECK(icd.find("| 0x6C0 | ground→rover") != std::string::npos);
    CHECK(icd.find("| 0x6C1 | rover→ground") != std::string::npos);
}

// The science instruments' ids (docs/icd.md §1.7): outside every restricted
// range, no predefined-connection-set id of any node, no other device's or the
// ground link's, distinct; their node ids after the sensors'; all in the ICD.
TEST(CanIdPlan, InstrumentIdsAreFreeDistinctAndInTheIcd) {
    namespace ids = hal::device_ids;
    const std::uint32_t instruments[] = {ids::kGrinderStatus, ids::kCameraStatus, ids::kGrinderCommand,
                                         ids::kCameraCommand};
    const std::uint32_t others[] = {ids::kImuRates, ids::kPower,          ids::kHazard,
                                    ids::kFixX,     ids::kFixY,           hal::kGroundUplinkCanId,
                                    hal::kGroundDownlinkCanId};
    const std::uint32_t functions[] = {kEmcy,  kTpdo1, kRpdo1, kTpdo2, 0x300,       0x380,       0x400,
                                       0x480, 0x500,  kSdoResponse, kSdoRequest, kHeartbeat};
    for (std::size_t i = 0; i < sizeof instruments / sizeof instruments[0]; ++i) {
        const std::uint32_t id = instruments[i];
        CHECK_TEXT(!isCia301Restricted(id), std::to_string(id).c_str());
        CHECK(id != kNmt && id != kSync);
        for (const std::uint32_t f : functions) {
            for (std::uint32_t node = 1; node <= kMaxNodeId; ++node) {
                CHECK_TEXT(id != f + node, std::to_string(f + node).c_str());
            }
        }
        for (const std::uint32_t o : others) {
            CHECK(id != o);
        }
        for (std::size_t j = 0; j < i; ++j) {
            CHECK(id != instruments[j]);
        }
    }
    CHECK(hal::instrument::kGrinderNodeId == 0x24 && hal::instrument::kCameraNodeId == 0x25);
    std::ifstream in("docs/icd.md");
    std::stringstream text;
    text << in.rdbuf();
    const std::string icd = text.str();
    for (const char* entry : {"| 0x6A5 | grinder→M", "| 0x6A6 | camera→M", "| 0x6B5 | M→grinder", "| 0x6B6 | M→camera",
                              "| 0x24 | grinder/sampler", "| 0x25 | camera"}) {
        CHECK_TEXT(icd.find(entry) != std::string::npos, entry);
    }
}

// The flight table service: start-up, load / validate / activate at a frame
// boundary / dump, and that nothing a bad image does reaches the active tables.
#include <cstring>
#include <string>
#include <vector>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_events.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/support/alloc_guard.hpp"
#include "unit_test/support/event_probe.hpp"
#include "unit_test/fsw/tables/table_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::tables;
using rse::core::EventLog;
using rse::core::FrameContext;
using rse::core::Status;
using rse::core::VirtualClock;
using rse::test::defaultImage;
using rse::test::drainEvents;
using rse::test::drainEventsWithId;

namespace {

RoverGeometryTable geometryFrom(const std::vector<std::uint8_t>& image) {
    RoverGeometryTable t{};
    CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
    return t;
}

std::vector<std::uint8_t> geometryImage(const RoverGeometryTable& t, std::uint32_t version) {
    std::vector<std::uint8_t> image(kMaxTableImageSize);
    image.resize(encodeTable(t, version, image.data(), image.size()));
    return image;
}

}  // namespace

TEST_GROUP(TableService) {
    VirtualClock clock{0};
    EventLog events{clock};
    TableService service{events};
    FrameContext frame{};
    std::vector<std::uint8_t> defaultGeometry;
    std::vector<std::uint8_t> faster;  // a good ROVER_GEOMETRY image, version 2, max wheel speed 4

    void setup() override {
        CHECK_TRUE(Status::kOk == service.init(kDefaultTableImages, kDefaultTableImageCount));
        (void)drainEventsWithId(events, 0);
        defaultGeometry = defaultImage(TableId::kRoverGeometry);
        RoverGeometryTable t = geometryFrom(defaultGeometry);
        t.max_wheel_speed_rad_s = 4.0F;
        faster = geometryImage(t, 2);
    }

    // Loads an image in chunks of `chunk` bytes.
    TableCheck load(TableId id, const std::vector<std::uint8_t>& image, std::size_t chunk = 7) {
        TableCheck last;
        for (std::size_t at = 0; at < image.size() && last.ok(); at += chunk) {
            const std::size_t n = image.size() - at < chunk ? image.size() - at : chunk;
            last = service.loadChunk(id, static_cast<std::uint32_t>(at), image.data() + at, n);
        }
        return last;
    }

    // Loads, validates and activates; returns the validation verdict.
    TableCheck upload(TableId id, const std::vector<std::uint8_t>& image) {
        const TableCheck loaded = load(id, image);
        if (!loaded.ok()) {
            return loaded;
        }
        const TableCheck valid = service.validate(id);
        if (!valid.ok()) {
            return valid;
        }
        return service.activate(id);
    }

    void checkGeometryUnchanged() {
        CHECK_EQUAL(5.0F, service.roverGeometry().max_wheel_speed_rad_s);
        LONGS_EQUAL(1, service.status(TableId::kRoverGeometry).activeVersion);
        std::uint8_t out[kMaxTableImageSize];
        std::size_t length = 0;
        CHECK_TRUE(service.dump(TableId::kRoverGeometry, false, out, sizeof out, &length).ok());
        CHECK_TRUE(std::vector<std::uint8_t>(out, out + length) == defaultGeometry);
    }
};

TEST(TableService, StartUpActivatesEveryDefaultTable) {
    std::size_t count = 0;
    const TableDesc* descs = tableDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        const TableStatus s = service.status(descs[i].id);
        CHECK_TEXT(s.active, descs[i].name);
        LONGS_EQUAL(1, s.activeVersion);
        LONGS_EQUAL(1, s.activations);
        CHECK_TRUE(TableBufferState::kEmpty == s.inactiveState);
    }
    LONGS_EQUAL(kTableCount, service.activations());
    LONGS_EQUAL(0, service.rejects());
    CHECK_EQUAL(5.0F, service.roverGeometry().max_wheel_speed_rad_s);
    LONGS_EQUAL(1, service.canNodeMap().drive_node_id[0]);
    LONGS_EQUAL(6, service.canNodeMap().drive_node_id[5]);
    LONGS_EQUAL(250, service.canNodeMap().heartbeat_timeout_ms);
    DOUBLES_EQUAL(1e-3, service.planner().default_risk_bound, 0.0);
    LONGS_EQUAL(3, service.faultResponse().sdo_retries);
    CHECK(service.estimatorNoise().pose_clear_sigma_m < service.estimatorNoise().pose_fault_sigma_m);
    CHECK(service.habitual().rrt_iterations > 0);
}

TEST(TableService, StartUpEventsEachTable) {
    VirtualClock c{0};
    EventLog log{c};
    TableService fresh{log};
    CHECK_TRUE(Status::kOk == fresh.init(kDefaultTableImages, kDefaultTableImageCount));
    LONGS_EQUAL(kTableCount, drainEventsWithId(log, events::kTableStartupActive));
}

TEST(TableService, StartUpFailsNamingAMissingTable) {
    VirtualClock c{0};
    EventLog log{c};
    TableService fresh{log};
    CHECK_TRUE(Status::kInvalidArgument == fresh.init(kDefaultTableImages, kDefaultTableImageCount - 1));
    const auto d = drainEvents(log, events::kTableMissing);
    LONGS_EQUAL(1, d.count);
    CHECK_TRUE(d.text.find("FAULT_PROTECTION") != std::string::npos);
    CHECK_FALSE(fresh.status(TableId::kFaultProtection).active);
    CHECK_TRUE(fresh.status(TableId::kRoverGeometry).active);
}

TEST(TableService, StartUpRejectsABadImageNamingTheTableAndKeepsWhatWasActive) {
    std::vector<std::uint8_t> bad = faster;
    bad[bad.size() - 1] ^= 0x10;
    TableImageRef refs[kTableCount];
    for (std::size_t i = 0; i < kTableCount; ++i) {
        refs[i] = kDefaultTableImages[i];
    }
    refs[0] = {bad.data(), bad.size()};  // ROVER_GEOMETRY is first (id order)
    CHECK_TRUE(Status::kInvalidArgument == service.init(refs, kTableCount));
    const auto d = drainEvents(events, events::kRejectBadCrc);
    LONGS_EQUAL(1, d.count);
    CHECK_TRUE(d.text.find("ROVER_GEOMETRY") != std::string::npos);
    checkGeometryUnchanged();

    // Into a fresh service the same list fails and leaves that table inactive.
    VirtualClock c{0};
    EventLog log{c};
    TableService fresh{log};
    CHECK_TRUE(Status::kInvalidArgument == fresh.init(refs, kTableCount));
    CHECK_FALSE(fresh.status(TableId::kRoverGeometry).active);
    LONGS_EQUAL(1, drainEventsWithId(log, events::kTableMissing));
}

TEST(TableService, StartUpRefusesDuplicatesAndBadLists) {
    VirtualClock c{0};
    EventLog log{c};
    TableService fresh{log};
    const TableImageRef twice[] = {kDefaultTableImages[0], kDefaultTableImages[0]};
    CHECK_TRUE(Status::kInvalidArgument == fresh.init(twice, 2));
    auto d = drainEvents(log, events::kTableDuplicate);
    LONGS_EQUAL(1, d.count);
    CHECK_TRUE(d.text.find("ROVER_GEOMETRY") != std::string::npos);
    CHECK_TRUE(Status::kInvalidArgument == fresh.init(nullptr, 3));
    LONGS_EQUAL(1, drainEventsWithId(log, events::kTableStartupInvalid));
    const std::uint8_t junk[4] = {1, 2, 3, 4};
    const TableImageRef junkRef[] = {{junk, sizeof junk}};
    CHECK_TRUE(Status::kInvalidArgument == fresh.init(junkRef, 1));
    LONGS_EQUAL(1, drainEventsWithId(log, events::kRejectTooShort));
}

TEST(TableService, AGoodImageTakesEffectOnlyAtTheFrameBoundary) {
    CHECK_TRUE(load(TableId::kRoverGeometry, faster).ok());
    CHECK_TRUE(TableBufferState::kLoaded == service.status(TableId::kRoverGeometry).inactiveState);
    LONGS_EQUAL(faster.size(), service.status(TableId::kRoverGeometry).inactiveLength);
    CHECK_TRUE(service.validate(TableId::kRoverGeometry).ok());
    CHECK_TRUE(TableBufferState::kValidated == service.status(TableId::kRoverGeometry).inactiveState);
    CHECK_TRUE(service.activate(TableId::kRoverGeometry).ok());
    CHECK_TRUE(TableBufferState::kPending == service.status(TableId::kRoverGeometry).inactiveState);
    // Activated but the frame has not ended: the rest of this frame still sees the old table.
    CHECK_EQUAL(5.0F, service.roverGeometry().max_wheel_speed_rad_s);
    LONGS_EQUAL(1, service.status(TableId::kRoverGeometry).activeVersion);
    LONGS_EQUAL(0, drainEventsWithId(events, events::kTableActivated));

    service.run(frame);  // first task of the next frame

    CHECK_EQUAL(4.0F, service.roverGeometry().max_wheel_speed_rad_s);
    const TableStatus s = service.status(TableId::kRoverGeometry);
    LONGS_EQUAL(2, s.activeVersion);
    LONGS_EQUAL(2, s.activations);
    CHECK_TRUE(TableBufferState::kEmpty == s.inactiveState);
    TableHeader header;
    CHECK_TRUE(readTableHeader(faster.data(), faster.size(), &header));
    LONGS_EQUAL(header.crc, s.activeCrc);
    LONGS_EQUAL(kTableCount + 1, service.activations());
    LONGS_EQUAL(0, service.rejects());
    const auto d = drainEvents(events, events::kTableActivated);
    LONGS_EQUAL(1, d.count);
    CHECK_TRUE(d.text.find("ROVER_GEOMETRY") != std::string::npos);
    CHECK_TRUE(d.text.find("1 -> 2") != std::string::npos);
    char crc[16];
    std::snprintf(crc, sizeof crc, "0x%08X", static_cast<unsigned>(header.crc));
    CHECK_TRUE(d.text.find(crc) != std::string::npos);
    // Nothing left to apply: a second run changes nothing.
    service.run(frame);
    LONGS_EQUAL(0, drainEventsWithId(events, events::kTableActivated));
    LONGS_EQUAL(2, service.status(TableId::kRoverGeometry).activations);
}

TEST(TableService, ANodeMapActivationSaysItAppliesAtTheNextStart) {
    std::vector<std::uint8_t> image = defaultImage(TableId::kCanNodeMap);
    CHECK_TRUE(upload(TableId::kCanNodeMap, image).ok());
    service.run(frame);
    const auto d = drainEvents(events, events::kTableActivated);
    LONGS_EQUAL(1, d.count);
    CHECK_TRUE(d.text.find("next start") != std::string::npos);
}

TEST(TableService, AFlippedByteAnywhereIsRejectedAndTheActiveTableStays) {
    for (std::size_t i = 0; i < faster.size(); ++i) {
        std::vector<std::uint8_t> bad = faster;
        bad[i] ^= 0x04;
        CHECK_TRUE(load(TableId::kRoverGeometry, bad).ok());
        const TableCheck check = service.validate(TableId::kRoverGeometry);
        CHECK_FALSE(check.ok());
        CHECK_TRUE(TableReject::kNotValidated == service.activate(TableId::kRoverGeometry).reason);
        service.run(frame);
        checkGeometryUnchanged();
    }
    LONGS_EQUAL(2 * faster.size(), service.rejects());
    LONGS_EQUAL(kTableCount, service.activations());
}

TEST(TableService, OutOfRangeIsRejectedNamingTheFieldAndTheActiveTableStays) {
    RoverGeometryTable t = geometryFrom(defaultGeometry);
    t.max_wheel_speed_rad_s = 25.0F;
    const std::vector<std::uint8_t> bad = geometryImage(t, 3);
    CHECK_TRUE(load(TableId::kRoverGeometry, bad).ok());
    const TableCheck check = service.validate(TableId::kRoverGeometry);
    CHECK_TRUE(TableReject::kOutOfRange == check.reason);
    LONGS_EQUAL(RoverGeometryField::max_wheel_speed_rad_s, check.field);
    const auto d = drainEvents(events, events::kRejectOutOfRange);
    LONGS_EQUAL(1, d.count);
    CHECK_TRUE(d.text.find("ROVER_GEOMETRY") != std::string::npos);
    CHECK_TRUE(d.text.find("max_wheel_speed_rad_s") != std::string::npos);
    CHECK_TRUE(d.text.find("out of range") != std::string::npos);
    LONGS_EQUAL(1, service.rejects());
    LONGS_EQUAL(1, service.status(TableId::kRoverGeometry).rejects);
    CHECK_TRUE(TableReject::kOutOfRange == service.status(TableId::kRoverGeometry).lastReject);
    service.run(frame);
    checkGeometryUnchanged();
}

TEST(TableService, ArrayElementFaultsNameTheElement) {
    CanNodeMapTable map = service.canNodeMap();
    map.drive_node_id[4] = 200;
    std::vector<std::uint8_t> image(kMaxTableImageSize);
    image.resize(encodeTable(map, 5, image.data(), image.size()));
    CHECK_TRUE(load(TableId::kCanNodeMap, image).ok());
    CHECK_TRUE(TableReject::kOutOfRange == service.validate(TableId::kCanNodeMap).reason);
    const auto d = drainEvents(events, events::kRejectOutOfRange);
    CHECK_TRUE(d.text.find("drive_node_id[4]") != std::string::npos);
    LONGS_EQUAL(5, service.canNodeMap().drive_node_id[4]);
}

TEST(TableService, InconsistentPairIsRejectedNamingBothFields) {
    EstimatorNoiseTable noise = service.estimatorNoise();
    noise.pose_clear_sigma_m = noise.pose_fault_sigma_m + 1.0F;
    std::vector<std::uint8_t> image(kMaxTableImageSize);
    image.resize(encodeTable(noise, 2, image.data(), image.size()));
    CHECK_TRUE(load(TableId::kEstimatorNoise, image).ok());
    CHECK_TRUE(TableReject::kInconsistent == service.validate(TableId::kEstimatorNoise).reason);
    const auto d = drainEvents(events, events::kRejectInconsistent);
    CHECK_TRUE(d.text.find("pose_clear_sigma_m") != std::string::npos);
    CHECK_TRUE(d.text.find("pose_fault_sigma_m") != std::string::npos);
}

TEST(TableService, NotFiniteIsRejected) {
    RoverGeometryTable t = geometryFrom(defaultGeometry);
    std::uint32_t nanBits = 0x7FC00000U;
    std::memcpy(&t.wheel_radius_m, &nanBits, sizeof nanBits);
    CHECK_TRUE(load(TableId::kRoverGeometry, geometryImage(t, 4)).ok());
    CHECK_TRUE(TableReject::kNotFinite == service.validate(TableId::kRoverGeometry).reason);
    LONGS_EQUAL(1, drainEventsWithId(events, events::kRejectNotFinite));
    checkGeometryUnchanged();
}

TEST(TableService, WrongLengthsAreRejectedAndTheActiveTableStays) {
    // Truncated.
    std::vector<std::uint8_t> bad(faster.begin(), faster.end() - 1);
    CHECK_TRUE(load(TableId::kRoverGeometry, bad).ok());
    CHECK_TRUE(TableBufferState::kLoading == service.status(TableId::kRoverGeometry).inactiveState);
    CHECK_TRUE(TableReject::kBadLength == service.validate(TableId::kRoverGeometry).reason);
    LONGS_EQUAL(1, drainEventsWithId(events, events::kRejectBadLength));
    // Extended: COARSE_MAP is the largest table, so its buffer refuses the
    // extra byte; a smaller table's buffer takes it and validation refuses it.
    bad = defaultImage(TableId::kCoarseMap);
    LONGS_EQUAL(kMaxTableImageSize, bad.size());
    bad.push_back(0xAA);
    CHECK_TRUE(TableReject::kTooLarge == load(TableId::kCoarseMap, bad).reason);
    LONGS_EQUAL(1, drainEventsWithId(events, events::kRejectTooLarge));
    std::vector<std::uint8_t> longMap = defaultImage(TableId::kCanNodeMap);
    longMap.push_back(0xAA);
    CHECK_TRUE(load(TableId::kCanNodeMap, longMap).ok());
    CHECK_TRUE(TableReject::kBadLength == service.validate(TableId::kCanNodeMap).reason);
    LONGS_EQUAL(1, drainEventsWithId(events, events::kRejectBadLength));
    // Header only, and less than a header.
    bad.assign(faster.begin(), faster.begin() + kTableHeaderSize);
    CHECK_TRUE(load(TableId::kRoverGeometry, bad).ok());
    CHECK_TRUE(TableReject::kBadLength == service.validate(TableId::kRoverGeometry).reason);
    LONGS_EQUAL(1, drainEventsWithId(events, events::kRejectBadLength));
    bad.assign(faster.begin(), faster.begin() + 5);
    CHECK_TRUE(load(TableId::kRoverGeometry, bad).ok());
    CHECK_TRUE(TableReject::kTooShort == service.validate(TableId::kRoverGeometry).reason);
    LONGS_EQUAL(1, drainEventsWithId(events, events::kRejectTooShort));
    LONGS_EQUAL(5, service.rejects());
    CHECK_TRUE(TableReject::kNotValidated == service.activate(TableId::kRoverGeometry).reason);
    service.run(frame);
    checkGeometryUnchanged();
}

TEST(TableService, AnImageOfAnotherTableIsRejected) {
    CHECK_TRUE(load(TableId::kPlanner, faster).ok());
    CHECK_TRUE(TableReject::kWrongTable == service.validate(TableId::kPlanner).reason);
    LONGS_EQUAL(1, drainEventsWithId(events, events::kRejectWrongTable));
}

TEST(TableService, ActivateNeedsAValidatedImage) {
    CHECK_TRUE(TableReject::kNotLoaded == service.activate(TableId::kRoverGeometry).reason);
    CHECK_TRUE(load(TableId::kRoverGeometry, faster).ok());
    CHECK_TRUE(TableReject::kNotValidated == service.activate(TableId::kRoverGeometry).reason);
    const auto d = drainEvents(events, events::kRejectNotValidated);
    LONGS_EQUAL(1, d.count);
    CHECK_TRUE(d.text.find("ROVER_GEOMETRY activate") != std::string::npos);
    service.run(frame);
    checkGeometryUnchanged();
    // Any further chunk after validation makes it unvalidated again.
    const std::vector<std::uint8_t> map = defaultImage(TableId::kCanNodeMap);
    CHECK_TRUE(load(TableId::kCanNodeMap, map).ok());
    CHECK_TRUE(service.validate(TableId::kCanNodeMap).ok());
    const std::uint8_t extra = 0;
    CHECK_TRUE(service.loadChunk(TableId::kCanNodeMap, static_cast<std::uint32_t>(map.size()), &extra, 1).ok());
    CHECK_TRUE(TableBufferState::kLoading == service.status(TableId::kCanNodeMap).inactiveState);
    CHECK_TRUE(TableReject::kNotValidated == service.activate(TableId::kCanNodeMap).reason);
}

TEST(TableService, ChunksMustBeContiguous) {
    CHECK_TRUE(service.loadChunk(TableId::kRoverGeometry, 0, faster.data(), 10).ok());
    CHECK_TRUE(TableReject::kChunkGap == service.loadChunk(TableId::kRoverGeometry, 12, faster.data() + 12, 10).reason);
    CHECK_TRUE(TableReject::kChunkGap == service.loadChunk(TableId::kRoverGeometry, 5, faster.data() + 5, 10).reason);
    LONGS_EQUAL(2, drainEventsWithId(events, events::kRejectChunkGap));
    LONGS_EQUAL(10, service.status(TableId::kRoverGeometry).inactiveLength);  // the gap did not disturb the load
    // The right chunk continues the load.
    CHECK_TRUE(service.loadChunk(TableId::kRoverGeometry, 10, faster.data() + 10, faster.size() - 10).ok());
    CHECK_TRUE(service.validate(TableId::kRoverGeometry).ok());
    LONGS_EQUAL(1, drainEventsWithId(events, events::kTableValidated));
}

TEST(TableService, LoadsBeyondTheLargestImageAreRefused) {
    std::vector<std::uint8_t> big(kMaxTableImageSize + 1, 0);
    CHECK_TRUE(TableReject::kTooLarge == service.loadChunk(TableId::kPlanner, 0, big.data(), big.size()).reason);
    CHECK_TRUE(service.loadChunk(TableId::kPlanner, 0, big.data(), kMaxTableImageSize).ok());
    CHECK_TRUE(TableReject::kTooLarge ==
               service.loadChunk(TableId::kPlanner, kMaxTableImageSize, big.data(), 1).reason);
    LONGS_EQUAL(2, drainEventsWithId(events, events::kRejectTooLarge));
    CHECK_TRUE(TableReject::kNoData == service.loadChunk(TableId::kPlanner, 0, nullptr, 4).reason);
}

TEST(TableService, UnknownTableIdsAreRejectedAndEvented) {
    const auto bogus = static_cast<TableId>(42);
    CHECK_TRUE(TableReject::kUnknownTable == service.loadChunk(bogus, 0, faster.data(), faster.size()).reason);
    CHECK_TRUE(TableReject::kUnknownTable == service.validate(bogus).reason);
    CHECK_TRUE(TableReject::kUnknownTable == service.activate(bogus).reason);
    const auto d = drainEvents(events, events::kRejectUnknownTable);
    LONGS_EQUAL(3, d.count);
    CHECK_TRUE(d.text.find("42") != std::string::npos);
    LONGS_EQUAL(3, service.rejects());
    std::uint8_t out[kMaxTableImageSize];
    std::size_t length = 1;
    CHECK_TRUE(TableReject::kUnknownTable == service.dump(bogus, false, out, sizeof out, &length).reason);
    CHECK_FALSE(service.status(bogus).active);
}

TEST(TableService, WhileAnActivationIsPendingTheBufferIsHeld) {
    CHECK_TRUE(upload(TableId::kRoverGeometry, faster).ok());
    CHECK_TRUE(TableReject::kActivationPending ==
               service.loadChunk(TableId::kRoverGeometry, 0, defaultGeometry.data(), defaultGeometry.size()).reason);
    CHECK_TRUE(TableReject::kActivationPending == service.validate(TableId::kRoverGeometry).reason);
    CHECK_TRUE(TableReject::kActivationPending == service.activate(TableId::kRoverGeometry).reason);
    service.run(frame);
    CHECK_EQUAL(4.0F, service.roverGeometry().max_wheel_speed_rad_s);
}

TEST(TableService, AbortDropsTheBufferAndAPendingActivation) {
    CHECK_TRUE(TableReject::kNoPending == service.abort(TableId::kRoverGeometry).reason);
    CHECK_TRUE(upload(TableId::kRoverGeometry, faster).ok());
    CHECK_TRUE(service.abort(TableId::kRoverGeometry).ok());
    LONGS_EQUAL(1, drainEventsWithId(events, events::kTableAborted));
    service.run(frame);
    checkGeometryUnchanged();
    CHECK_TRUE(TableBufferState::kEmpty == service.status(TableId::kRoverGeometry).inactiveState);
}

TEST(TableService, DumpOfTheActiveTableIsTheImageItCameFrom) {
    std::uint8_t out[kMaxTableImageSize];
    std::size_t length = 0;
    std::size_t count = 0;
    const TableDesc* descs = tableDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        CHECK_TRUE(service.dump(descs[i].id, false, out, sizeof out, &length).ok());
        CHECK_TEXT(std::vector<std::uint8_t>(out, out + length) == defaultImage(descs[i].id), descs[i].name);
    }
    CHECK_TRUE(upload(TableId::kRoverGeometry, faster).ok());
    service.run(frame);
    CHECK_TRUE(service.dump(TableId::kRoverGeometry, false, out, sizeof out, &length).ok());
    CHECK_TRUE(std::vector<std::uint8_t>(out, out + length) == faster);
    CHECK_TRUE(TableReject::kTooLarge == service.dump(TableId::kRoverGeometry, false, out, length - 1, &length).reason);
    LONGS_EQUAL(0, length);
}

TEST(TableService, DumpOfTheInactiveBufferIsWhatWasLoaded) {
    std::uint8_t out[kMaxTableImageSize];
    std::size_t length = 0;
    CHECK_TRUE(TableReject::kNotLoaded == service.dump(TableId::kHabitual, true, out, sizeof out, &length).reason);
    std::vector<std::uint8_t> partial(faster.begin(), faster.begin() + 30);
    partial[25] ^= 0xFF;  // unchecked: a dump shows exactly what arrived
    CHECK_TRUE(load(TableId::kHabitual, partial).ok());
    CHECK_TRUE(service.dump(TableId::kHabitual, true, out, sizeof out, &length).ok());
    CHECK_TRUE(std::vector<std::uint8_t>(out, out + length) == partial);
    CHECK_TRUE(TableReject::kTooLarge == service.dump(TableId::kHabitual, true, out, 29, &length).reason);
    CHECK_TRUE(TableReject::kNoData == service.dump(TableId::kHabitual, true, nullptr, 0, &length).reason);
}

TEST(TableService, ResetCountersClearsTotalsAndPerTableCounts) {
    CHECK_TRUE(TableReject::kNotLoaded == service.validate(TableId::kPlanner).reason);
    LONGS_EQUAL(1, service.rejects());
    service.resetCounters();
    LONGS_EQUAL(0, service.rejects());
    LONGS_EQUAL(0, service.activations());
    LONGS_EQUAL(0, service.status(TableId::kPlanner).rejects);
    CHECK_TRUE(TableReject::kNone == service.status(TableId::kPlanner).lastReject);
    CHECK_TRUE(service.status(TableId::kPlanner).active);  // counters only
}

TEST(TableService, RunsAsTheFirstTaskOfAnExecutiveFrame) {
    // The rule the application relies on: a table activated during frame N is
    // in force for every task of frame N+1, and unchanged for the rest of frame N.
    struct Reader final : rse::core::Task {
        const TableService* tables = nullptr;
        std::vector<float> seen;
        void run(const FrameContext&) override { seen.push_back(tables->roverGeometry().max_wheel_speed_rad_s); }
    };
    struct Commander final : rse::core::Task {
        TableService* tables = nullptr;
        const std::vector<std::uint8_t>* image = nullptr;
        int frames = 0;
        void run(const FrameContext&) override {
            if (++frames == 2) {
                (void)tables->loadChunk(TableId::kRoverGeometry, 0, image->data(), image->size());
                (void)tables->validate(TableId::kRoverGeometry);
                (void)tables->activate(TableId::kRoverGeometry);
            }
        }
    };
    Reader before;
    Reader after;
    Commander commander;
    before.tables = &service;
    after.tables = &service;
    commander.tables = &service;
    commander.image = &faster;
    const rse::core::RateGroupEntry table[] = {
        {"tables", &service, 1, 0, 1000},
        {"before", &before, 1, 0, 1000},
        {"commander", &commander, 1, 0, 1000},
        {"after", &after, 1, 0, 1000},
    };
    rse::core::Executive executive{clock, events};
    CHECK_TRUE(Status::kOk == executive.init(rse::core::ExecutiveConfig{}, table, 4));
    for (int i = 0; i < 3; ++i) {
        executive.runFrame();
    }
    const std::vector<float> expectBefore = {5.0F, 5.0F, 4.0F};
    const std::vector<float> expectAfter = {5.0F, 5.0F, 4.0F};  // frame 2 ends with the old table
    CHECK_TRUE(before.seen == expectBefore);
    CHECK_TRUE(after.seen == expectAfter);
}

TEST(TableService, TableOperationsAllocateNothing) {
    std::vector<std::uint8_t> image = faster;
    std::vector<std::uint8_t> bad = faster;
    bad[30] ^= 0x01;
    std::uint8_t out[kMaxTableImageSize];
    std::size_t length = 0;
    rse::test::AllocationWatch watch;
    for (int round = 0; round < 3; ++round) {
        (void)service.loadChunk(TableId::kRoverGeometry, 0, bad.data(), 20);
        (void)service.loadChunk(TableId::kRoverGeometry, 20, bad.data() + 20, bad.size() - 20);
        (void)service.validate(TableId::kRoverGeometry);  // rejected: evented
        (void)service.activate(TableId::kRoverGeometry);  // rejected: not validated
        (void)service.loadChunk(TableId::kRoverGeometry, 0, image.data(), image.size());
        (void)service.validate(TableId::kRoverGeometry);
        (void)service.activate(TableId::kRoverGeometry);
        service.run(frame);
        (void)service.dump(TableId::kRoverGeometry, false, out, sizeof out, &length);
        (void)service.dump(TableId::kRoverGeometry, true, out, sizeof out, &length);
        (void)service.status(TableId::kRoverGeometry);
    }
    LONGS_EQUAL(0, watch.count());
    CHECK_EQUAL(4.0F, service.roverGeometry().max_wheel_speed_rad_s);
}

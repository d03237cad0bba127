// libFuzzer target: the table loader - image checks, the typed decoders and
// encoders (fuzz_table_checks.hpp, which fuzz_table fuzzes alone and faster),
// and the table service's load / validate / activate / run / dump sequence
// (unit_test/fuzz/README.md).
//
// An input is one table image, exactly as `rse-ground table build` writes it
// (so the seed corpus holds real images and the unit tests replay it as is).
// Each input is tried twice:
//   raw       the bytes as they are;
//   repaired  the header's payload length and CRC recomputed, so mutated
//             payloads reach the field range and cross-field checks instead
//             of dying at the CRC.
//
// Invariants (a broken one traps, which libFuzzer reports as a crash):
//   - checkTableImage without an expected id agrees with the check against
//     the header's own id, and passes against no other id;
//   - decodeTable gives the verdict of checkTableImage for its table, leaves
//     its output untouched when it refuses, and when it accepts, encodeTable of
//     the result reproduces the image byte for byte;
//   - every element of an accepted image reads back finite (floats) and within
//     its [min, max], and every cross-field rule holds;
//   - TableService: chunks (split at points derived from the data) load into
//     the inactive buffer and dump back unchanged; a chunk at the wrong offset
//     is refused with chunk_gap and changes nothing; validate gives
//     checkTableImage's verdict; a refused validate or activate leaves every
//     active table byte for byte as it was, also after run(); an accepted one
//     changes nothing until run(), after which the table's active dump is the
//     image byte for byte (version and CRC included) and no other table moved.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_service.hpp"
#include "fsw/tables/table_types.hpp"
#include "unit_test/fuzz/fuzz_table_checks.hpp"

using namespace rse;
using namespace rse::tables;
using namespace rse::fuzz_table;

namespace {

struct Rig {
    core::VirtualClock clock;
    core::EventLog events{clock};
    std::uint64_t frame = 0;

    void drainEvents() {
        while (core::isOk(events.pop(nullptr))) {
        }
    }
};

Rig& rig() {
    static Rig r;
    return r;
}

struct ActiveDumps {
    std::uint8_t bytes[kTableCount][kMaxTableImageSize];
    std::size_t length[kTableCount];
};

void dumpActive(const TableService& service, ActiveDumps* out) {
    const TableDesc* descs = tableDescs(nullptr);
    for (std::size_t i = 0; i < kTableCount; ++i) {
        FUZZ_REQUIRE(service.dump(descs[i].id, false, out->bytes[i], kMaxTableImageSize, &out->length[i]).ok());
        FUZZ_REQUIRE(checkTableImage(out->bytes[i], out->length[i], descs[i].id).ok());
    }
}

bool sameDump(const ActiveDumps& a, const ActiveDumps& b, std::size_t i) {
    return a.length[i] == b.length[i] && std::memcmp(a.bytes[i], b.bytes[i], a.length[i]) == 0;
}

void requireUnchangedBut(const ActiveDumps& before, const TableService& service, std::size_t except) {
    ActiveDumps now;
    dumpActive(service, &now);
    for (std::size_t i = 0; i < kTableCount; ++i) {
        FUZZ_REQUIRE(i == except || sameDump(before, now, i));
    }
}

// Loads the image into table `id` in chunks and takes it through validate,
// activate and run, checking the service against checkTableImage.
void loadSequence(const std::uint8_t* data, std::size_t size, TableId id) {
    Rig& r = rig();
    TableService service(r.events);
    FUZZ_REQUIRE(core::isOk(service.init(kDefaultTableImages, kDefaultTableImageCount)));
    const std::size_t index = tableIndex(id);
    FUZZ_REQUIRE(index < kTableCount);

    ActiveDumps before;
    dumpActive(service, &before);
    const TableStatus statusBefore = service.status(id);

    // An id that names no table is refused by every operation and changes nothing.
    const auto bogus = static_cast<TableId>(kTableCount + 1 + (size % 3));
    std::uint8_t scratch[kMaxTableImageSize];
    std::size_t scratchLength = 0;
    FUZZ_REQUIRE(service.loadChunk(bogus, 0, data, size).reason == TableReject::kUnknownTable);
    FUZZ_REQUIRE(service.validate(bogus).reason == TableReject::kUnknownTable);
    FUZZ_REQUIRE(service.activate(bogus).reason == TableReject::kUnknownTable);
    FUZZ_REQUIRE(service.abort(bogus).reason == TableReject::kUnknownTable);
    FUZZ_REQUIRE(service.dump(bogus, false, scratch, sizeof scratch, &scratchLength).reason ==
                 TableReject::kUnknownTable);
    FUZZ_REQUIRE(service.dump(id, true, scratch, sizeof scratch, &scratchLength).reason == TableReject::kNotLoaded);

    // One to three chunks, the boundaries picked by the data. The first starts
    // the load even when empty; empty later ones are skipped.
    const std::uint32_t h = fnv1a(data, size);
    std::size_t cut1 = (h >> 8) % (size + 1);
    std::size_t cut2 = (h >> 20) % (size + 1);
    if (cut1 > cut2) {
        const std::size_t t = cut1;
        cut1 = cut2;
        cut2 = t;
    }
    const std::size_t chunks = 1 + h % 3;
    const std::size_t bounds[4] = {0, chunks >= 2 ? cut1 : size, chunks == 3 ? cut2 : size, size};
    bool allLoaded = true;
    for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t from = bounds[c];
        const std::size_t to = bounds[c + 1];
        if (c > 0 && to == from) {
            continue;
        }
        const TableCheck loaded = service.loadChunk(id, static_cast<std::uint32_t>(from), data + from, to - from);
        if (!allLoaded) {
            // After a refused chunk the buffer ends short of this one's offset.
            FUZZ_REQUIRE(loaded.reason == TableReject::kChunkGap);
        } else if (to <= kMaxTableImageSize) {
            FUZZ_REQUIRE(loaded.ok());
        } else {
            FUZZ_REQUIRE(loaded.reason == TableReject::kTooLarge);
        }
        allLoaded = allLoaded && loaded.ok();
    }
    FUZZ_REQUIRE(allLoaded == (size <= kMaxTableImageSize));
    requireUnchangedBut(before, service, kTableCount);  // loading touches no active table

    std::uint8_t inactive[kMaxTableImageSize];
    std::size_t inactiveLength = 0;
    if (allLoaded) {
        FUZZ_REQUIRE(service.dump(id, true, inactive, sizeof inactive, &inactiveLength).ok());
        FUZZ_REQUIRE(inactiveLength == size && (size == 0 || std::memcmp(inactive, data, size) == 0));
        // A chunk that does not continue where the buffer ends changes nothing.
        const std::uint8_t stray = 0x5A;
        const TableCheck gap = service.loadChunk(id, static_cast<std::uint32_t>(size + 1), &stray, 1);
        FUZZ_REQUIRE(gap.reason == TableReject::kChunkGap);
        std::size_t againLength = 0;
        std::uint8_t again[kMaxTableImageSize];
        FUZZ_REQUIRE(service.dump(id, true, again, sizeof again, &againLength).ok());
        FUZZ_REQUIRE(againLength == size && (size == 0 || std::memcmp(again, data, size) == 0));
        if (size > 0) {
            FUZZ_REQUIRE(service.dump(id, true, again, size - 1, &againLength).reason == TableReject::kTooLarge);
        }
        const bool complete = service.status(id).inactiveState == TableBufferState::kLoaded;
        TableHeader header;
        FUZZ_REQUIRE(complete == (readTableHeader(data, size, &header) && size - kTableHeaderSize == header.payloadLength));
    }

    // What the inactive buffer holds: the whole input, or (when a chunk was
    // refused) the chunks before it - which may happen to be an image too.
    std::uint8_t buffer[kMaxTableImageSize];
    std::size_t bufferLength = 0;
    const bool haveBuffer = service.status(id).inactiveState != TableBufferState::kEmpty;
    if (haveBuffer) {
        FUZZ_REQUIRE(service.dump(id, true, buffer, sizeof buffer, &bufferLength).ok());
        FUZZ_REQUIRE(bufferLength <= size && (bufferLength == 0 || std::memcmp(buffer, data, bufferLength) == 0));
    }
    FUZZ_REQUIRE(!allLoaded || (haveBuffer && bufferLength == size));

    const TableCheck validated = service.validate(id);
    if (haveBuffer) {
        const TableCheck expected = checkTableImage(buffer, bufferLength, id);
        FUZZ_REQUIRE(validated.reason == expected.reason && validated.field == expected.field &&
                     validated.element == expected.element);
    } else {
        FUZZ_REQUIRE(validated.reason == TableReject::kNotLoaded);
    }
    if (!validated.ok()) {
        FUZZ_REQUIRE(service.status(id).lastReject == validated.reason);
        const TableCheck activated = service.activate(id);
        FUZZ_REQUIRE(activated.reason == (haveBuffer ? TableReject::kNotValidated : TableReject::kNotLoaded));
        core::FrameContext fc;
        fc.frame = r.frame++;
        service.run(fc);
        requireUnchangedBut(before, service, kTableCount);
        const TableStatus after = service.status(id);
        FUZZ_REQUIRE(after.activeVersion == statusBefore.activeVersion && after.activeCrc == statusBefore.activeCrc);
        FUZZ_REQUIRE(after.activations == statusBefore.activations);
        FUZZ_REQUIRE(service.abort(id).reason == (haveBuffer ? TableReject::kNone : TableReject::kNoPending));
        FUZZ_REQUIRE(service.status(id).inactiveState == TableBufferState::kEmpty);
        FUZZ_REQUIRE(service.validate(id).reason == TableReject::kNotLoaded);
        return;
    }

    FUZZ_REQUIRE(service.status(id).inactiveState == TableBufferState::kValidated);
    FUZZ_REQUIRE(service.activate(id).ok());
    FUZZ_REQUIRE(service.status(id).inactiveState == TableBufferState::kPending);
    requireUnchangedBut(before, service, kTableCount);  // nothing changes before the frame boundary
    FUZZ_REQUIRE(service.loadChunk(id, 0, buffer, bufferLength).reason == TableReject::kActivationPending);
    FUZZ_REQUIRE(service.validate(id).reason == TableReject::kActivationPending);
    FUZZ_REQUIRE(service.activate(id).reason == TableReject::kActivationPending);

    core::FrameContext fc;
    fc.frame = r.frame++;
    service.run(fc);
    requireUnchangedBut(before, service, index);
    std::uint8_t active[kMaxTableImageSize];
    std::size_t activeLength = 0;
    FUZZ_REQUIRE(service.dump(id, false, active, sizeof active, &activeLength).ok());
    FUZZ_REQUIRE(activeLength == bufferLength && std::memcmp(active, buffer, bufferLength) == 0);  // round trip
    FUZZ_REQUIRE(service.dump(id, false, active, bufferLength - 1, &activeLength).reason == TableReject::kTooLarge);
    TableHeader header;
    FUZZ_REQUIRE(readTableHeader(buffer, bufferLength, &header));
    const TableStatus after = service.status(id);
    FUZZ_REQUIRE(after.activeVersion == header.version && after.activeCrc == header.crc);
    FUZZ_REQUIRE(after.activations == statusBefore.activations + 1);
    FUZZ_REQUIRE(after.inactiveState == TableBufferState::kEmpty);
    FUZZ_REQUIRE(service.dump(id, true, buffer, sizeof buffer, &bufferLength).reason == TableReject::kNotLoaded);
}

// Start-up with the input in place of one default image (its own table's when
// it names one): init succeeds exactly when the image passes its checks, and
// then that table's active dump is the image. A second init with the defaults
// brings every table back to its default bytes.
void startup(const std::uint8_t* data, std::size_t size) {
    Rig& r = rig();
    TableHeader header;
    const bool haveHeader = readTableHeader(data, size, &header);
    const std::size_t named = haveHeader ? tableIndex(static_cast<TableId>(header.tableId)) : kTableCount;
    const std::size_t slot = named < kTableCount ? named : fnv1a(data, size) % kTableCount;
    FUZZ_REQUIRE(kDefaultTableImageCount == kTableCount);
    TableImageRef images[kTableCount];
    std::size_t replaced = kTableCount;
    for (std::size_t i = 0; i < kTableCount; ++i) {
        images[i] = kDefaultTableImages[i];
        TableHeader h;
        FUZZ_REQUIRE(readTableHeader(images[i].data, images[i].length, &h));
        if (tableIndex(static_cast<TableId>(h.tableId)) == slot) {
            images[i] = TableImageRef{data, size};
            replaced = i;
        }
    }
    FUZZ_REQUIRE(replaced < kTableCount);
    const TableId id = tableDescs(nullptr)[slot].id;
    const bool valid = checkTableImage(data, size).ok() && named == slot;

    TableService service(r.events);
    FUZZ_REQUIRE(core::isOk(service.init(images, kTableCount)) == valid);
    FUZZ_REQUIRE(service.status(id).active == valid);
    std::uint8_t dumped[kMaxTableImageSize];
    std::size_t dumpedLength = 0;
    if (valid) {
        FUZZ_REQUIRE(service.dump(id, false, dumped, sizeof dumped, &dumpedLength).ok());
        FUZZ_REQUIRE(dumpedLength == size && std::memcmp(dumped, data, size) == 0);
    }
    FUZZ_REQUIRE(core::isOk(service.init(kDefaultTableImages, kDefaultTableImageCount)));
    for (std::size_t i = 0; i < kDefaultTableImageCount; ++i) {
        const TableImageRef& image = kDefaultTableImages[i];
        TableHeader h;
        FUZZ_REQUIRE(readTableHeader(image.data, image.length, &h));
        FUZZ_REQUIRE(service.dump(static_cast<TableId>(h.tableId), false, dumped, sizeof dumped, &dumpedLength).ok());
        FUZZ_REQUIRE(dumpedLength == image.length && std::memcmp(dumped, image.data, image.length) == 0);
    }
}

void exercise(const std::uint8_t* data, std::size_t size) {
    checkAndDecode(data, size);
    startup(data, size);
    TableHeader header;
    const bool haveHeader = readTableHeader(data, size, &header);
    const TableId named = static_cast<TableId>(header.tableId);
    const std::uint32_t h = fnv1a(data, size);
    const TableDesc* descs = tableDescs(nullptr);
    // The table the header names (when it names one), and one picked by the data.
    if (haveHeader && tableIndex(named) < kTableCount) {
        loadSequence(data, size, named);
    }
    const TableId other = descs[h % kTableCount].id;
    if (!haveHeader || other != named) {
        loadSequence(data, size, other);
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    (void)rig();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > kMaxInput) {
        return -1;  // not added to the corpus
    }
    exercise(data, size);
    std::uint8_t repaired[kMaxTableImageSize];
    if (repair(data, size, repaired) && std::memcmp(repaired, data, size) != 0) {
        exercise(repaired, size);
    }
    rig().drainEvents();
    return 0;
}

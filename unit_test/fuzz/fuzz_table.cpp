// libFuzzer target: the table image checks and codecs alone - checkTableImage
// against every table id, decodeTable / encodeTable of every table,
// readFieldValue / writeFieldValue / sealTableImage (fuzz_table_checks.hpp has
// the invariants). No table service: fuzz_table_service drives the whole load
// sequence, at a few hundred inputs a second; this one runs thousands a second,
// so a 60 s run explores the decoder and the validator in depth
// (unit_test/fuzz/README.md).
//
// An input is one table image, exactly as `rse-ground table build` writes it
// (so the seed corpus holds real images and the unit tests replay it as is).
// Each input is tried twice:
//   raw       the bytes as they are;
//   repaired  the header's payload length and CRC recomputed, so mutated
//             payloads reach the field range and cross-field checks instead
//             of dying at the CRC.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "unit_test/fuzz/fuzz_table_checks.hpp"

using namespace rse::fuzz_table;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > kMaxInput) {
        return -1;  // not added to the corpus
    }
    checkAndDecode(data, size);
    std::uint8_t repaired[kMaxTableImageSize];
    if (repair(data, size, repaired) && std::memcmp(repaired, data, size) != 0) {
        checkAndDecode(repaired, size);
    }
    return 0;
}

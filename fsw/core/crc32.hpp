// CRC-32 as in IEEE 802.3, zlib and PNG (reflected polynomial 0xEDB88320,
// initial value and final XOR 0xFFFFFFFF): crc32("123456789") = 0xCBF43926,
// so any standard tool (python's zlib.crc32, `crc32` from libarchive-zip-perl)
// checks a table image by hand. Used for table images (docs/tables.md).
#pragma once

#include <cstddef>
#include <cstdint>

namespace rse::core {

// Continues a CRC: crc32(b, crc32(a)) == crc32(a then b). Start with 0.
std::uint32_t crc32(const void* data, std::size_t length, std::uint32_t crc = 0);

}  // namespace rse::core

// `rse-ground table load` and `table dump`: moving table images over the link
// with the dictionary's table commands (TABLE_LOAD chunks, TABLE_VALIDATE,
// TABLE_ACTIVATE, TABLE_DUMP) and reassembling TABLE_DUMP telemetry.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "fsw/tables/table_types.hpp"
#include "ground/ground_session.hpp"
#include "ground/telemetry_decoder.hpp"

namespace rse::ground {

constexpr std::size_t kTableChunkBytes = 200;  // TABLE_LOAD.data maximum

// The table id in an image's header (bytes 4-5, big-endian); nullopt if the
// image is shorter than that.
std::optional<std::uint16_t> imageTableId(const std::vector<std::uint8_t>& image);

// The TABLE_LOAD argument bytes for each chunk of the image, in order (offset
// 0 first, chunks of at most kTableChunkBytes).
std::vector<std::vector<std::uint8_t>> tableLoadChunks(std::uint16_t tableId, const std::vector<std::uint8_t>& image);

// "ROVER_GEOMETRY", "rover_geometry" or "1" -> the table; nullopt if none.
const tables::TableDesc* lookupTable(const std::string& nameOrId);

// Collects the TABLE_DUMP packets of one table and buffer into the image.
class TableDumpAssembler {
public:
    TableDumpAssembler(std::uint16_t tableId, bool inactive) : tableId_(tableId), inactive_(inactive) {}
    // Takes a packet; false when it is not a TABLE_DUMP of this table and buffer
    // (or is inconsistent: a chunk beyond total_length, a changed total length).
    bool add(const DecodedPacket& packet);
    bool started() const { return total_ > 0 || sawEmpty_; }
    bool complete() const;
    std::size_t totalLength() const { return total_; }
    std::size_t bytesReceived() const;
    const std::vector<std::uint8_t>& image() const { return image_; }

private:
    std::uint16_t tableId_;
    bool inactive_;
    std::size_t total_ = 0;
    bool sawEmpty_ = false;
    std::vector<std::uint8_t> image_;
    std::vector<bool> have_;
};

// Exit codes as the CLI's: 0 done, 1 link error / no ack / bad file, 3 rejected.
// load: sends TABLE_LOAD chunks, TABLE_VALIDATE and (activate) TABLE_ACTIVATE,
// each waiting for its ack; stops at the first rejection. The image is checked
// locally first (checkTableImage) and refused unless force.
int loadTableImage(GroundSession& session, const std::vector<std::uint8_t>& image, bool activate, bool force,
                   std::ostream& out, std::ostream& err);
// dump: sends TABLE_DUMP, collects the image (waiting the ack timeout between
// chunks), writes it to outputPath when not empty and prints it decoded.
int dumpTableImage(GroundSession& session, const tables::TableDesc& table, bool inactive,
                   const std::string& outputPath, std::ostream& out, std::ostream& err);

}  // namespace rse::ground

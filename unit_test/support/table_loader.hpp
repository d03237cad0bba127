// Test helper: put a table's new values in force as ground would (load one
// chunk, validate, activate) and let the table service apply it between frames.
#pragma once

#include <cstdint>

#include "fsw/core/executive.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::test {

template <typename Table>
bool activateTable(tables::TableService& service, tables::TableId id, const Table& table, std::uint32_t version) {
    std::uint8_t image[tables::kMaxTableImageSize];
    const std::size_t length = tables::encodeTable(table, version, image, sizeof image);
    if (length == 0 || !service.loadChunk(id, 0, image, length).ok() || !service.validate(id).ok() ||
        !service.activate(id).ok()) {
        return false;
    }
    core::FrameContext frame{};
    service.run(frame);
    return true;
}

}  // namespace rse::test

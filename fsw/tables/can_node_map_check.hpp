// The CAN node map's content rule, beyond what field ranges can say: every
// node id (six drives, four devices) is different. Two devices on one id
// would share one heartbeat record and one SDO channel, so each would mask the
// other's loss and the master would configure the wrong one. Run by
// checkTablePayload, so the ground table compiler and the flight table service
// refuse the same images; the refusal is kInconsistent naming the second use.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/tables/table_image.hpp"

namespace rse::tables {

TableCheck checkCanNodeMapPayload(const TableDesc& table, const std::uint8_t* payload, std::size_t length);

}  // namespace rse::tables

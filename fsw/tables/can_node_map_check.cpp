#include "fsw/tables/can_node_map_check.hpp"

#include "fsw/tables/table_types.hpp"

namespace rse::tables {
namespace {

constexpr CanNodeMapField::Index kNodeFields[] = {
    CanNodeMapField::drive_node_id, CanNodeMapField::imu_node_id, CanNodeMapField::power_node_id,
    CanNodeMapField::hazard_node_id, CanNodeMapField::position_fix_node_id,
};

}  // namespace

TableCheck checkCanNodeMapPayload(const TableDesc& table, const std::uint8_t* payload, std::size_t length) {
    bool used[128] = {};
    for (const CanNodeMapField::Index field : kNodeFields) {
        for (std::uint16_t e = 0; e < table.fields[field].count; ++e) {
            double v = 0.0;
            (void)readFieldValue(table, payload, length, static_cast<std::uint16_t>(field), e, &v);
            // Ranges were checked first (1..127), so the index is in bounds.
            const auto id = static_cast<std::size_t>(v) & 0x7FU;
            if (used[id]) {
                TableCheck check;
                check.reason = TableReject::kInconsistent;
                check.field = static_cast<std::int16_t>(field);
                check.element = e;
                return check;
            }
            used[id] = true;
        }
    }
    return TableCheck{};
}

}  // namespace rse::tables

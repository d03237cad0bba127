#include "fsw/tables/coarse_map_check.hpp"

#include "fsw/tables/table_types.hpp"

namespace rse::tables {
namespace {

constexpr std::uint16_t kSlots = 16;
constexpr std::uint16_t kVerticesPerSlot = 8;

TableCheck inconsistent(CoarseMapField::Index field, std::uint16_t element) {
    TableCheck check;
    check.reason = TableReject::kInconsistent;
    check.field = static_cast<std::int16_t>(field);
    check.element = element;
    return check;
}

double value(const TableDesc& table, const std::uint8_t* payload, std::size_t length, CoarseMapField::Index field,
             std::uint16_t element) {
    double v = 0.0;
    (void)readFieldValue(table, payload, length, static_cast<std::uint16_t>(field), element, &v);
    return v;
}

}  // namespace

TableCheck checkCoarseMapPayload(const TableDesc& table, const std::uint8_t* payload, std::size_t length) {
    const auto used = static_cast<std::uint16_t>(value(table, payload, length, CoarseMapField::obstacle_count, 0));
    for (std::uint16_t slot = 0; slot < kSlots; ++slot) {
        const auto n = static_cast<std::uint16_t>(value(table, payload, length, CoarseMapField::vertex_count, slot));
        const bool inUse = slot < used;
        if (inUse ? (n < 3 || n > kVerticesPerSlot) : n != 0) {
            return inconsistent(CoarseMapField::vertex_count, slot);
        }
        const auto base = static_cast<std::uint16_t>(slot * kVerticesPerSlot);
        for (std::uint16_t j = n; j < kVerticesPerSlot; ++j) {
            const auto e = static_cast<std::uint16_t>(base + j);
            if (value(table, payload, length, CoarseMapField::vertex_x_m, e) != 0.0) {
                return inconsistent(CoarseMapField::vertex_x_m, e);
            }
            if (value(table, payload, length, CoarseMapField::vertex_y_m, e) != 0.0) {
                return inconsistent(CoarseMapField::vertex_y_m, e);
            }
        }
        // Strictly convex: every turn along the boundary has the sign of the
        // first one (either winding), none is straight or folded back.
        double sign = 0.0;
        for (std::uint16_t j = 0; j < n; ++j) {
            const auto a = static_cast<std::uint16_t>(base + j);
            const auto b = static_cast<std::uint16_t>(base + (j + 1) % n);
            const auto c = static_cast<std::uint16_t>(base + (j + 2) % n);
            const double abx = value(table, payload, length, CoarseMapField::vertex_x_m, b) -
                               value(table, payload, length, CoarseMapField::vertex_x_m, a);
            const double aby = value(table, payload, length, CoarseMapField::vertex_y_m, b) -
                               value(table, payload, length, CoarseMapField::vertex_y_m, a);
            const double bcx = value(table, payload, length, CoarseMapField::vertex_x_m, c) -
                               value(table, payload, length, CoarseMapField::vertex_x_m, b);
            const double bcy = value(table, payload, length, CoarseMapField::vertex_y_m, c) -
                               value(table, payload, length, CoarseMapField::vertex_y_m, b);
            const double turn = abx * bcy - aby * bcx;
            if (turn == 0.0 || (sign != 0.0 && (turn > 0.0) != (sign > 0.0))) {
                return inconsistent(CoarseMapField::vertex_x_m, b);
            }
            sign = turn;
        }
        // ... and winds once: every other vertex strictly on the inner side of
        // each edge. Turns of one sign alone let a polygon that winds twice
        // through (a pentagram) pass, whose faces bound only its inner pentagon.
        for (std::uint16_t j = 0; j < n; ++j) {
            const auto a = static_cast<std::uint16_t>(base + j);
            const auto b = static_cast<std::uint16_t>(base + (j + 1) % n);
            const double ax = value(table, payload, length, CoarseMapField::vertex_x_m, a);
            const double ay = value(table, payload, length, CoarseMapField::vertex_y_m, a);
            const double abx = value(table, payload, length, CoarseMapField::vertex_x_m, b) - ax;
            const double aby = value(table, payload, length, CoarseMapField::vertex_y_m, b) - ay;
            for (std::uint16_t k = 0; k < n; ++k) {
                const auto w = static_cast<std::uint16_t>(base + k);
                if (w == a || w == b) {
                    continue;
                }
                const double side = abx * (value(table, payload, length, CoarseMapField::vertex_y_m, w) - ay) -
                                    aby * (value(table, payload, length, CoarseMapField::vertex_x_m, w) - ax);
                const bool inner = sign > 0.0 ? side > 0.0 : side < 0.0;
                if (!inner) {
                    return inconsistent(CoarseMapField::vertex_x_m, w);
                }
            }
        }
    }
    return TableCheck{};
}

}  // namespace rse::tables

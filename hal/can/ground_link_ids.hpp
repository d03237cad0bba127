// CAN ids of the ISO-TP ground link (docs/icd.md §1.2 and §2), one place for
// the rover (fsw/io/can_ground_link) and the ground (ground/ground_link,
// rse-ground --can). Normal addressing, 11-bit ids. They lie outside every CiA 301
// restricted CAN-ID range (hal/canopen/canopen_ids.hpp, kCia301RestrictedIds: an
// independent CANopen stack flags those) and outside every id the rover's nodes
// use; unit_test/hal/canopen/test_can_id_plan.cpp checks both.
#pragma once

#include <cstdint>

namespace rse::hal {

constexpr std::uint32_t kGroundUplinkCanId = 0x6C0;    // ground -> rover: commands (the rover receives)
constexpr std::uint32_t kGroundDownlinkCanId = 0x6C1;  // rover -> ground: telemetry (the rover sends)

}  // namespace rse::hal

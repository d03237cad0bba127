// The software-bus message catalogue: every message id in one place.
// Each id's payload type lives in its own header in fsw/msg/; the table with
// producers and consumers is in docs/architecture.md ("Bus message catalogue").
//
// Ranges: 0x08xx telemetry-bound (one day one CCSDS APID each, 0x0800 | APID),
//         0x18xx commands from ground, 0x01xx-0x07xx internal between layers.
#pragma once

#include "fsw/core/software_bus.hpp"

namespace rse::msg::ids {

constexpr core::MsgId kHousekeeping = 0x0801;  // HousekeepingMsg, 1 Hz, cmdtlm -> telemetry

}  // namespace rse::msg::ids

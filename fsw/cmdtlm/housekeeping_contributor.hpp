// HK is one packet with fields from many owners (docs/icd.md §5.5): the
// command service's cmd_*, auth_* and link_*, the mode owner's mode and estop,
// CAN I/O's can_*, the table service's table_*, telemetry output's tlm_*. Each
// owner fills its own fields when HK is packed (housekeeping_telemetry.hpp, in
// the order they were registered); the executive's, bus's and event log's
// counters come from the housekeeping collection (HousekeepingMsg).
#pragma once

#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::cmdtlm {

class HousekeepingContributor {
public:
    // Writes this owner's fields of hk and no other.
    virtual void fillHousekeeping(HK_Tlm& hk) const = 0;

protected:
    ~HousekeepingContributor() = default;
};

}  // namespace rse::cmdtlm

#include "fsw/tables/table_telemetry.hpp"

#include <algorithm>
#include <cstring>

namespace rse::tables {

void TableTelemetry::sendStatus(TableId id, const TableCheck& check, cmdtlm::TelemetrySink& sink) const {
    const TableStatus s = tables_.status(id);
    cmdtlm::TABLE_STATUS_Tlm tlm{};
    tlm.table_id = static_cast<std::uint16_t>(id);
    tlm.inactive_state = static_cast<std::uint8_t>(s.inactiveState);
    tlm.inactive_length = static_cast<std::uint16_t>(s.inactiveLength);
    tlm.active_version = s.activeVersion;
    tlm.active_crc = s.activeCrc;
    tlm.last_reject = static_cast<std::uint8_t>(check.reason);
    tlm.last_reject_field = check.field;
    tlm.activations = s.activations;
    sink.send(tlm);
}

core::Status TableTelemetry::sendDump(TableId id, bool inactive, cmdtlm::TelemetrySink& sink) {
    std::size_t length = 0;
    const TableCheck check = tables_.dump(id, inactive, image_, sizeof image_, &length);
    if (check.reason != TableReject::kNone) {
        return core::Status::kNotFound;
    }
    // Bounded: kMaxTableImageSize / sizeof data chunks.
    for (std::size_t offset = 0; offset < length; offset += sizeof dump_.data) {
        dump_ = cmdtlm::TABLE_DUMP_Tlm{};
        dump_.table_id = static_cast<std::uint16_t>(id);
        dump_.buffer = inactive ? 1 : 0;
        dump_.total_length = static_cast<std::uint16_t>(length);
        dump_.offset = static_cast<std::uint16_t>(offset);
        const std::size_t chunk = std::min(sizeof dump_.data, length - offset);
        dump_.length = static_cast<std::uint16_t>(chunk);
        std::memcpy(dump_.data, image_ + offset, chunk);
        sink.send(dump_);
    }
    return core::Status::kOk;
}

void TableTelemetry::fillHousekeeping(cmdtlm::HK_Tlm& hk) const {
    hk.table_activations = tables_.activations();
    hk.table_rejects = tables_.rejects();
}

}  // namespace rse::tables

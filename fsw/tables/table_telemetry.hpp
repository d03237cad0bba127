// The table service's packets (docs/icd.md §5.5), sent right after the table
// command that asks for them, through the telemetry sink:
//   TABLE_STATUS  after every table command: the table's buffers, its last
//                 rejection (reason and field) and its activations
//   TABLE_DUMP    TABLE_DUMP's image, active or inactive, in chunks of the
//                 packet's data field
// and HK's table_* fields (table activations and rejections, all tables).
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/housekeeping_contributor.hpp"
#include "fsw/cmdtlm/telemetry_sink.hpp"
#include "fsw/core/status.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::tables {

class TableTelemetry final : public cmdtlm::HousekeepingContributor {
public:
    explicit TableTelemetry(const TableService& tables) : tables_(tables) {}

    // TABLE_STATUS of table id, with the verdict of the command just carried out.
    void sendStatus(TableId id, const TableCheck& check, cmdtlm::TelemetrySink& sink) const;
    // TABLE_DUMP packets of the image (inactive: the load buffer). kNotFound
    // when the table has no such image (nothing sent).
    core::Status sendDump(TableId id, bool inactive, cmdtlm::TelemetrySink& sink);

    void fillHousekeeping(cmdtlm::HK_Tlm& hk) const override;

private:
    const TableService& tables_;
    // Kept off the command task's stack.
    cmdtlm::TABLE_DUMP_Tlm dump_{};
    std::uint8_t image_[kMaxTableImageSize] = {};
};

}  // namespace rse::tables

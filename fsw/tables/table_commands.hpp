// The table commands (APID 0x183), owned by the table service: TABLE_LOAD
// (a chunk into the inactive buffer), TABLE_VALIDATE, TABLE_ACTIVATE (at the
// next frame boundary) and TABLE_DUMP (the image in TABLE_DUMP packets). Each
// is answered with the table's TABLE_STATUS, and refused (execution_failed)
// with the TableReject code as CMD_ACK.detail; a dump of an image that is not
// there reads as kNotLoaded. RESET_COUNTERS zeroes the service's counters.
#pragma once

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/cmdtlm/telemetry_sink.hpp"
#include "fsw/tables/table_service.hpp"
#include "fsw/tables/table_telemetry.hpp"

namespace rse::tables {

class TableCommands final : public cmdtlm::AppCommands {
public:
    TableCommands(TableService& tables, TableTelemetry& telemetry, cmdtlm::TelemetrySink& sink)
        : tables_(tables), telemetry_(telemetry), sink_(sink) {}

    std::uint16_t apid() const override { return cmdtlm::describe(cmdtlm::CommandCode::TABLE_LOAD).apid; }
    cmdtlm::CommandOutcome execute(const cmdtlm::CommandVerdict& verdict) override;
    void resetCounters() override { tables_.resetCounters(); }

private:
    TableService& tables_;
    TableTelemetry& telemetry_;
    cmdtlm::TelemetrySink& sink_;
};

}  // namespace rse::tables

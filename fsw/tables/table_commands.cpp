#include "fsw/tables/table_commands.hpp"

namespace rse::tables {

using cmdtlm::CommandCode;

cmdtlm::CommandOutcome TableCommands::execute(const cmdtlm::CommandVerdict& verdict) {
    TableId id{};
    TableCheck check{};
    switch (verdict.command->code) {
        case CommandCode::TABLE_LOAD: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::TABLE_LOAD_Args>(verdict);
            id = static_cast<TableId>(a.table_id);
            check = tables_.loadChunk(id, a.offset, a.data, a.data_length);
            break;
        }
        case CommandCode::TABLE_VALIDATE:
            id = static_cast<TableId>(cmdtlm::decodedArgs<cmdtlm::TABLE_VALIDATE_Args>(verdict).table_id);
            check = tables_.validate(id);
            break;
        case CommandCode::TABLE_ACTIVATE:
            id = static_cast<TableId>(cmdtlm::decodedArgs<cmdtlm::TABLE_ACTIVATE_Args>(verdict).table_id);
            check = tables_.activate(id);
            break;
        case CommandCode::TABLE_DUMP: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::TABLE_DUMP_Args>(verdict);
            id = static_cast<TableId>(a.table_id);
            if (!core::isOk(telemetry_.sendDump(id, a.buffer != 0, sink_))) {
                check.reason = TableReject::kNotLoaded;
            }
            break;
        }
        default:
            return cmdtlm::commandFailed(-1);
    }
    telemetry_.sendStatus(id, check, sink_);
    if (check.reason != TableReject::kNone) {
        return cmdtlm::commandFailed(static_cast<std::int16_t>(check.reason));
    }
    return {};
}

}  // namespace rse::tables

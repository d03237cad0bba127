#include "fsw/site_map/site_map_commands.hpp"

namespace rse::site_map {

using cmdtlm::CommandCode;

cmdtlm::CommandOutcome SiteMapCommands::execute(const cmdtlm::CommandVerdict& verdict) {
    UploadRefusal why = UploadRefusal::kNone;
    switch (verdict.command->code) {
        case CommandCode::MAP_LOAD: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::MAP_LOAD_Args>(verdict);
            why = service_.loadChunk(a.offset, a.data, a.data_length);
            break;
        }
        case CommandCode::MAP_COMMIT: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::MAP_COMMIT_Args>(verdict);
            why = service_.commit(a.length, a.crc32);
            break;
        }
        case CommandCode::MAP_ABORT:
            why = service_.abort();
            break;
        default:
            return cmdtlm::commandFailed(-1);
    }
    telemetry_.send(sink_);
    if (why != UploadRefusal::kNone) {
        return cmdtlm::commandFailed(static_cast<std::int16_t>(why));
    }
    return {};
}

}  // namespace rse::site_map

#include "fsw/plan_executive/plan_commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rse::plan_executive {

using cmdtlm::CommandCode;

namespace {

// Blob arguments are at most the dictionary's size; the message holds kPlanChunkBytes.
std::uint16_t chunkLength(std::size_t length) {
    return static_cast<std::uint16_t>(std::min<std::size_t>(length, msg::kPlanChunkBytes));
}

}  // namespace

cmdtlm::CommandOutcome PlanCommands::execute(const cmdtlm::CommandVerdict& verdict) {
    msg::PlanCommandMsg& m = message_;
    m = msg::PlanCommandMsg{};
    m.timeNs = clock_.now();
    switch (verdict.command->code) {
        case CommandCode::PLAN_LOAD: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::PLAN_LOAD_Args>(verdict);
            m.kind = msg::PlanCommandKind::kChunk;
            m.offset = a.offset;
            m.length = chunkLength(a.data_length);
            std::memcpy(m.data, a.data, m.length);
            break;
        }
        case CommandCode::PLAN_START: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::PLAN_START_Args>(verdict);
            m.kind = msg::PlanCommandKind::kStart;
            m.textLength = a.length;
            m.crc32 = a.crc32;
            break;
        }
        case CommandCode::PLAN_SHORT: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::PLAN_SHORT_Args>(verdict);
            m.kind = msg::PlanCommandKind::kShort;
            m.length = chunkLength(a.text_length);
            std::memcpy(m.data, a.text, m.length);
            break;
        }
        case CommandCode::PLAN_ABORT:
            m.kind = msg::PlanCommandKind::kAbort;
            break;
        case CommandCode::PLAN_EXTEND: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::PLAN_EXTEND_Args>(verdict);
            m.kind = msg::PlanCommandKind::kExtend;
            // extra is checked finite and within [0.1, 6553.5] s by the validator.
            m.extendMs = static_cast<std::uint32_t>(std::lround(static_cast<double>(a.extra) * 1000.0));
            m.length = chunkLength(a.activity_length);
            std::memcpy(m.data, a.activity, m.length);
            break;
        }
        default:
            return cmdtlm::commandFailed(-1);
    }
    return core::isOk(bus_.publish(m)) ? cmdtlm::CommandOutcome{} : cmdtlm::commandFailed(0);
}

}  // namespace rse::plan_executive

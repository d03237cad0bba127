// Why ground's EXEC_SET_TASK was refused: CMD_ACK.detail (reason
// execution_failed) and event 225. Numeric values are part of the command
// interface (docs/icd.md §5.4), so the ground tool names them too.
//
// Ground may disable any other rate-group row for a while (the health monitor
// then sees it stall and fault protection runs it again). The rows below it may
// not: once disabled, nothing onboard or on the ground could bring them, or the
// rover, back.
#pragma once

#include <cstdint>

namespace rse::cmdtlm {

enum class TaskCommandRefusal : std::uint8_t {
    kNone = 0,
    kNoSuchRow = 1,       // beyond the rate-group table
    kCommandIngest = 2,   // commands: no command could enable it again, and it carries out fault protection's restarts
    kCanIo = 3,           // can_io: the CAN ground link and every drive command (the wheels would keep their last speed)
    kFaultDetection = 4,  // health: its own stall would go unseen, so nothing would restart it
    kFaultResponse = 5,   // fault_prot: the task that restarts stalled rows, itself included
};
constexpr std::uint8_t kTaskCommandRefusalCount = 6;

// At most 45 characters: it ends event 225's text.
constexpr const char* toString(TaskCommandRefusal why) {
    switch (why) {
        case TaskCommandRefusal::kNone: return "none";
        case TaskCommandRefusal::kNoSuchRow: return "no such row in the rate-group table";
        case TaskCommandRefusal::kCommandIngest: return "command ingest: nothing could enable it again";
        case TaskCommandRefusal::kCanIo: return "CAN I/O: CAN ground link and drive commands";
        case TaskCommandRefusal::kFaultDetection: return "health: its stall would go unseen";
        case TaskCommandRefusal::kFaultResponse: return "fault protection: nothing would restart it";
    }
    return "?";
}

}  // namespace rse::cmdtlm

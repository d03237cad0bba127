// `rse-ground plan load`, `plan short` and `plan abort`: mission plans over
// the link with the dictionary's plan commands (APID 0x185; docs/ground.md
// "plan", docs/plan_executive.md "The task").
//
// load: PLAN_LOAD chunks of the text (offset 0 first, each as large as the
// command's data blob allows, 200 B), then PLAN_START with the text's length
// and CRC-32 (fsw/core/crc32.hpp, the function the executive checks it
// with). Each command waits for its acknowledgement before the next goes:
// that is the pacing. The rover executes a command in the frame it arrives
// and acknowledges it in that frame, so the next chunk is executed a frame
// later at the earliest: at most one chunk a 10 ms frame, 10 between two
// runs of the executive (10 Hz), inside its pipe of 12
// (PlanExecutiveTask::kPipeDepth; a burst beyond it would be lost and seen
// as a gap). Then the executive's verdict: the first of its events 950
// (accepted) and 952 / 953 / 954 (refused: upload, parse, no selection) that
// comes down after the PLAN_START; a 952 while the chunks go up (a chunk
// refused: the upload is spoiled) stops the load at once.
//
// The ground check comes first (checkPlanForUplink): the text's size, then
// `plan check`'s flight parser and method selection (ground/plan_tool.hpp);
// a plan that fails is not sent unless forced, an oversize one never.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/tpn.hpp"
#include "ground/ground_session.hpp"

namespace rse::ground {

// PLAN_LOAD's data blob and PLAN_SHORT's text: the largest chunk and the
// longest short plan (the dictionary's, which the bus message matches).
constexpr std::size_t kPlanLoadChunkBytes = sizeof(cmdtlm::PLAN_LOAD_Args{}.data);
constexpr std::size_t kPlanShortBytes = sizeof(cmdtlm::PLAN_SHORT_Args{}.text);
static_assert(kPlanLoadChunkBytes == msg::kPlanChunkBytes && kPlanShortBytes == msg::kPlanChunkBytes,
              "the plan commands' blobs and PlanCommandMsg::data differ");
// The executive's upload buffer: the longest plan PLAN_LOAD can build.
constexpr std::size_t kPlanUploadBytes = plan_executive::kMaxPlanText;

// How long load and short wait for the executive's verdict at least (the
// CLI's --timeout when longer): its selection takes up to its budget, ten
// 100 ms runs, and the verdict comes down as an event at once.
constexpr double kPlanVerdictSeconds = 3.0;

// The PLAN_LOAD argument bytes (u16 offset, the chunk's bytes) of each chunk
// of text, in order: offset 0 first, every chunk kPlanLoadChunkBytes long
// but the last. Text longer than kPlanUploadBytes: none (it cannot be sent).
std::vector<std::vector<std::uint8_t>> planLoadChunks(const std::string& text);
// The PLAN_START argument bytes: u32 length, u32 CRC-32 of the text.
std::vector<std::uint8_t> planStartArgs(const std::string& text);

// Before anything is sent: text of 1..limit bytes (kPlanUploadBytes for
// load, kPlanShortBytes for short) that `plan check` passes under the given
// component states (summary on out, the reason on err). Returns 0 (send it),
// or 2: too long or empty (never sent), or refused by the check and not
// forced (with force the refusal is shown and 0 returned).
int checkPlanForUplink(const std::string& text, const std::string& where, std::size_t limit,
                       const plan_executive::SelectionInput& components, bool force, std::ostream& out,
                       std::ostream& err);

// Exit codes as the CLI's: 0 the executive accepted the plan; 1 no
// acknowledgement, or no verdict within verdictSeconds after the PLAN_START
// (PLAN_SHORT) was accepted; 2 text too long (nothing sent); 3 a command
// rejected, or the plan refused by the executive (its event printed).
int loadPlanText(GroundSession& session, const std::string& text, double verdictSeconds, std::ostream& out,
                 std::ostream& err);
// PLAN_SHORT with the whole text (at most kPlanShortBytes), then the verdict as load.
int sendShortPlan(GroundSession& session, const std::string& text, double verdictSeconds, std::ostream& out,
                  std::ostream& err);

}  // namespace rse::ground

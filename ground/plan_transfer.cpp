#include "ground/plan_transfer.hpp"

#include <cstring>
#include <ostream>

#include "fsw/core/byte_codec.hpp"
#include "fsw/core/crc32.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "ground/command_encoder.hpp"
#include "ground/plan_tool.hpp"
#include "ground/telemetry_decoder.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

namespace pe_events = plan_executive::events;

// The plan executive's events that say what became of an upload, as they
// come down, numbered by the session's receive count (arrival order).
class PlanVerdictWatch {
public:
    explicit PlanVerdictWatch(GroundSession& session) : session_(session) {
        session_.setObserver([this](const DecodedPacket& p) { take(p); });
    }
    ~PlanVerdictWatch() { session_.setObserver(nullptr); }
    PlanVerdictWatch(const PlanVerdictWatch&) = delete;
    PlanVerdictWatch& operator=(const PlanVerdictWatch&) = delete;

    // The first 952 (upload refused) received after packet number `after`.
    const DecodedPacket* uploadRefusal(std::uint64_t after) const {
        for (const Seen& s : seen_) {
            if (s.index > after && s.id == pe_events::kUploadRefused) {
                return &s.packet;
            }
        }
        return nullptr;
    }
    // Waits up to `seconds` for the first verdict (950, 952, 953, 954)
    // received after packet number `after`; nullptr if none came.
    const DecodedPacket* awaitVerdict(std::uint64_t after, double seconds) {
        const double deadline = monotonicSeconds() + seconds;
        for (;;) {
            for (const Seen& s : seen_) {
                if (s.index > after) {
                    return &s.packet;
                }
            }
            const double left = deadline - monotonicSeconds();
            if (left <= 0.0) {
                return nullptr;
            }
            (void)session_.receive(left);
        }
    }

private:
    struct Seen {
        std::uint64_t index;
        unsigned id;
        DecodedPacket packet;
    };
    void take(const DecodedPacket& p) {
        if (!p.ok || p.apid != cmdtlm::EVENT_Tlm::kApid) {
            return;
        }
        const auto id = static_cast<unsigned>(p.value("event_id").value_or(0));
        if (id == pe_events::kPlanAccepted || id == pe_events::kUploadRefused || id == pe_events::kParseRefused ||
            id == pe_events::kSelectionRefused) {
            seen_.push_back(Seen{session_.receivedCount(), id, p});
        }
    }

    GroundSession& session_;
    std::vector<Seen> seen_;
};

// "EVT 950 INFO plan_exec: plan two_targets accepted: ..."
std::string eventLine(const DecodedPacket& p) {
    const DecodedField* text = p.field("text");
    return "EVT " + formatNumber(p.value("event_id").value_or(0)) + " " +
           severityName(static_cast<unsigned>(p.value("severity").value_or(0))) + " " +
           (text != nullptr ? text->text : std::string());
}

// After the PLAN_START / PLAN_SHORT (sent as the session's last command) was
// accepted: the executive's verdict, reported.
int reportVerdict(PlanVerdictWatch& watch, GroundSession& session, const std::string& what, double seconds,
                  std::ostream& out, std::ostream& err) {
    const DecodedPacket* verdict = watch.awaitVerdict(session.receivedAtLastSend(), seconds);
    if (verdict == nullptr) {
        err << what << ": accepted, but no verdict from the plan executive within " << formatNumber(seconds)
            << " s (events " << pe_events::kPlanAccepted << " accepted, " << pe_events::kUploadRefused << "-"
            << pe_events::kSelectionRefused
            << " refused): rse-ground watch --only PLAN_EXEC shows plans_accepted and last_refusal\n";
        return 1;
    }
    if (verdict->value("event_id").value_or(0) != pe_events::kPlanAccepted) {
        err << "the plan executive refused the plan: " << eventLine(*verdict) << "\n";
        return 3;
    }
    out << "the plan executive accepted the plan: " << eventLine(*verdict) << "\n";
    return 0;
}

// Text the command can carry: 1..limit bytes; else false and why on err.
bool fits(const std::string& text, std::size_t limit, const std::string& where, std::ostream& err) {
    if (!text.empty() && text.size() <= limit) {
        return true;
    }
    err << where << ": " << text.size() << " bytes of plan text; the rover takes 1 to " << limit
        << (limit == kPlanUploadBytes ? " (its plan upload buffer)" : " (one PLAN_SHORT)") << ": not sent\n";
    return false;
}

}  // namespace

std::vector<std::vector<std::uint8_t>> planLoadChunks(const std::string& text) {
    std::vector<std::vector<std::uint8_t>> chunks;
    if (text.size() > kPlanUploadBytes) {
        return chunks;
    }
    for (std::size_t offset = 0; offset < text.size(); offset += kPlanLoadChunkBytes) {
        cmdtlm::PLAN_LOAD_Args args{};
        args.offset = static_cast<std::uint16_t>(offset);
        args.data_length = static_cast<std::uint16_t>(
            text.size() - offset < kPlanLoadChunkBytes ? text.size() - offset : kPlanLoadChunkBytes);
        std::memcpy(args.data, text.data() + offset, args.data_length);
        chunks.push_back(argumentBytes(args));
    }
    return chunks;
}

std::vector<std::uint8_t> planStartArgs(const std::string& text) {
    cmdtlm::PLAN_START_Args args{};
    args.length = static_cast<std::uint32_t>(text.size());
    args.crc32 = core::crc32(text.data(), text.size());
    return argumentBytes(args);
}

int checkPlanForUplink(const std::string& text, const std::string& where, std::size_t limit,
                       const plan_executive::SelectionInput& components, bool force, std::ostream& out,
                       std::ostream& err) {
    if (!fits(text, limit, where, err)) {
        return 2;
    }
    if (checkPlanText(text, where, components, false, out, err)) {
        return 0;
    }
    if (!force) {
        err << where << ": not sent (--force sends it anyway, to see the rover refuse it)\n";
        return 2;
    }
    err << where << ": sending it anyway (--force)\n";
    return 0;
}

int loadPlanText(GroundSession& session, const std::string& text, double verdictSeconds, std::ostream& out,
                 std::ostream& err) {
    if (!fits(text, kPlanUploadBytes, "plan load", err)) {
        return 2;
    }
    const std::vector<std::vector<std::uint8_t>> chunks = planLoadChunks(text);
    const std::uint32_t crc = core::crc32(text.data(), text.size());
    out << "loading " << text.size() << " bytes of plan text (CRC-32 0x" << std::hex << crc << std::dec << ") in "
        << chunks.size() << " PLAN_LOAD chunk" << (chunks.size() == 1 ? "" : "s") << " over "
        << session.link().describe() << "\n";
    PlanVerdictWatch watch(session);
    std::uint64_t uploadBegan = 0;
    for (std::size_t i = 0; i <= chunks.size(); ++i) {
        if (i > 0) {
            // What has come down meanwhile: a chunk refused spoils the upload.
            while (session.receive(0.0)) {
            }
            if (const DecodedPacket* refusal = watch.uploadRefusal(uploadBegan)) {
                err << "the plan executive refused the upload: " << eventLine(*refusal) << "\n";
                return 3;
            }
        }
        if (i == chunks.size()) {
            break;
        }
        const std::string what = "PLAN_LOAD " + std::to_string(i + 1) + "/" + std::to_string(chunks.size()) +
                                 " (offset " + std::to_string(i * kPlanLoadChunkBytes) + ")";
        if (const int rc = sendReported(session, cmdtlm::CommandCode::PLAN_LOAD, chunks[i], what, out, err)) {
            return rc;
        }
        uploadBegan = i == 0 ? session.receivedAtLastSend() : uploadBegan;
    }
    if (const int rc =
            sendReported(session, cmdtlm::CommandCode::PLAN_START, planStartArgs(text), "PLAN_START", out, err)) {
        return rc;
    }
    return reportVerdict(watch, session, "PLAN_START", verdictSeconds, out, err);
}

int sendShortPlan(GroundSession& session, const std::string& text, double verdictSeconds, std::ostream& out,
                  std::ostream& err) {
    if (!fits(text, kPlanShortBytes, "plan short", err)) {
        return 2;
    }
    cmdtlm::PLAN_SHORT_Args args{};
    args.text_length = static_cast<std::uint16_t>(text.size());
    std::memcpy(args.text, text.data(), text.size());
    PlanVerdictWatch watch(session);
    if (const int rc =
            sendReported(session, cmdtlm::CommandCode::PLAN_SHORT, argumentBytes(args), "PLAN_SHORT", out, err)) {
        return rc;
    }
    return reportVerdict(watch, session, "PLAN_SHORT", verdictSeconds, out, err);
}

}  // namespace rse::ground

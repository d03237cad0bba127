#include "ground/map_transfer.hpp"

#include <chrono>
#include <cstring>
#include <optional>
#include <ostream>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/crc32.hpp"
#include "fsw/site_map/site_map_image.hpp"
#include "fsw/site_map/site_map_upload.hpp"
#include "ground/command_encoder.hpp"

namespace rse::ground {

namespace {

constexpr std::size_t kChunkBytes = sizeof(cmdtlm::MAP_LOAD_Args{}.data);
// A commit of the largest map takes about 31 command-task runs (0.31 s); the
// rest is the link's.
constexpr double kCommitEndTimeoutS = 10.0;
// A command's SITE_MAP comes in the run that takes it.
constexpr double kAnswerTimeoutS = 2.0;

// The last SITE_MAP the session received (the rover answers each site map
// command with one, and sends one when a commit ends), and whether it came
// after the last command was sent (an acknowledgement goes at a higher
// priority than the answer and may overtake it).
class SiteMapWatch {
public:
    explicit SiteMapWatch(GroundSession& session) : session_(session) {
        session_.setObserver([this](const DecodedPacket& p) {
            if (p.ok && p.desc != nullptr && std::strcmp(p.name(), "SITE_MAP") == 0) {
                last_ = p;
                lastNumber_ = session_.receivedCount();
            }
        });
    }
    ~SiteMapWatch() { session_.setObserver(nullptr); }
    SiteMapWatch(const SiteMapWatch&) = delete;
    SiteMapWatch& operator=(const SiteMapWatch&) = delete;
    double value(const char* field) const { return last_ ? last_->value(field).value_or(-1.0) : -1.0; }
    bool answeredSinceSend() const { return last_.has_value() && lastNumber_ > session_.receivedAtLastSend(); }
    bool any() const { return last_.has_value(); }
    // Packets until done() or timeoutSeconds: whether done() came true.
    template <typename Done>
    bool waitUntil(Done done, double timeoutSeconds) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutSeconds);
        while (!done()) {
            const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
            if (left <= 0.0) {
                return false;
            }
            (void)session_.receive(left);
        }
        return true;
    }

private:
    GroundSession& session_;
    std::optional<DecodedPacket> last_;
    std::uint64_t lastNumber_ = 0;   // the session's packet number of last_
};

std::string refusalName(int detail) {
    return site_map::toString(static_cast<site_map::UploadRefusal>(detail < 0 ? 0 : detail));
}

// A commit refused (at once: the CMD_ACK's summary first; or in its slices):
// the reason and, for an image's, its rock or zone. Exit status 3.
int reportRefusal(std::ostream& err, const std::string& ackSummary, int refusal, const SiteMapWatch& watch) {
    err << "the rover refused the map: " << ackSummary << refusalName(refusal);
    if (refusal >= static_cast<int>(site_map::UploadRefusal::kImage)) {
        err << " (item " << static_cast<long>(watch.value("last_refusal_item")) << ")";
    }
    err << "; the map in force is kept\n";
    return 3;
}

}  // namespace

std::vector<std::vector<std::uint8_t>> mapLoadChunks(const std::vector<std::uint8_t>& image) {
    std::vector<std::vector<std::uint8_t>> chunks;
    for (std::size_t offset = 0; offset < image.size(); offset += kChunkBytes) {
        cmdtlm::MAP_LOAD_Args args{};
        args.offset = static_cast<std::uint32_t>(offset);
        args.data_length =
            static_cast<std::uint16_t>(image.size() - offset < kChunkBytes ? image.size() - offset : kChunkBytes);
        std::memcpy(args.data, image.data() + offset, args.data_length);
        chunks.push_back(argumentBytes(args));
    }
    return chunks;
}

std::vector<std::uint8_t> mapCommitArgs(const std::vector<std::uint8_t>& image) {
    cmdtlm::MAP_COMMIT_Args args{};
    args.length = static_cast<std::uint32_t>(image.size());
    args.crc32 = core::crc32(image.data(), image.size());
    return argumentBytes(args);
}

int checkSiteMapFile(const std::vector<std::uint8_t>& image, const std::string& where, std::ostream& out,
                     std::ostream& err) {
    const site_map::SiteMapCheck c = site_map::checkSiteMapImage(image.data(), image.size());
    if (!c.ok()) {
        err << where << ": " << site_map::toString(c.reason);
        if (c.reason >= site_map::SiteMapReject::kBadVertexCount && c.reason <= site_map::SiteMapReject::kBadKind) {
            err << " (" << (c.keepOut ? "zone " : "rock ") << c.item << ")";
        }
        err << "\n";
        return 2;
    }
    out << where << ": a site map of " << c.rocks << " rocks and " << c.keepOuts << " keep-out zones, "
        << image.size() << " bytes, CRC-32 0x" << std::hex << core::crc32(image.data(), image.size()) << std::dec
        << "\n";
    return 0;
}

int loadSiteMap(GroundSession& session, const std::vector<std::uint8_t>& image, std::ostream& out, std::ostream& err) {
    const std::vector<std::vector<std::uint8_t>> chunks = mapLoadChunks(image);
    out << "loading " << image.size() << " bytes of site map in " << chunks.size() << " MAP_LOAD chunks over "
        << session.link().describe() << "\n";
    SiteMapWatch watch(session);
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        const AckResult r = session.sendCommand(cmdtlm::describe(cmdtlm::CommandCode::MAP_LOAD), chunks[i]);
        if (r.outcome == AckOutcome::kNoAck) {
            err << "MAP_LOAD " << i + 1 << "/" << chunks.size() << ": " << r.summary << "\n";
            return 1;
        }
        if (r.outcome == AckOutcome::kRejected) {
            err << "MAP_LOAD " << i + 1 << "/" << chunks.size() << " (offset " << i * kChunkBytes
                << ") refused: " << r.summary << " (" << refusalName(r.detail) << ")\n";
            return 3;
        }
    }
    // A SITE_MAP that came after the last chunk went (its answer, or a late
    // one of an earlier chunk: no MAP_LOAD moves the counts read below), else
    // the last one of the upload when that is lost on the way; one at least.
    if (!watch.waitUntil([&] { return watch.answeredSinceSend(); }, kAnswerTimeoutS) && !watch.any()) {
        err << "MAP_LOAD " << chunks.size() << "/" << chunks.size() << ": acknowledged, but no SITE_MAP came within "
            << kAnswerTimeoutS << " s: the counts the commit would be judged by are unknown; not committed\n";
        return 1;
    }
    // Never zeroed on board (RESET_COUNTERS leaves them): a commit's end is
    // told by commits_started, its outcome by the revision and commits_cancelled.
    const double startedBefore = watch.value("commits_started");
    const double revisionBefore = watch.value("revision");
    const double cancelledBefore = watch.value("commits_cancelled");
    const AckResult r = session.sendCommand(cmdtlm::describe(cmdtlm::CommandCode::MAP_COMMIT), mapCommitArgs(image));
    if (r.outcome == AckOutcome::kNoAck) {
        err << "MAP_COMMIT: " << r.summary << "\n";
        return 1;
    }
    if (r.outcome == AckOutcome::kRejected) {
        return reportRefusal(err, r.summary + ": ", r.detail, watch);
    }
    // Accepted: the commit runs in slices on board. Its end is a SITE_MAP
    // with no commit under way that counts it among those started.
    const bool ended = watch.waitUntil(
        [&] { return watch.value("commit_phase") == 0.0 && watch.value("commits_started") > startedBefore; },
        kCommitEndTimeoutS);
    if (!ended) {
        err << "MAP_COMMIT accepted, but no SITE_MAP told its end within " << kCommitEndTimeoutS
            << " s (rse-ground tlm SITE_MAP shows commit_phase)\n";
        return 1;
    }
    if (watch.value("commits_cancelled") > cancelledBefore) {
        err << "the commit was cancelled (MAP_ABORT); the map in force is kept\n";
        return 3;
    }
    if (!(watch.value("revision") > revisionBefore)) {
        return reportRefusal(err, "", static_cast<int>(watch.value("last_refusal")), watch);
    }
    out << "MAP_COMMIT: " << r.summary << " and checked in " << static_cast<long>(watch.value("commit_runs"))
        << " command-task runs: map " << static_cast<long>(watch.value("revision")) << " in force, "
        << static_cast<long>(watch.value("rocks")) << " rocks\n";
    return 0;
}

}  // namespace rse::ground

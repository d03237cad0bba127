#include "ground/map_transfer.hpp"

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

// The last SITE_MAP the session received (the rover answers each site map command with one).
class SiteMapWatch {
public:
    explicit SiteMapWatch(GroundSession& session) : session_(session) {
        session_.setObserver([this](const DecodedPacket& p) {
            if (p.ok && p.desc != nullptr && std::strcmp(p.name(), "SITE_MAP") == 0) {
                last_ = p;
            }
        });
    }
    ~SiteMapWatch() { session_.setObserver(nullptr); }
    SiteMapWatch(const SiteMapWatch&) = delete;
    SiteMapWatch& operator=(const SiteMapWatch&) = delete;
    double value(const char* field) const { return last_ ? last_->value(field).value_or(-1.0) : -1.0; }

private:
    GroundSession& session_;
    std::optional<DecodedPacket> last_;
};

std::string refusalName(int detail) {
    return site_map::toString(static_cast<site_map::UploadRefusal>(detail < 0 ? 0 : detail));
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
    const AckResult r = session.sendCommand(cmdtlm::describe(cmdtlm::CommandCode::MAP_COMMIT), mapCommitArgs(image));
    if (r.outcome == AckOutcome::kNoAck) {
        err << "MAP_COMMIT: " << r.summary << "\n";
        return 1;
    }
    if (r.outcome == AckOutcome::kRejected) {
        err << "the rover refused the map: " << r.summary << ": " << refusalName(r.detail);
        if (r.detail >= static_cast<int>(site_map::UploadRefusal::kImage)) {
            err << " (item " << static_cast<long>(watch.value("last_refusal_item")) << ")";
        }
        err << "; the map in force is kept\n";
        return 3;
    }
    out << "MAP_COMMIT: " << r.summary << ": map " << static_cast<long>(watch.value("revision")) << " in force, "
        << static_cast<long>(watch.value("rocks")) << " rocks\n";
    return 0;
}

}  // namespace rse::ground

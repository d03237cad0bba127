#include "ground/table_transfer.hpp"

#include <ostream>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/table_compiler.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

std::vector<std::uint8_t> idArgs(std::uint16_t tableId) {
    std::vector<std::uint8_t> bytes(2);
    core::BeWriter w(bytes.data(), bytes.size());
    w.u16(tableId);
    return bytes;
}

}  // namespace

std::optional<std::uint16_t> imageTableId(const std::vector<std::uint8_t>& image) {
    if (image.size() < 6) {
        return std::nullopt;
    }
    return static_cast<std::uint16_t>((image[4] << 8) | image[5]);
}

std::vector<std::vector<std::uint8_t>> tableLoadChunks(std::uint16_t tableId, const std::vector<std::uint8_t>& image) {
    std::vector<std::vector<std::uint8_t>> chunks;
    for (std::size_t offset = 0; offset < image.size(); offset += kTableChunkBytes) {
        const std::size_t length = image.size() - offset < kTableChunkBytes ? image.size() - offset : kTableChunkBytes;
        std::vector<std::uint8_t> args(4 + length);
        core::BeWriter w(args.data(), args.size());
        w.u16(tableId);
        w.u16(static_cast<std::uint16_t>(offset));
        w.bytes(image.data() + offset, length);
        chunks.push_back(std::move(args));
    }
    return chunks;
}

const tables::TableDesc* lookupTable(const std::string& nameOrId) {
    long long id = 0;
    if (parseInteger(nameOrId, &id)) {
        return id > 0 && id <= 0xFFFF ? tables::findTable(static_cast<tables::TableId>(id)) : nullptr;
    }
    return tables::findTable(toUpper(nameOrId).c_str());
}

bool TableDumpAssembler::add(const DecodedPacket& p) {
    if (!p.ok || p.apid != cmdtlm::TABLE_DUMP_Tlm::kApid ||
        p.value("table_id").value_or(-1) != tableId_ || p.value("buffer").value_or(-1) != (inactive_ ? 1 : 0)) {
        return false;
    }
    const auto total = static_cast<std::size_t>(p.value("total_length").value_or(0));
    const auto offset = static_cast<std::size_t>(p.value("offset").value_or(0));
    const auto length = static_cast<std::size_t>(p.value("length").value_or(0));
    const DecodedField* data = p.field("data");
    if (data == nullptr || length > data->raw.size() || offset + length > total) {
        return false;
    }
    if (total == 0) {
        sawEmpty_ = true;
        return true;
    }
    if (total_ != 0 && total != total_) {
        return false;  // another dump of a different image: keep the first
    }
    if (total_ == 0) {
        total_ = total;
        image_.assign(total, 0);
        have_.assign(total, false);
    }
    for (std::size_t i = 0; i < length; ++i) {
        image_[offset + i] = static_cast<std::uint8_t>(data->raw[i]);
        have_[offset + i] = true;
    }
    return true;
}

std::size_t TableDumpAssembler::bytesReceived() const {
    std::size_t n = 0;
    for (const bool b : have_) {
        n += b ? 1 : 0;
    }
    return n;
}

bool TableDumpAssembler::complete() const {
    return sawEmpty_ || (total_ > 0 && bytesReceived() == total_);
}

int loadTableImage(GroundSession& session, const std::vector<std::uint8_t>& image, bool activate, bool force,
                   std::ostream& out, std::ostream& err) {
    const std::optional<std::uint16_t> id = imageTableId(image);
    if (!id) {
        err << "table load: the image is " << image.size() << " bytes, too short for a table header\n";
        return 1;
    }
    const tables::TableDesc* table = tables::findTable(static_cast<tables::TableId>(*id));
    const tables::TableCheck check = tables::checkTableImage(image.data(), image.size());
    if (!check.ok()) {
        err << "table load: the image does not pass the table checks: " << describeCheck(image.data(), image.size())
            << "\n";
        if (!force) {
            err << "table load: not sent (--force sends it anyway, to see the rover refuse it)\n";
            return 1;
        }
    }
    const cmdtlm::CommandDesc& load = cmdtlm::describe(cmdtlm::CommandCode::TABLE_LOAD);
    if (image.size() > static_cast<std::size_t>(load.args[1].max) + 1) {
        err << "table load: the image is " << image.size() << " bytes; the rover takes at most "
            << formatNumber(load.args[1].max + 1) << "\n";
        return 1;
    }
    const std::string name = table != nullptr ? table->name : "table " + std::to_string(*id);
    out << "loading " << name << " (id " << *id << ", " << image.size() << " bytes) over "
        << session.link().describe() << "\n";
    const std::vector<std::vector<std::uint8_t>> chunks = tableLoadChunks(*id, image);
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        const std::string what = "TABLE_LOAD " + std::to_string(i + 1) + "/" + std::to_string(chunks.size()) +
                                 " (offset " + std::to_string(i * kTableChunkBytes) + ")";
        if (const int rc = sendReported(session, cmdtlm::CommandCode::TABLE_LOAD, chunks[i], what, out, err)) {
            return rc;
        }
    }
    if (const int rc = sendReported(session, cmdtlm::CommandCode::TABLE_VALIDATE, idArgs(*id), "TABLE_VALIDATE",
                                        out, err)) {
        return rc;
    }
    if (activate) {
        if (const int rc = sendReported(session, cmdtlm::CommandCode::TABLE_ACTIVATE, idArgs(*id),
                                            "TABLE_ACTIVATE", out, err)) {
            return rc;
        }
        out << name << " loaded, validated and activated (at the next frame boundary)\n";
    } else {
        out << name << " loaded and validated; TABLE_ACTIVATE (or --activate) makes it active\n";
    }
    return 0;
}

int dumpTableImage(GroundSession& session, const tables::TableDesc& table, bool inactive,
                   const std::string& outputPath, std::ostream& out, std::ostream& err) {
    const auto id = static_cast<std::uint16_t>(table.id);
    TableDumpAssembler assembler(id, inactive);
    session.setObserver([&assembler](const DecodedPacket& p) { (void)assembler.add(p); });
    std::vector<std::uint8_t> args(3);
    core::BeWriter w(args.data(), args.size());
    w.u16(id);
    w.u8(inactive ? 1 : 0);
    const std::string what = std::string("TABLE_DUMP ") + table.name + (inactive ? " (inactive)" : " (active)");
    const AckResult result = session.sendCommand(cmdtlm::describe(cmdtlm::CommandCode::TABLE_DUMP), args);
    int rc = 0;
    if (result.outcome == AckOutcome::kNoAck) {
        err << what << ": " << session.noAckText() << "\n";
        rc = 1;
    } else if (result.outcome == AckOutcome::kRejected) {
        err << what << ": " << result.summary << "\n";
        rc = 3;
    }
    // Chunks keep coming after the ack; wait the ack timeout after each one.
    while (rc == 0 && !assembler.complete()) {
        const std::size_t before = assembler.bytesReceived();
        const double deadline = monotonicSeconds() + session.ackTimeout();
        while (!assembler.complete() && assembler.bytesReceived() == before && monotonicSeconds() < deadline) {
            (void)session.receive(deadline - monotonicSeconds());
        }
        if (!assembler.complete() && assembler.bytesReceived() == before) {
            err << what << ": dump incomplete: " << assembler.bytesReceived() << " of "
                << (assembler.totalLength() > 0 ? std::to_string(assembler.totalLength()) : std::string("?"))
                << " bytes within " << formatNumber(session.ackTimeout()) << " s of the last chunk\n";
            rc = 1;
        }
    }
    session.setObserver(nullptr);
    if (rc != 0) {
        return rc;
    }
    out << what << ": " << result.summary << ", " << assembler.image().size() << " bytes\n";
    if (assembler.image().empty()) {
        out << "the " << (inactive ? "inactive" : "active") << " buffer of " << table.name << " is empty\n";
        return 0;
    }
    if (!outputPath.empty()) {
        try {
            writeTableImageFile(outputPath, assembler.image());
        } catch (const std::exception& e) {
            err << what << ": " << e.what() << "\n";
            return 1;
        }
        out << "wrote " << outputPath << "\n";
    }
    out << describeImage(assembler.image().data(), assembler.image().size());
    return 0;
}

}  // namespace rse::ground

#include "sim_stub/lockstep/map_upload.hpp"

#include "fsw/core/crc32.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/map_transfer.hpp"
#include "ground/site_map_encoder.hpp"
#include "ground/table_compiler.hpp"
#include "ground/table_transfer.hpp"
#include "sim_stub/scenario/coarse_map_source.hpp"

namespace rse::sim {

namespace {

MapUploadResult failed(MapUploadResult r, const std::string& why) {
    r.ok = false;
    r.error = why;
    return r;
}

}  // namespace

MapUploadResult uploadCoarseMap(const Scenario& scenario, MemoryGround& ground, LockstepRig& rig,
                                const std::function<void()>& service) {
    MapUploadResult r;
    ground::CompiledTable table;
    try {
        table = ground::compileTableText(coarseMapSource(scenario), scenario.name + " COARSE_MAP");
    } catch (const std::exception& e) {
        return failed(r, e.what());
    }
    tables::TableHeader header;
    if (!tables::readTableHeader(table.image.data(), table.image.size(), &header)) {
        return failed(r, "the compiled COARSE_MAP image has no header");
    }
    for (const Obstacle& o : scenario.obstacles) {
        r.obstacles += o.known ? 1U : 0U;
    }
    r.bytes = table.image.size();
    r.crc = header.crc;
    // One command a frame at most: each is executed and acknowledged in the
    // frame it arrives, as rse-ground's table load waits for each.
    const auto sendAndStep = [&](const char* name, const std::uint8_t* args, std::size_t n) {
        const std::uint32_t before = ground.tableStatus().packets;
        if (!ground.send(name, args, n)) {
            return false;
        }
        return rig.runUntil([&] { service(); return ground.tableStatus().packets > before; }, kMapUploadLimitNs);
    };
    const std::uint16_t id = header.tableId;
    for (const auto& chunk : ground::tableLoadChunks(id, table.image)) {
        if (!sendAndStep("TABLE_LOAD", chunk.data(), chunk.size()) || ground.tableStatus().lastReject != 0) {
            return failed(r, "TABLE_LOAD chunk " + std::to_string(r.chunks) + " not taken (reject " +
                                 std::to_string(ground.tableStatus().lastReject) + ")");
        }
        ++r.chunks;
    }
    const std::uint8_t idArgs[2] = {static_cast<std::uint8_t>(id >> 8), static_cast<std::uint8_t>(id & 0xFF)};
    if (!sendAndStep("TABLE_VALIDATE", idArgs, sizeof idArgs) || ground.tableStatus().lastReject != 0) {
        return failed(r, "TABLE_VALIDATE refused the scenario's COARSE_MAP (reject " +
                             std::to_string(ground.tableStatus().lastReject) + ")");
    }
    if (!sendAndStep("TABLE_ACTIVATE", idArgs, sizeof idArgs) || ground.tableStatus().lastReject != 0) {
        return failed(r, "TABLE_ACTIVATE refused (reject " + std::to_string(ground.tableStatus().lastReject) + ")");
    }
    // Active at the next frame boundary; TABLE_STATUS comes after a table
    // command, so a TABLE_DUMP of the active buffer a frame later shows it,
    // with the image's CRC, as an operator would check.
    (void)rig.runUntil([&] { service(); return false; }, 20 * core::kNsPerMs);
    const std::uint8_t dumpArgs[3] = {idArgs[0], idArgs[1], 0};
    const bool answered = sendAndStep("TABLE_DUMP", dumpArgs, sizeof dumpArgs);
    const MemoryGround::TableStatusSeen& s = ground.tableStatus();
    if (!answered || s.tableId != id || s.activeCrc != r.crc) {
        return failed(r, "TABLE_STATUS does not show the scenario's COARSE_MAP active");
    }
    r.ok = true;
    return r;
}

MapUploadResult uploadSiteMap(const Scenario& scenario, MemoryGround& ground, LockstepRig& rig,
                              const std::function<void()>& service) {
    MapUploadResult r;
    const ground::SiteMapSpec spec = siteMapSpec(scenario);
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(spec);
    r.obstacles = spec.rocks.size();
    r.bytes = image.size();
    r.crc = core::crc32(image.data(), image.size());
    const auto sendAndStep = [&](const char* name, const std::vector<std::uint8_t>& args) {
        const std::uint32_t before = ground.siteMap().packets;
        if (!ground.send(name, args.data(), args.size())) {
            return false;
        }
        return rig.runUntil([&] { service(); return ground.siteMap().packets > before; }, kMapUploadLimitNs);
    };
    for (const std::vector<std::uint8_t>& chunk : ground::mapLoadChunks(image)) {
        if (!sendAndStep("MAP_LOAD", chunk) || ground.siteMap().lastRefusal != 0) {
            return failed(r, "MAP_LOAD chunk " + std::to_string(r.chunks) + " not taken (refusal " +
                                 std::to_string(ground.siteMap().lastRefusal) + ")");
        }
        ++r.chunks;
    }
    if (!sendAndStep("MAP_COMMIT", ground::mapCommitArgs(image))) {
        return failed(r, "MAP_COMMIT not answered");
    }
    // The commit runs in slices, a command-task run each: its end is the
    // SITE_MAP with commit_phase 0 (sent in the run it ends).
    // (A commit refused at once answers with commit_phase 0 already.)
    if (!rig.runUntil([&] { service(); return ground.siteMap().commitPhase == 0; }, kMapUploadLimitNs)) {
        return failed(r, "MAP_COMMIT did not end within " + std::to_string(kMapUploadLimitNs / core::kNsPerSec) + " s");
    }
    const MemoryGround::SiteMapSeen& seen = ground.siteMap();
    if (seen.lastRefusal != 0 || seen.mapCrc != r.crc || seen.rocks != r.obstacles) {
        return failed(r, "SITE_MAP does not show the scenario's map in force (refusal " +
                             std::to_string(seen.lastRefusal) + ", item " + std::to_string(seen.lastRefusalItem) +
                             ")");
    }
    r.ok = true;
    return r;
}

}  // namespace rse::sim

// A ground station for lockstep runs (tests, rse-demo): authenticated command
// packets (the dictionary's names, the lab key) into the flight software over an
// in-memory packet link, and the downlink drained (counted, not decoded) so it
// never fills. Add link() to the FswApp before LockstepRig::init(). Host side:
// HMAC-SHA-256 through mbedTLS (LDLIBS_CRYPTO).
//
// It is also the scenario's FlightTaskCommander (RoverSim::attachFlightTasks):
// a task_stall fault becomes EXEC_SET_TASK, sent like any other command. Task
// names are resolved as an operator would, from the TASK_TIMING packets the
// downlink brings (task_index, task_name; one per row each second), so a
// stall by name before the first TASK_TIMING of that task is not sent.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_packet.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "hal/link/memory_packet_link.hpp"
#include "sim_stub/scenario/fault_target.hpp"

namespace rse::sim {

class MemoryGround final : public FlightTaskCommander {
public:
    // What the ground knows of one rate-group row, from TASK_TIMING.
    struct TaskSeen {
        bool known = false;
        char name[sizeof(cmdtlm::TASK_TIMING_Tlm{}.task_name) + 1] = {};
        std::uint32_t runs = 0;  // TASK_TIMING.runs, as of the last packet
    };
    static constexpr std::size_t kRows = 256;  // every u8 task_index

    hal::MemoryPacketLink& link() { return link_; }

    // Queues one command; false when the name is unknown or the packet was not sent.
    bool send(const char* name, const std::uint8_t* args = nullptr, std::size_t argLength = 0) {
        if (!hmacReady_) {
            hmacReady_ = core::isOk(hmac_.init());
        }
        const cmdtlm::CommandDesc* c = cmdtlm::findCommand(name);
        if (c == nullptr || !hmacReady_) {
            return false;
        }
        cmdtlm::CommandFields f;
        f.apid = c->apid;
        f.functionCode = c->functionCode;
        f.keyId = cmdtlm::kLabKeyId;
        f.authSequence = authSequence_++;
        std::uint8_t bytes[cmdtlm::kMaxCommandPacket];
        const std::size_t n =
            cmdtlm::encodeCommandPacket(f, args, argLength, cmdtlm::kLabKey, hmac_, bytes, sizeof bytes);
        return n > 0 && core::isOk(link_.groundSend(bytes, n));
    }
    bool setMode(std::uint8_t mode) { return send("SET_MODE", &mode, 1); }

    // Call every frame (e.g. from the rig's frame callback).
    void drainDownlink() {
        std::size_t length = 0;
        while (core::isOk(link_.groundReceive(buffer_, sizeof buffer_, &length))) {
            ++downlinked_;
            noteTaskTiming(length);
            noteTableStatus(length);
            noteSiteMap(length);
            keepPacket(length);
        }
    }
    // The latest TABLE_STATUS (sent after every table command), as an operator
    // reads it: which table, its active image's CRC, the command's reject code.
    struct TableStatusSeen {
        std::uint32_t packets = 0;  // TABLE_STATUS packets seen so far
        std::uint16_t tableId = 0;
        std::uint32_t activeCrc = 0;
        std::uint8_t lastReject = 0;
        std::uint32_t activations = 0;
    };
    const TableStatusSeen& tableStatus() const { return tableStatus_; }
    // The latest SITE_MAP (sent after every site map command).
    struct SiteMapSeen {
        std::uint32_t packets = 0;
        std::uint32_t revision = 0;
        std::uint32_t rocks = 0;
        std::uint32_t mapCrc = 0;
        std::uint8_t lastRefusal = 0;
        std::uint32_t lastRefusalItem = 0;
        std::uint32_t mapsLoaded = 0;
        std::uint32_t commitsRefused = 0;
        std::uint8_t commitPhase = 0;     // 0: no commit under way
        std::uint32_t commitRuns = 0;
    };
    const SiteMapSeen& siteMap() const { return siteMap_; }

    // Keeps the latest packet of one APID (0: none) for a test to decode.
    void keepApid(std::uint16_t apid) { keptApid_ = apid; }
    const std::uint8_t* kept() const { return kept_; }
    std::size_t keptLength() const { return keptLength_; }
    std::uint32_t keptCount() const { return keptCount_; }
    std::uint32_t downlinked() const { return downlinked_; }

    // EXEC_SET_TASK for `row`, or for the row TASK_TIMING names `name` when name is not empty.
    bool setFlightTaskEnabled(std::size_t row, const std::string& name, bool enabled) override {
        if (!name.empty()) {
            row = kRows;
            for (std::size_t i = 0; i < kRows; ++i) {
                row = tasks_[i].known && name == tasks_[i].name ? i : row;
            }
        }
        if (row >= kRows) {
            return false;
        }
        const std::uint8_t args[2] = {static_cast<std::uint8_t>(row), static_cast<std::uint8_t>(enabled ? 1 : 0)};
        if (!send("EXEC_SET_TASK", args, sizeof args)) {
            return false;
        }
        ++taskCommandsSent_;
        lastTaskRow_ = row;
        return true;
    }
    std::uint32_t taskCommandsSent() const { return taskCommandsSent_; }
    std::size_t lastTaskRow() const { return lastTaskRow_; }
    const TaskSeen& task(std::size_t row) const { return tasks_[row < kRows ? row : 0]; }

private:
    void keepPacket(std::size_t length) {
        if (keptApid_ == 0 || length < cmdtlm::kTelemetryHeaderSize || length > sizeof kept_ ||
            cmdtlm::decodePrimaryHeader(buffer_).apid != keptApid_) {
            return;
        }
        std::memcpy(kept_, buffer_, length);
        keptLength_ = length;
        ++keptCount_;
    }
    // A TASK_TIMING packet in buffer_: the row's name and runs (task_index,
    // task_name and runs are its first fields, docs/dictionary.md).
    void noteTaskTiming(std::size_t length) {
        if (length != cmdtlm::kTelemetryHeaderSize + cmdtlm::kTASK_TIMING_TlmSize ||
            cmdtlm::decodePrimaryHeader(buffer_).apid != cmdtlm::TASK_TIMING_Tlm::kApid) {
            return;
        }
        core::BeReader r(buffer_ + cmdtlm::kTelemetryHeaderSize, cmdtlm::kTASK_TIMING_TlmSize);
        TaskSeen& t = tasks_[r.u8()];
        r.bytes(t.name, sizeof t.name - 1);
        t.runs = r.u32();
        t.known = r.ok();
    }

    // A TABLE_STATUS packet in buffer_ (fields in the dictionary's order).
    void noteTableStatus(std::size_t length) {
        if (length != cmdtlm::kTelemetryHeaderSize + cmdtlm::kTABLE_STATUS_TlmSize ||
            cmdtlm::decodePrimaryHeader(buffer_).apid != cmdtlm::TABLE_STATUS_Tlm::kApid) {
            return;
        }
        core::BeReader r(buffer_ + cmdtlm::kTelemetryHeaderSize, cmdtlm::kTABLE_STATUS_TlmSize);
        TableStatusSeen s = tableStatus_;
        s.tableId = r.u16();
        (void)r.u8();   // inactive_state
        (void)r.u16();  // inactive_length
        (void)r.u32();  // active_version
        s.activeCrc = r.u32();
        s.lastReject = r.u8();
        (void)r.u16();  // last_reject_field
        s.activations = r.u32();
        if (r.ok()) {
            ++s.packets;
            tableStatus_ = s;
        }
    }

    // A SITE_MAP packet in buffer_ (fields in the dictionary's order).
    void noteSiteMap(std::size_t length) {
        if (length != cmdtlm::kTelemetryHeaderSize + cmdtlm::kSITE_MAP_TlmSize ||
            cmdtlm::decodePrimaryHeader(buffer_).apid != cmdtlm::SITE_MAP_Tlm::kApid) {
            return;
        }
        core::BeReader r(buffer_ + cmdtlm::kTelemetryHeaderSize, cmdtlm::kSITE_MAP_TlmSize);
        SiteMapSeen s = siteMap_;
        s.revision = r.u32();
        s.rocks = r.u32();
        (void)r.u16();  // keep_outs
        for (int i = 0; i < 4; ++i) {
            (void)r.u32();  // x_min, y_min, x_max, y_max (f32)
        }
        (void)r.u32();  // map_bytes
        s.mapCrc = r.u32();
        (void)r.u32();  // upload_bytes
        (void)r.u8();   // upload_open
        s.lastRefusal = r.u8();
        s.lastRefusalItem = r.u32();
        (void)r.u32();  // chunks_taken
        (void)r.u32();  // chunks_refused
        s.mapsLoaded = r.u32();
        s.commitsRefused = r.u32();
        (void)r.u32();  // uploads_aborted
        (void)r.u32();  // aborts_refused
        s.commitPhase = r.u8();
        s.commitRuns = r.u32();
        (void)r.u32();  // commits_started
        if (r.ok()) {
            ++s.packets;
            siteMap_ = s;
        }
    }

    hal::MemoryPacketLink link_;
    cmdtlm::HmacSha256 hmac_;
    bool hmacReady_ = false;
    std::uint32_t authSequence_ = 1;
    std::uint32_t downlinked_ = 0;
    std::uint32_t taskCommandsSent_ = 0;
    std::size_t lastTaskRow_ = kRows;
    TaskSeen tasks_[kRows] = {};
    std::uint8_t buffer_[hal::kMemoryLinkMaxPacket] = {};
    TableStatusSeen tableStatus_{};
    SiteMapSeen siteMap_{};
    std::uint16_t keptApid_ = 0;
    std::uint8_t kept_[hal::kMemoryLinkMaxPacket] = {};
    std::size_t keptLength_ = 0;
    std::uint32_t keptCount_ = 0;
};

}  // namespace rse::sim

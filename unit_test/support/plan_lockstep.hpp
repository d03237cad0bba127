// The plan executive in lockstep, with the test (or the benchmark) as the
// operator: the flight software and the simulator (sim::LockstepRig) with an
// authenticated in-memory ground station (sim::MemoryGround) that keeps the
// last PLAN_EXEC packet; plans go up as the ground sends them, PLAN_LOAD
// chunks of 200 B (one every 20 ms) then PLAN_START with the text's length
// and CRC-32. Shared by unit_test/system/lockstep/test_lockstep_plan_executive.cpp
// and unit_test/bench/bench_plan_executive.cpp. Host side; one session at a
// time (the rig's frame callback drains this session's downlink).
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/core/crc32.hpp"
#include "ground/telemetry_decoder.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/memory_ground.hpp"

namespace rse::test {

inline std::string readTextFile(const char* path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class PlanLockstep {
public:
    static constexpr std::size_t kChunkBytes = 200;

    explicit PlanLockstep(const sim::Scenario& scenario)
        : ground_(std::make_unique<sim::MemoryGround>()), rig_(std::make_unique<sim::LockstepRig>(scenario)) {
        ground_->keepApid(cmdtlm::PLAN_EXEC_Tlm::kApid);
    }
    ~PlanLockstep() {
        if (active() == ground_.get()) {
            active() = nullptr;
        }
    }
    PlanLockstep(const PlanLockstep&) = delete;
    PlanLockstep& operator=(const PlanLockstep&) = delete;

    // Initialises the rig (the console in memory, or quiet), waits for the
    // six drives (3 s at most), sets AUTONOMOUS and runs 100 ms. nullptr when
    // all went well, else what did not.
    const char* start(bool quiet = false) {
        if (!core::isOk(rig_->fsw().addGroundLink(&ground_->link()))) {
            return "ground link not added";
        }
        if (!core::isOk(quiet ? rig_->init(nullptr) : rig_->init())) {
            return "rig init failed";
        }
        active() = ground_.get();
        rig_->setOnFrame(drain);
        if (!rig_->runUntil([&] { return rig_->allDrivesOperational(); }, 3 * core::kNsPerSec)) {
            return "drives not operational within 3 s";
        }
        if (!ground_->setMode(2)) {  // AUTONOMOUS
            return "SET_MODE not sent";
        }
        rig_->runFor(100 * core::kNsPerMs);
        return nullptr;
    }

    // PLAN_LOAD in 200-byte chunks (one every 20 ms), then PLAN_START (its
    // CRC-32 xored with crcXor: a bad CRC when not 0). The start is queued,
    // not yet run. False when a command could not be sent.
    bool uplink(const std::string& text, std::uint32_t crcXor = 0) {
        for (std::size_t at = 0; at < text.size(); at += kChunkBytes) {
            const std::size_t n = text.size() - at < kChunkBytes ? text.size() - at : kChunkBytes;
            std::uint8_t args[2 + kChunkBytes];
            core::BeWriter w(args, sizeof args);
            w.u16(static_cast<std::uint16_t>(at));
            w.bytes(reinterpret_cast<const std::uint8_t*>(text.data() + at), n);
            if (!ground_->send("PLAN_LOAD", args, 2 + n)) {
                return false;
            }
            rig_->runFor(20 * core::kNsPerMs);
        }
        std::uint8_t args[8];
        core::BeWriter w(args, sizeof args);
        w.u32(static_cast<std::uint32_t>(text.size()));
        w.u32(core::crc32(text.data(), text.size()) ^ crcXor);
        return ground_->send("PLAN_START", args, sizeof args);
    }

    sim::LockstepRig& rig() { return *rig_; }
    sim::MemoryGround& ground() { return *ground_; }
    msg::PlanExecutiveState state() const { return rig_->fsw().planExecutive().state(); }
    bool complete() const { return state() == msg::PlanExecutiveState::kComplete; }
    // The last PLAN_EXEC packet the ground received, decoded.
    ground::DecodedPacket planExec() const { return ground::decodeTelemetry(ground_->kept(), ground_->keptLength()); }

private:
    static sim::MemoryGround*& active() {
        static sim::MemoryGround* ground = nullptr;
        return ground;
    }
    static void drain(sim::LockstepRig&) {
        if (active() != nullptr) {
            active()->drainDownlink();
        }
    }

    std::unique_ptr<sim::MemoryGround> ground_;
    std::unique_ptr<sim::LockstepRig> rig_;  // after ground_: destroyed first (it holds the ground's link)
};

}  // namespace rse::test

// Test rig for the CiA 402 drive emulator: an in-memory CAN bus on a virtual
// clock, one endpoint for the emulator (node 5) and one that plays the master
// with hand-built frames. Nothing here allocates: the rig is also used to show
// that the emulator does not.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "sim_stub/drives/cia402_drive_emulator.hpp"

namespace rse::test {

constexpr std::uint8_t kNode = 5;
constexpr core::TimeNs kCycle = 10 * core::kNsPerMs;

inline hal::CanFrame makeFrame(std::uint32_t id, std::uint8_t dlc, const std::uint8_t* data = nullptr) {
    hal::CanFrame f;
    f.id = id;
    f.dlc = dlc;
    for (std::uint8_t i = 0; i < dlc && i < 8 && data != nullptr; ++i) {
        f.data[i] = data[i];
    }
    return f;
}

struct Tpdo {
    bool present = false;
    std::uint16_t statusword = 0;
    std::int32_t velocity = 0;
    std::int16_t current = 0;
};

// Every frame one step produced (up to 32).
struct Captured {
    hal::CanFrame frames[32];
    std::size_t count = 0;
    bool find(std::uint32_t id, hal::CanFrame* out) const {
        for (std::size_t i = 0; i < count; ++i) {
            if (frames[i].id == id) {
                *out = frames[i];
                return true;
            }
        }
        return false;
    }
    std::size_t countId(std::uint32_t id) const {
        std::size_t n = 0;
        for (std::size_t i = 0; i < count; ++i) {
            n += frames[i].id == id ? 1U : 0U;
        }
        return n;
    }
};

struct DriveRig {
    core::VirtualClock clock;
    hal::MemoryCanBus wire{clock};
    hal::MemoryCanEndpoint* master = wire.attach("master");
    hal::MemoryCanEndpoint* driveEnd = wire.attach("drive");
    sim::Cia402DriveEmulator drive;

    explicit DriveRig(const sim::DriveEmulatorConfig& config = {}) : drive(*driveEnd, kNode, config) {}

    void send(const hal::CanFrame& f) { (void)master->send(f); }
    void send(std::uint32_t id, std::uint8_t dlc, const std::uint8_t* data = nullptr) { send(makeFrame(id, dlc, data)); }
    void nmt(std::uint8_t command, std::uint8_t node) {
        const std::uint8_t b[2] = {command, node};
        send(0x000, 2, b);
    }
    void sync() { send(0x080, 0); }
    void rpdo(std::uint16_t controlword, std::int32_t velocity) {
        std::uint8_t b[6] = {};
        b[0] = static_cast<std::uint8_t>(controlword & 0xFF);
        b[1] = static_cast<std::uint8_t>(controlword >> 8);
        const auto v = static_cast<std::uint32_t>(velocity);
        for (int i = 0; i < 4; ++i) {
            b[2 + i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF);
        }
        send(0x200 + kNode, 6, b);
    }

    // Steps the emulator at the current time, or after advancing the clock.
    void step() { drive.step(clock.now()); }
    void advance(core::TimeNs dt) {
        clock.advance(dt);
        step();
    }
    // Steps every cycle for `duration`, without traffic from the master.
    void idle(core::TimeNs duration) {
        for (core::TimeNs t = 0; t < duration; t += kCycle) {
            advance(kCycle);
        }
    }

    bool receive(hal::CanFrame* f) { return core::isOk(master->receive(f)); }
    // Drops everything the drive has sent so far; returns how many frames.
    std::size_t drain() {
        hal::CanFrame f;
        std::size_t n = 0;
        while (n < 10000 && receive(&f)) {
            ++n;
        }
        return n;
    }
    // The next frame with this id, skipping others (nullptr-safe), or false.
    bool receiveId(std::uint32_t id, hal::CanFrame* out) {
        hal::CanFrame f;
        for (std::size_t n = 0; n < 10000 && receive(&f); ++n) {
            if (f.id == id) {
                *out = f;
                return true;
            }
        }
        return false;
    }

    // One 10 ms master cycle: clock advances, RPDO1 then SYNC, the drive steps;
    // returns the TPDO1 it answered with (other frames are dropped).
    Tpdo cycle(std::uint16_t controlword, std::int32_t velocity) {
        clock.advance(kCycle);
        rpdo(controlword, velocity);
        sync();
        step();
        return readTpdo();
    }
    // The same cycle, keeping every frame the drive sent (EMCY, TPDO1, heartbeat ...).
    Captured cycleAll(std::uint16_t controlword, std::int32_t velocity) {
        clock.advance(kCycle);
        rpdo(controlword, velocity);
        sync();
        step();
        return capture();
    }
    Captured capture() {
        Captured c;
        while (c.count < 32 && receive(&c.frames[c.count])) {
            ++c.count;
        }
        return c;
    }
    static Tpdo decodeTpdo(const hal::CanFrame& f) {
        Tpdo t;
        t.present = f.dlc == 8;
        t.statusword = static_cast<std::uint16_t>(f.data[0] | (f.data[1] << 8));
        t.velocity = static_cast<std::int32_t>(static_cast<std::uint32_t>(f.data[2]) |
                                               (static_cast<std::uint32_t>(f.data[3]) << 8) |
                                               (static_cast<std::uint32_t>(f.data[4]) << 16) |
                                               (static_cast<std::uint32_t>(f.data[5]) << 24));
        t.current = static_cast<std::int16_t>(f.data[6] | (f.data[7] << 8));
        return t;
    }
    Tpdo readTpdo() {
        hal::CanFrame f;
        if (receiveId(0x180 + kNode, &f)) {
            return decodeTpdo(f);
        }
        return Tpdo{};
    }

    // One SDO request (8 bytes) and the drive's answer in the same step.
    bool sdo(const std::uint8_t (&request)[8], hal::CanFrame* response) {
        send(0x600 + kNode, 8, request);
        step();
        return receiveId(0x580 + kNode, response);
    }
    bool sdoDownload(std::uint16_t index, std::uint8_t sub, std::uint32_t value, std::uint8_t size,
                     hal::CanFrame* response) {
        const std::uint8_t b[8] = {static_cast<std::uint8_t>(0x23 | ((4 - size) << 2)),
                                   static_cast<std::uint8_t>(index & 0xFF),
                                   static_cast<std::uint8_t>(index >> 8),
                                   sub,
                                   static_cast<std::uint8_t>(value & 0xFF),
                                   static_cast<std::uint8_t>((value >> 8) & 0xFF),
                                   static_cast<std::uint8_t>((value >> 16) & 0xFF),
                                   static_cast<std::uint8_t>((value >> 24) & 0xFF)};
        return sdo(b, response);
    }
    bool sdoUpload(std::uint16_t index, std::uint8_t sub, hal::CanFrame* response) {
        const std::uint8_t b[8] = {0x40, static_cast<std::uint8_t>(index & 0xFF), static_cast<std::uint8_t>(index >> 8),
                                   sub, 0, 0, 0, 0};
        return sdo(b, response);
    }
    // Expedited upload value (0xFFFFFFFF when anything else came back).
    std::uint32_t uploadValue(std::uint16_t index, std::uint8_t sub) {
        hal::CanFrame r;
        if (!sdoUpload(index, sub, &r) || (r.data[0] & 0xE3) != 0x43) {
            return 0xFFFFFFFF;
        }
        std::uint32_t v = 0;
        for (int i = 0; i < 4; ++i) {
            v |= static_cast<std::uint32_t>(r.data[4 + i]) << (8 * i);
        }
        return v;
    }
    // Abort code of a response, 0 if it is not an abort.
    static std::uint32_t abortCode(const hal::CanFrame& r) {
        if (r.data[0] != 0x80) {
            return 0;
        }
        return static_cast<std::uint32_t>(r.data[4]) | (static_cast<std::uint32_t>(r.data[5]) << 8) |
               (static_cast<std::uint32_t>(r.data[6]) << 16) | (static_cast<std::uint32_t>(r.data[7]) << 24);
    }

    // Power on and boot (boot-up frame dropped).
    void boot() {
        drive.powerOn();
        step();
        drain();
    }
    // The ICD start-up: boot, heartbeat 100 ms, mode 3, NMT start; all answers dropped.
    void configureAndStart() {
        boot();
        hal::CanFrame r;
        (void)sdoDownload(0x1017, 0, 100, 2, &r);
        (void)sdoDownload(0x6060, 0, 3, 1, &r);
        nmt(0x01, kNode);
        advance(kCycle);
        drain();
    }
    // configureAndStart, then shutdown / switch on / enable operation.
    void enable() {
        configureAndStart();
        (void)cycle(0x0006, 0);
        (void)cycle(0x0007, 0);
        (void)cycle(0x000F, 0);
        drain();
    }
};

}  // namespace rse::test

// The ground station of the FswApp tests: the whole flight application
// commanded over an in-memory link, commands in as CCSDS packets signed with
// the lab key, acknowledgements and telemetry out, decoded with the
// dictionary's descriptors (so these tests also check that the flight's
// telemetry matches the dictionary the ground reads). Used by
// test_ground_commands.cpp and test_ground_telemetry.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "fsw/app/app_events.hpp"
#include "fsw/app/fsw_app.hpp"
#include "fsw/cmdtlm/command_packet.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/tables/table_image.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/link/memory_packet_link.hpp"
#include "hal/nvm/record_store.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

namespace rse::test::ground {

using namespace rse::cmdtlm;


struct Packet {
    std::uint16_t apid = 0;
    std::vector<std::uint8_t> payload;
};

// Value of one field (element) of a telemetry payload, found by name in the dictionary.
inline double field(const Packet& p, const char* name, std::size_t element = 0) {
    const TelemetryDesc* t = findTelemetry(p.apid);
    CHECK(t != nullptr);
    core::BeReader r(p.payload.data(), p.payload.size());
    for (std::size_t i = 0; i < t->fieldCount; ++i) {
        const FieldDesc& f = t->fields[i];
        for (std::size_t e = 0; e < f.count; ++e) {
            const double v = readAsDouble(r, f.type);
            if (std::strcmp(f.name, name) == 0 && e == element) {
                return v;
            }
        }
    }
    FAIL(name);
    return 0.0;
}

// Takes what the flight software sent down the link so far (each packet
// checked against its dictionary size).
inline void collectDownlink(hal::MemoryPacketLink& link, std::vector<Packet>* received) {
    std::uint8_t bytes[hal::kMemoryLinkMaxPacket];
    std::size_t length = 0;
    while (core::isOk(link.groundReceive(bytes, sizeof bytes, &length))) {
        const PrimaryHeader h = decodePrimaryHeader(bytes);
        LONGS_EQUAL(length, h.dataLength + 7u);
        Packet p;
        p.apid = h.apid;
        p.payload.assign(bytes + kTelemetryHeaderSize, bytes + length);
        const TelemetryDesc* t = findTelemetry(h.apid);
        CHECK(t != nullptr);
        LONGS_EQUAL(t->payloadSize, p.payload.size());
        received->push_back(p);
    }
}

// Runs the flight software n frames, collecting what it sends down the link.
inline void runAndCollect(app::FswApp& fsw, hal::MemoryPacketLink& link, int n, std::vector<Packet>* received) {
    for (int i = 0; i < n; ++i) {
        fsw.run(nullptr, 1);
        collectDownlink(link, received);
    }
}

// The last packet of a kind received so far (fails if none).
inline const Packet& lastOf(const std::vector<Packet>& received, const char* name) {
    const TelemetryDesc* t = findTelemetry(name);
    for (auto it = received.rbegin(); it != received.rend(); ++it) {
        if (it->apid == t->apid) {
            return *it;
        }
    }
    FAIL(name);
    return received.front();
}


// The fixture: a started FswApp with the ground link, a probe on the wheel commands.
struct GroundStation : public Utest {
    core::VirtualClock clock;
    hal::MemoryCanBus can{clock};
    hal::MemoryPacketLink link;
    app::FswApp fsw{clock, *can.attach("fsw")};
    HmacSha256 hmac;
    std::uint32_t authSequence = 1;
    std::vector<Packet> received;
    core::PipeId probe = 0;

    void setup() override {
        CHECK(core::isOk(fsw.addGroundLink(&link)));
        CHECK(core::isOk(fsw.useLabKey()));  // a lab bench: asked for explicitly
        CHECK(core::isOk(fsw.init(nullptr)));
        CHECK(core::isOk(hmac.init()));
        CHECK(core::isOk(fsw.bus().createPipe("probe", 16, &probe)));
        CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kWheelCommand)));
    }

    void send(const char* name, const std::vector<std::uint8_t>& args = {}) {
        const CommandDesc* c = findCommand(name);
        CHECK(c != nullptr);
        CommandFields f;
        f.apid = c->apid;
        f.functionCode = c->functionCode;
        f.keyId = kLabKeyId;
        f.authSequence = authSequence++;
        std::uint8_t bytes[kMaxCommandPacket];
        const std::size_t n = encodeCommandPacket(f, args.data(), args.size(), kLabKey, hmac, bytes, sizeof bytes);
        CHECK(n > 0);
        CHECK(core::isOk(link.groundSend(bytes, n)));
    }
    void runFrames(int n) { runAndCollect(fsw, link, n, &received); }
    const Packet& last(const char* name) { return lastOf(received, name); }
    std::size_t countOf(const char* name) {
        std::size_t n = 0;
        for (const Packet& p : received) {
            n += p.apid == findTelemetry(name)->apid ? 1 : 0;
        }
        return n;
    }
    void expectAccepted(const char* name) {
        const Packet& ack = last("CMD_ACK");
        LONGS_EQUAL(findCommand(name)->apid, static_cast<long>(field(ack, "apid")));
        LONGS_EQUAL(0, static_cast<long>(field(ack, "reason")));
    }
    // EVENT packets received with this id.
    long eventCount(std::uint16_t id) {
        long n = 0;
        for (const Packet& p : received) {
            n += p.apid == findTelemetry("EVENT")->apid && static_cast<std::uint16_t>(field(p, "event_id")) == id ? 1 : 0;
        }
        return n;
    }
    // The rate-group row of a task, by the name TASK_TIMING gives it.
    std::size_t rowOf(const char* name) {
        const std::size_t row = fsw.executive().findTask(name);
        CHECK_TEXT(row < fsw.executive().taskCount(), name);
        return row;
    }
    std::vector<std::uint8_t> u16(std::uint16_t v) { return {static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v)}; }
    std::vector<std::uint8_t> f32s(std::initializer_list<float> values) {
        std::vector<std::uint8_t> out(values.size() * 4);
        core::BeWriter w(out.data(), out.size());
        for (float v : values) {
            w.f32(v);
        }
        return out;
    }
    // TABLE_LOAD in chunks of at most 40 bytes, then TABLE_VALIDATE.
    void uploadTable(const std::uint8_t* image, std::size_t length, std::uint16_t id) {
        for (std::size_t offset = 0; offset < length; offset += 40) {
            std::vector<std::uint8_t> args = u16(id);
            const std::vector<std::uint8_t> off = u16(static_cast<std::uint16_t>(offset));
            args.insert(args.end(), off.begin(), off.end());
            args.insert(args.end(), image + offset, image + std::min(length, offset + 40));
            send("TABLE_LOAD", args);
            runFrames(1);
            expectAccepted("TABLE_LOAD");
        }
        send("TABLE_VALIDATE", u16(id));
        runFrames(1);
    }
};

}  // namespace rse::test::ground

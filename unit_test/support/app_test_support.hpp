// Test helpers for the applications' commands and packers (the owners of
// APIDs and packet families, docs/architecture.md "Commands and telemetry by
// owner"): a telemetry sink that keeps what it was sent and reads its fields
// by dictionary name, a verdict as the command service hands an accepted
// command over, and a bus probe that takes one message type off a pipe.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include "fsw/cmdtlm/command_verdict.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/cmdtlm/telemetry_sink.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"

#include "CppUTest/TestHarness.h"

namespace rse::test {

class RecordingSink final : public cmdtlm::TelemetrySink {
public:
    struct Packet {
        std::uint16_t apid = 0;
        std::vector<std::uint8_t> payload;
    };

    void sendPayload(std::uint16_t apid, const std::uint8_t* payload, std::size_t length) override {
        packets.push_back(Packet{apid, std::vector<std::uint8_t>(payload, payload + length)});
    }

    // Packets of one kind sent so far.
    template <typename T>
    std::size_t count() const {
        std::size_t n = 0;
        for (const Packet& p : packets) {
            n += p.apid == T::kApid ? 1U : 0U;
        }
        return n;
    }
    // The last packet of one kind (fails the test if none).
    template <typename T>
    const Packet& last() const {
        for (auto it = packets.rbegin(); it != packets.rend(); ++it) {
            if (it->apid == T::kApid) {
                return *it;
            }
        }
        FAIL("no such packet sent");
        return packets.front();
    }
    // A field (element) of a packet, found by name in the dictionary.
    static double field(const Packet& p, const char* name, std::size_t element = 0) {
        const cmdtlm::TelemetryDesc* t = cmdtlm::findTelemetry(p.apid);
        CHECK(t != nullptr);
        LONGS_EQUAL(t->payloadSize, p.payload.size());
        core::BeReader r(p.payload.data(), p.payload.size());
        for (std::size_t i = 0; i < t->fieldCount; ++i) {
            const cmdtlm::FieldDesc& f = t->fields[i];
            for (std::size_t e = 0; e < f.count; ++e) {
                const double v = cmdtlm::readAsDouble(r, f.type);
                if (std::strcmp(f.name, name) == 0 && e == element) {
                    return v;
                }
            }
        }
        FAIL(name);
        return 0.0;
    }

    std::vector<Packet> packets;
    unsigned tooLarge = 0;

private:
    void reportTooLarge(std::uint16_t, std::size_t) override { ++tooLarge; }
};

// An accepted command with these arguments, as the command router hands it to
// the application that owns its APID. Keeps the argument bytes.
class AcceptedCommand {
public:
    template <typename Args>
    AcceptedCommand(cmdtlm::CommandCode code, const Args& args) {
        core::BeWriter w(bytes_, sizeof bytes_);
        cmdtlm::encodeArgs(w, args);
        CHECK(w.ok());
        init(code, w.size());
    }
    explicit AcceptedCommand(cmdtlm::CommandCode code) { init(code, 0); }
    AcceptedCommand(const AcceptedCommand&) = delete;
    AcceptedCommand& operator=(const AcceptedCommand&) = delete;

    const cmdtlm::CommandVerdict& verdict() const { return verdict_; }

private:
    void init(cmdtlm::CommandCode code, std::size_t length) {
        const cmdtlm::CommandDesc& d = cmdtlm::describe(code);
        verdict_.command = &d;
        verdict_.header.apid = d.apid;
        verdict_.functionCode = d.functionCode;
        verdict_.keyId = 1;
        verdict_.authSequence = 7;
        verdict_.args = bytes_;
        verdict_.argLength = length;
    }

    std::uint8_t bytes_[256] = {};
    cmdtlm::CommandVerdict verdict_{};
};

// Takes messages of type M off the bus (a pipe of its own).
template <typename M>
class BusProbe {
public:
    BusProbe(core::SoftwareBus& bus, const char* name) : bus_(bus) {
        CHECK(core::isOk(bus.createPipe(name, 8, &pipe_)));
        CHECK(core::isOk(bus.subscribe(pipe_, M::kMsgId)));
    }
    // How many are waiting; the last of them in *last (when any).
    unsigned drain(M* last = nullptr) {
        unsigned n = 0;
        core::Message m;
        while (core::isOk(bus_.receive(pipe_, &m))) {
            M decoded{};
            CHECK(core::isOk(m.decode(&decoded)));
            if (last != nullptr) {
                *last = decoded;
            }
            ++n;
        }
        return n;
    }

private:
    core::SoftwareBus& bus_;
    core::PipeId pipe_ = 0;
};

// The frame context of frame n (100 frames a second, as the flight's).
inline core::FrameContext frameAt(std::uint64_t n) {
    core::FrameContext f{};
    f.frame = n;
    f.slot = static_cast<std::uint32_t>(n % 100);
    f.actualStart = static_cast<core::TimeNs>(n) * 10 * core::kNsPerMs;
    f.scheduledStart = f.actualStart;
    return f;
}

// One packer as the telemetry task schedules it: its inputs routed on a pipe
// of its own; run() drains the pipe, then packs frame n into the sink.
class PackerRig {
public:
    explicit PackerRig(cmdtlm::TelemetryPacker& packer) : packer_(packer) {
        CHECK(core::isOk(pipe.create()));
        CHECK(core::isOk(packer.routeInputs(pipe)));
    }
    template <typename M>
    void publish(const M& message) {
        CHECK(core::isOk(bus.publish(message)));
    }
    // Frame n: the pipe drained, then the packer's pack() into sink.
    void run(std::uint64_t n) {
        (void)pipe.drain();
        packer_.pack(frameAt(n), sink);
    }
    // Frames first .. last, inclusive.
    void runFrames(std::uint64_t first, std::uint64_t last) {
        for (std::uint64_t n = first; n <= last; ++n) {
            run(n);
        }
    }

    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    core::InputPipe pipe{bus, events, core::InputPipeConfig{"telemetry", 16, 211, "telemetry"}};
    RecordingSink sink;

private:
    cmdtlm::TelemetryPacker& packer_;
};

}  // namespace rse::test

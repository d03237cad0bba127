// Test support for the ground tool: a fake rover that checks command packets
// with the flight's own CommandValidator (lab key, anti-replay window, modes) and
// answers as the flight does (one CMD_ACK per command, then an HK), reachable
// in memory (FakeRoverLink) or over UDP; a temporary directory; and the CLI run
// in memory (cli(), CliRig).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <dirent.h>
#include <unistd.h>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "hal/nvm/record_store.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/core/crc32.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/site_map/site_map_commands.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/command_encoder.hpp"
#include "ground/ground_cli.hpp"
#include "ground/ground_link.hpp"
#include "ground/ground_session.hpp"
#include "ground/sequence_store.hpp"

namespace rse::test {

// A packet as the flight's TelemetryOutput builds it.
template <typename T>
std::vector<std::uint8_t> telemetryPacket(const T& tlm, std::uint16_t sequence = 0, core::TimeNs time = 0) {
    std::uint8_t payload[cmdtlm::kMaxTelemetryPacket];
    core::BeWriter w(payload, sizeof payload);
    cmdtlm::encodeTelemetry(w, tlm);
    std::vector<std::uint8_t> packet(cmdtlm::kMaxTelemetryPacket);
    const std::size_t n = cmdtlm::buildTelemetryPacket(T::kApid, sequence, time, payload, w.size(), packet.data(),
                                                       packet.size());
    packet.resize(n);
    return packet;
}

class FakeRover {
public:
    FakeRover() : validator_(keys_, hmac_) {
        (void)hmac_.init();
        (void)keys_.add(cmdtlm::kLabKeyId, cmdtlm::kLabKey);
    }

    cmdtlm::Mode mode = cmdtlm::Mode::kStandby;
    std::vector<std::uint8_t> tableImage;     // what TABLE_DUMP sends
    std::vector<std::uint8_t> loadedImage;    // what TABLE_LOAD chunks built
    std::vector<cmdtlm::CommandVerdict> verdicts;
    std::vector<std::string> executed;        // names of accepted commands
    std::uint32_t accepted = 0;
    std::uint32_t rejected = 0;
    bool answer = true;                       // false: silent (no link)
    // The plan executive, as far as the ground sees it: PLAN_LOAD chunks
    // assembled (a gap spoils the upload, event 952, as the flight's), and
    // PLAN_START checked for length and CRC-32 then answered with planVerdict.
    std::string planText;                     // what PLAN_LOAD chunks built
    std::string planTaken;                    // the text of the last good PLAN_START or PLAN_SHORT
    std::size_t planChunks = 0;               // PLAN_LOAD commands accepted
    std::size_t planLoseChunk = SIZE_MAX;     // this chunk (0 first) acknowledged but lost (a full pipe)
    std::uint16_t planVerdict = 950;          // the event a good plan gets (953: parse refusal)
    bool planEvents = true;                   // false: the executive says nothing

    void setAuthRequired(bool required) { validator_.setAuthRequired(required); }
    // The flight's persisted anti-replay state over `store` (read now, as at start-up).
    void attachAuthStore(hal::RecordStore* store, std::uint64_t nonce) {
        validator_.replay().attach(store);
        validator_.replay().setChallengeSeed(nonce);
        validator_.replay().load(keys_, false);
    }

    // The telemetry the flight would send in answer to one command packet.
    std::vector<std::vector<std::uint8_t>> handle(const std::uint8_t* packet, std::size_t length) {
        std::vector<std::vector<std::uint8_t>> out;
        if (!answer) {
            return out;
        }
        cmdtlm::CommandVerdict v = validator_.check(packet, length, mode);
        std::vector<std::vector<std::uint8_t>> after;
        if (v.reason == cmdtlm::CommandReject::kAccepted) {
            execute(v, &after);
        }
        verdicts.push_back(v);
        cmdtlm::CMD_ACK_Tlm ack{};
        ack.apid = v.header.apid;
        ack.function_code = v.functionCode;
        ack.ccsds_sequence = v.header.sequenceCount;
        ack.key_id = v.keyId;
        ack.auth_sequence = v.authSequence;
        ack.reason = static_cast<std::uint8_t>(v.reason);
        ack.detail = v.detail;
        (v.reason == cmdtlm::CommandReject::kAccepted ? accepted : rejected)++;
        ack.accepted = accepted;
        ack.rejected = rejected;
        out.push_back(telemetryPacket(ack, static_cast<std::uint16_t>(verdicts.size())));
        out.insert(out.end(), after.begin(), after.end());
        out.push_back(housekeeping());
        return out;
    }
    // The HK the flight sends, with what the ground reads from it.
    std::vector<std::uint8_t> housekeeping() const {
        cmdtlm::HK_Tlm hk{};
        hk.mode = static_cast<std::uint8_t>(mode);
        hk.cmd_accepted = accepted;
        hk.cmd_rejected = rejected;
        const cmdtlm::AntiReplayState& replay = validator_.replay();
        hk.auth_store_state = static_cast<std::uint8_t>(replay.state());
        hk.auth_keys_unsynced = replay.unsynced(cmdtlm::kLabKeyId) == cmdtlm::Unsynced::kSynced ? 0 : 1;
        hk.auth_challenge_high = static_cast<std::uint32_t>(replay.challenge() >> 32);
        hk.auth_challenge_low = static_cast<std::uint32_t>(replay.challenge());
        return telemetryPacket(hk, static_cast<std::uint16_t>(verdicts.size()));
    }
    bool beacon = false;  // true: HK whenever the ground listens and nothing else is due (its 1 Hz HK)

private:
    void execute(cmdtlm::CommandVerdict& v, std::vector<std::vector<std::uint8_t>>* after) {
        core::BeReader r(v.args, v.argLength);
        executed.push_back(v.command->name);
        switch (v.command->code) {
            case cmdtlm::CommandCode::SET_MODE: {
                cmdtlm::SET_MODE_Args a{};
                cmdtlm::decodeArgs(r, &a);
                mode = static_cast<cmdtlm::Mode>(a.mode);
                break;
            }
            case cmdtlm::CommandCode::TABLE_LOAD: {
                cmdtlm::TABLE_LOAD_Args a{};
                cmdtlm::decodeArgs(r, &a);
                if (a.offset == 0) {
                    loadedImage.clear();
                }
                if (a.offset != loadedImage.size()) {
                    fail(v, tables::TableReject::kChunkGap);
                    return;
                }
                loadedImage.insert(loadedImage.end(), a.data, a.data + a.data_length);
                break;
            }
            case cmdtlm::CommandCode::TABLE_VALIDATE: {
                const tables::TableCheck check = tables::checkTableImage(loadedImage.data(), loadedImage.size());
                if (!check.ok()) {
                    fail(v, check.reason);
                }
                break;
            }
            case cmdtlm::CommandCode::TABLE_DUMP: {
                cmdtlm::TABLE_DUMP_Args a{};
                cmdtlm::decodeArgs(r, &a);
                for (std::size_t offset = 0; offset < tableImage.size(); offset += 200) {
                    cmdtlm::TABLE_DUMP_Tlm d{};
                    d.table_id = a.table_id;
                    d.buffer = a.buffer;
                    d.total_length = static_cast<std::uint16_t>(tableImage.size());
                    d.offset = static_cast<std::uint16_t>(offset);
                    d.length = static_cast<std::uint16_t>(std::min<std::size_t>(200, tableImage.size() - offset));
                    std::memcpy(d.data, tableImage.data() + offset, d.length);
                    after->push_back(telemetryPacket(d));
                }
                break;
            }
            case cmdtlm::CommandCode::PLAN_LOAD: {
                cmdtlm::PLAN_LOAD_Args a{};
                cmdtlm::decodeArgs(r, &a);
                if (planChunks++ == planLoseChunk) {
                    return;
                }
                planSpoiled_ = a.offset == 0 ? false : planSpoiled_;
                planText.resize(a.offset == 0 ? 0 : planText.size());
                if (planSpoiled_ || a.offset > planText.size()) {
                    planSpoiled_ = true;
                    planEvent(952, 3, "plan_exec: refused (gap): chunk beyond the text assembled so far", after);
                    return;
                }
                planText.resize(std::max<std::size_t>(planText.size(), a.offset + a.data_length));
                std::memcpy(&planText[a.offset], a.data, a.data_length);
                break;
            }
            case cmdtlm::CommandCode::PLAN_START: {
                cmdtlm::PLAN_START_Args a{};
                cmdtlm::decodeArgs(r, &a);
                if (planSpoiled_ || a.length != planText.size()) {
                    planEvent(952, 3, "plan_exec: refused (gap or bad length)", after);
                } else if (a.crc32 != core::crc32(planText.data(), planText.size())) {
                    planEvent(952, 3, "plan_exec: refused (bad CRC-32)", after);
                } else {
                    planTaken = planText;
                    planEvent(planVerdict, planVerdict == 950 ? 1 : 3, "plan_exec: verdict", after);
                }
                break;
            }
            case cmdtlm::CommandCode::MAP_LOAD:
            case cmdtlm::CommandCode::MAP_COMMIT:
            case cmdtlm::CommandCode::MAP_ABORT:
                siteMapCommand(v, after);
                break;
            case cmdtlm::CommandCode::PLAN_SHORT: {
                cmdtlm::PLAN_SHORT_Args a{};
                cmdtlm::decodeArgs(r, &a);
                planTaken.assign(reinterpret_cast<const char*>(a.text), a.text_length);
                planEvent(planVerdict, planVerdict == 950 ? 1 : 3, "plan_exec: verdict", after);
                break;
            }
            default:
                break;
        }
    }
    void planEvent(std::uint16_t id, std::uint8_t severity, const char* text,
                   std::vector<std::vector<std::uint8_t>>* after) const {
        if (!planEvents) {
            return;
        }
        cmdtlm::EVENT_Tlm e{};
        e.event_id = id;
        e.severity = severity;
        std::strncpy(e.text, text, sizeof e.text - 1);
        after->push_back(telemetryPacket(e));
    }
    static void fail(cmdtlm::CommandVerdict& v, tables::TableReject reason) {
        v.reason = cmdtlm::CommandReject::kExecutionFailed;
        v.detail = static_cast<std::int16_t>(reason);
    }

    // The site map commands, as the flight's own service takes them: its
    // SITE_MAP answers follow the CMD_ACK. An accepted MAP_COMMIT's slices
    // run at once, a command-task run each, until the SITE_MAP of its end.
    struct SiteMapRig {
        struct Sink final : cmdtlm::TelemetrySink {
            std::vector<std::vector<std::uint8_t>> packets;
            void sendPayload(std::uint16_t apid, const std::uint8_t* payload, std::size_t length) override {
                std::vector<std::uint8_t> packet(cmdtlm::kMaxTelemetryPacket);
                packet.resize(cmdtlm::buildTelemetryPacket(apid, 0, 0, payload, length, packet.data(), packet.size()));
                packets.push_back(packet);
            }
            void reportTooLarge(std::uint16_t, std::size_t) override {}
        };
        core::VirtualClock clock;
        core::EventLog events{clock};
        Sink sink;
        site_map::SiteMapService service{events};
        site_map::SiteMapTelemetry telemetry{service};
        site_map::SiteMapCommands commands{service, telemetry, sink};
    };
    void siteMapCommand(cmdtlm::CommandVerdict& v, std::vector<std::vector<std::uint8_t>>* after) {
        if (!siteMap_) {
            siteMap_ = std::make_unique<SiteMapRig>();  // 6 MB: off the stack
        }
        SiteMapRig& m = *siteMap_;
        m.sink.packets.clear();
        const cmdtlm::CommandOutcome out = m.commands.execute(v);
        if (!out.ok) {
            v.reason = cmdtlm::CommandReject::kExecutionFailed;
            v.detail = out.detail;
        }
        for (int run = 0; run < 1000 && m.service.commitPhase() != site_map::CommitPhase::kNone; ++run) {
            m.commands.serviceOnboardRequests(mode);
            ++siteMapCommitRuns;
        }
        after->insert(after->end(), m.sink.packets.begin(), m.sink.packets.end());
    }

public:
    std::size_t siteMapCommitRuns = 0;   // command-task runs MAP_COMMITs took
    const site_map::SiteMapService* siteMapService() const { return siteMap_.get() != nullptr ? &siteMap_->service : nullptr; }

private:
    std::unique_ptr<SiteMapRig> siteMap_;
    cmdtlm::KeyStore keys_;
    cmdtlm::HmacSha256 hmac_;
    cmdtlm::CommandValidator validator_;
    bool planSpoiled_ = false;
};

// The fake rover behind an in-memory GroundLink.
class FakeRoverLink final : public ground::GroundLink {
public:
    explicit FakeRoverLink(FakeRover& rover) : rover_(rover) {}

    void send(const std::vector<std::uint8_t>& packet) override {
        sent.push_back(packet);
        for (auto& tlm : rover_.handle(packet.data(), packet.size())) {
            queue.push_back(std::move(tlm));
        }
    }
    std::optional<std::vector<std::uint8_t>> receive(double timeoutSeconds) override {
        if (queue.empty() && rover_.beacon) {
            return rover_.housekeeping();
        }
        if (queue.empty()) {
            // Nothing will come: let the time pass (in small steps for callers' deadlines).
            const double step = std::min(timeoutSeconds, 0.01);
            if (step > 0.0) {
                std::this_thread::sleep_for(std::chrono::duration<double>(step));
            }
            return std::nullopt;
        }
        std::vector<std::uint8_t> packet = std::move(queue.front());
        queue.pop_front();
        return packet;
    }
    std::string describe() const override { return "fake rover"; }

    std::deque<std::vector<std::uint8_t>> queue;
    std::vector<std::vector<std::uint8_t>> sent;

private:
    FakeRover& rover_;
};

// A fresh directory under /tmp, removed (one level deep) when the test ends.
class TempDir {
public:
    TempDir() {
        char pattern[] = "/tmp/rse_ground_test_XXXXXX";
        const char* made = ::mkdtemp(pattern);
        path_ = made != nullptr ? made : "/tmp";
    }
    ~TempDir() {
        if (DIR* d = ::opendir(path_.c_str())) {
            while (const dirent* e = ::readdir(d)) {
                const std::string name = e->d_name;
                if (name != "." && name != "..") {
                    ::unlink((path_ + "/" + name).c_str());
                }
            }
            ::closedir(d);
        }
        ::rmdir(path_.c_str());
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }
    std::string file(const std::string& name) const { return path_ + "/" + name; }

private:
    std::string path_;
};

// A ground session (lab key, acknowledgements waited for 0.3 s) on the fake
// rover, with its own state directory; what it prints captured.
struct SessionRig {
    FakeRover rover;
    FakeRoverLink link{rover};
    TempDir dir;
    ground::SequenceStore store{dir.path()};
    ground::GroundSession session{link, store, ground::labKeyAuth(), 0.3};
    std::ostringstream out;
    std::ostringstream err;
};

// A file's bytes ("" when it cannot be read).
inline std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A plan padded with comment lines before its last line ("end") to exactly
// `size` bytes: the same plan to the parser, as long as asked.
inline std::string paddedPlan(const std::string& plan, std::size_t size) {
    const std::size_t end = plan.rfind("end");
    std::string head = plan.substr(0, end);
    const std::string tail = plan.substr(end);
    while (head.size() + tail.size() < size) {
        const std::size_t room = size - head.size() - tail.size();
        const std::size_t line = room < 80 ? room : 80;
        head += line == 1 ? std::string("\n") : "#" + std::string(line - 2, 'x') + "\n";
    }
    return head + tail;
}

// rse-ground's command line in memory: argv from args, out and err captured;
// with a factory, the links the CLI opens are the factory's.
struct CliResult {
    int rc = -1;
    std::string out;
    std::string err;
};

inline CliResult cli(std::vector<std::string> args, const ground::LinkFactory& factory = ground::LinkFactory()) {
    args.insert(args.begin(), "rse-ground");
    std::vector<char*> argv;
    for (std::string& a : args) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    std::ostringstream out;
    std::ostringstream err;
    CliResult r;
    r.rc = factory ? ground::runGroundCli(static_cast<int>(args.size()), argv.data(), out, err, factory)
                   : ground::runGroundCli(static_cast<int>(args.size()), argv.data(), out, err);
    r.out = out.str();
    r.err = err.str();
    return r;
}

// Hands the CLI a link the test keeps (the CLI owns what it gets).
class BorrowedLink final : public ground::GroundLink {
public:
    explicit BorrowedLink(ground::GroundLink& inner) : inner_(inner) {}
    void send(const std::vector<std::uint8_t>& packet) override { inner_.send(packet); }
    std::optional<std::vector<std::uint8_t>> receive(double timeoutSeconds) override {
        return inner_.receive(timeoutSeconds);
    }
    std::string describe() const override { return inner_.describe(); }

private:
    ground::GroundLink& inner_;
};

// The CLI against the fake rover (no sockets, no threads: the aarch64 suite runs
// under qemu-user), with its own state directory.
struct CliRig {
    test::FakeRover rover;
    test::FakeRoverLink link{rover};
    test::TempDir dir;
    int linksOpened = 0;
    bool lastListen = false;

    CliResult run(std::vector<std::string> args) {
        args.insert(args.begin(), {"--state-dir", dir.path()});
        const ground::LinkFactory factory = [this](bool listen) -> std::unique_ptr<ground::GroundLink> {
            ++linksOpened;
            lastListen = listen;
            return std::make_unique<BorrowedLink>(link);
        };
        return cli(args, factory);
    }
};

}  // namespace rse::test

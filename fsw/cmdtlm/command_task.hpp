// The command service (cFS's command ingest plus dispatch), every minor frame:
//   1 ingest: take up to kMaxPacketsPerLink packets from each ground link into a
//     fixed queue of kCommandQueueDepth; a packet that finds the queue full is
//     rejected (queue_overflow), acknowledged, evented and counted - never lost
//     silently. Packets beyond kMaxPacketsPerLink wait in the link's own buffer.
//   2 dispatch: up to kCommandsPerFrame queued packets are checked
//     (CommandValidator: length, header, checksum, APID and function code, key,
//     MAC, anti-replay sequence, argument ranges, mode) and, when they pass,
//     executed by the application's CommandHandler.
// Every packet yields exactly one CMD_ACK in telemetry: accepted, or the reason
// (an unknown key id acknowledged and evented as bad_mac: linkReason()).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_handler.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/ground_links.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::cmdtlm {

constexpr std::size_t kCommandQueueDepth = 8;    // commands waiting between frames
constexpr std::size_t kMaxPacketsPerLink = 16;   // ingest bound per link per frame
constexpr std::size_t kCommandsPerFrame = 2;     // executed per frame (200 commands/s)
constexpr std::uint32_t kRejectEventsPerSecond = 8;  // beyond this, rejections are counted, not evented

struct CommandCounters {
    std::uint32_t accepted = 0;
    std::uint32_t rejected = 0;
    std::uint32_t byReason[kRejectReasonCount] = {};
    std::uint32_t rejectEventsSuppressed = 0;
    std::uint16_t lastApid = 0;
    std::uint8_t lastFunctionCode = 0;
    CommandReject lastResult = CommandReject::kAccepted;
    std::uint8_t queueDepth = 0;
    std::uint8_t queueHighWater = 0;
};

class CommandTask final : public core::Task {
public:
    CommandTask(const core::Clock& clock, core::EventLog& events, const GroundLinks& links,
                TelemetryOutput& telemetry, CommandHandler& handler);

    // Start-up: the MAC engine (its one allocation) and the events that say how
    // commanding is secured.
    core::Status init();
    KeyStore& keys() { return keys_; }
    void setAuthRequired(bool required) { validator_.setAuthRequired(required); }
    bool authRequired() const { return validator_.authRequired(); }
    // Before init: where the anti-replay reservations persist (none: volatile,
    // RAM only), and whether init may create a missing store / add missing keys
    // at floor 0 (first boot only: rse-fsw --auth-store-create).
    void attachAuthStore(hal::RecordStore* store, bool provision) {
        validator_.replay().attach(store);
        provisionAuthStore_ = provision;
    }
    // Before or after init: the AUTH_RESYNC nonce's start (a random value per boot).
    void setAuthChallengeSeed(std::uint64_t seed) { validator_.replay().setChallengeSeed(seed); }
    const AntiReplayState& antiReplay() const { return validator_.replay(); }
    const KeyStore& keys() const { return keys_; }
    // Loaded keys refused until AUTH_RESYNC.
    std::uint8_t keysUnsynced() const;
    bool labKeyInUse() const { return keys_.labKeyInUse(); }

    void run(const core::FrameContext& frame) override;

    const CommandCounters& counters() const { return counters_; }
    void resetCounters();

private:
    struct QueuedPacket {
        std::uint8_t bytes[kMaxCommandPacket];
        std::uint16_t length;
    };

    void reportAntiReplayState();  // init: reads the store, events what it found
    void ingest();
    void dispatchOne();
    void acknowledge(const CommandVerdict& verdict);
    void reject(const CommandVerdict& found);
    // Header fields of a packet we will not validate (queue overflow, too long),
    // read as far as the bytes allow, for the acknowledgement.
    static CommandVerdict claimedFields(const std::uint8_t* packet, std::size_t length);

    const core::Clock& clock_;
    core::EventLog& events_;
    TelemetryOutput& telemetry_;
    CommandHandler& handler_;
    HmacSha256 hmac_;
    KeyStore keys_;
    CommandValidator validator_;
    const GroundLinks& links_;
    QueuedPacket queue_[kCommandQueueDepth] = {};
    std::size_t head_ = 0;
    std::size_t count_ = 0;
    std::uint8_t scratch_[kMaxCommandPacket + 1] = {};  // one byte more: detects oversize packets
    CommandCounters counters_;
    core::TimeNs rejectWindowStart_ = 0;
    std::uint32_t rejectEventsInWindow_ = 0;
    bool provisionAuthStore_ = false;
};

}  // namespace rse::cmdtlm

// A ground station for lockstep runs (tests, rse-demo): authenticated command
// packets (the dictionary's names, the lab key) into the flight software over an
// in-memory packet link, and the downlink drained (counted, not decoded) so it
// never fills. Add link() to the FswApp before LockstepRig::init(). Host side:
// HMAC-SHA-256 through mbedTLS (LDLIBS_CRYPTO).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_packet.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "hal/link/memory_packet_link.hpp"

namespace rse::sim {

class MemoryGround {
public:
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
        }
    }
    std::uint32_t downlinked() const { return downlinked_; }

private:
    hal::MemoryPacketLink link_;
    cmdtlm::HmacSha256 hmac_;
    bool hmacReady_ = false;
    std::uint32_t authSequence_ = 1;
    std::uint32_t downlinked_ = 0;
    std::uint8_t buffer_[hal::kMemoryLinkMaxPacket] = {};
};

}  // namespace rse::sim

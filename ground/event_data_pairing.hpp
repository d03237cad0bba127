// Pairs each EVENT_DATA packet with its EVENT packet (fsw/cmdtlm/dictionary.def,
// "Event data"): by event_sequence and event id, in the order the packets were
// received. The flight sends an event's EVENT_DATA right after its EVENT at the
// same priority, so a pair is near; the pairing still copes with what a link
// does to them:
//   - an EVENT_DATA whose EVENT never came (lost, or beyond the window below):
//     stray, counted, its numbers dropped;
//   - an EVENT whose id carries numbers but whose EVENT_DATA never came (lost,
//     or withheld by the rover: EVENT_DATA.data_withheld): counted as missing
//     (while it is still awaited too); the event is read without numbers;
//   - the rover restarted (sequences begin again): the latest EVENT with the
//     sequence is the one paired.
// Bounded: the kPairingWindow latest events awaiting numbers are kept.
// Host only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>

#include "fsw/core/event_log.hpp"
#include "ground/telemetry_decoder.hpp"

namespace rse::ground {

// One EVENT_DATA packet's content.
struct EventDataPacket {
    std::uint32_t sequence = 0;
    std::uint16_t id = 0;
    core::EventData data;
    std::uint32_t withheld = 0;  // EVENT_DATA.data_withheld
};
// False when the packet is no decoded EVENT_DATA.
bool readEventData(const DecodedPacket& packet, EventDataPacket* out);

class EventDataPairing {
public:
    static constexpr std::size_t kPairingWindow = 256;

    // An EVENT received; handle: the caller's name for it (an index), handed
    // back when its numbers come.
    void onEvent(std::uint32_t sequence, std::uint16_t id, std::size_t handle);
    // An EVENT_DATA received: the handle of its EVENT, or nullopt (stray).
    std::optional<std::size_t> onData(const EventDataPacket& data);

    std::uint32_t paired() const { return paired_; }
    std::uint32_t stray() const { return stray_; }
    // Events whose id carries numbers that have none (yet).
    std::uint32_t missing() const { return expected_ - paired_; }
    std::uint32_t withheld() const { return withheld_; }  // the rover's count, as last received

private:
    struct Awaiting {
        std::uint32_t sequence;
        std::uint16_t id;
        std::size_t handle;
    };
    std::deque<Awaiting> awaiting_;
    std::uint32_t expected_ = 0;
    std::uint32_t paired_ = 0;
    std::uint32_t stray_ = 0;
    std::uint32_t withheld_ = 0;
};

}  // namespace rse::ground

// Event ids raised by the ground-link transports (hal/link, and the ISO-TP ground
// link fsw/io/can_ground_link): range 370-389. For docs/icd.md (events table).
//
// Conditions a peer or a busy network can cause packet after packet (drops, full
// queues, OS errors on send or receive, refusals) are evented on their 1st, 2nd,
// 4th, 8th ... occurrence (core::isReportableOccurrence), each reason with its own
// count; every occurrence is counted in PacketLinkStats. Opening, closing and
// redirecting a link are evented every time. The in-memory link only counts (as
// MemoryCanBus does): it stands in for a wire in tests and the lockstep demo.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::hal::events {

constexpr core::EventId kLinkOpenFailed = 370;          // socket, option or bind failed (errno in the text): link closed
constexpr core::EventId kLinkBadAddress = 371;          // not a numeric IPv4 address, or telemetry port 0: refused
constexpr core::EventId kLinkOpened = 372;              // link open: where commands arrive, where telemetry goes
constexpr core::EventId kLinkTelemetryRedirected = 373; // telemetry destination changed by the operator
constexpr core::EventId kLinkRxTooLarge = 374;          // received packet larger than the reader's buffer: dropped
constexpr core::EventId kLinkRxError = 375;             // OS error on receive
constexpr core::EventId kLinkTxFull = 376;              // send refused: transmit queue or socket buffer full
constexpr core::EventId kLinkTxError = 377;             // OS error on send: packet not sent
constexpr core::EventId kLinkTxUndeliverable = 378;     // the network reported a sent packet undeliverable (ICMP)
constexpr core::EventId kLinkTxInvalid = 379;           // send of an empty packet or one over the link's limit refused
constexpr core::EventId kLinkClosed = 380;              // link closed (close() or destructor)
constexpr core::EventId kLinkRxKernelDrops = 381;       // the OS dropped received datagrams (receive buffer full)
constexpr core::EventId kLinkRxDegraded = 382;          // open: receive buffer smaller than asked, or kernel drops uncountable

}  // namespace rse::hal::events

// Event ids raised by hal/can: the link (300-349) and ISO-TP (350-399). Documented in docs/icd.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::hal::events {

constexpr core::EventId kCanStateChanged = 301;  // error-active/warning/passive/bus-off/down
constexpr core::EventId kCanRxOverrun = 302;     // frames lost before they were read
constexpr core::EventId kCanTxRefused = 303;     // send refused: queue full, link down, bus-off
constexpr core::EventId kCanTxInvalid = 304;     // send of a malformed frame refused
constexpr core::EventId kCanOpenFailed = 305;    // a SocketCAN interface could not be opened

// ISO-TP (range 350-399): one id per error reason of IsoTpChannel (hal/can/isotp.hpp).
// Peer-provoked and send()-misuse reasons are evented on their 1st, 2nd, 4th ...
// occurrence; timeouts and refused transmissions every time. Each has a counter in
// IsoTpStats.
constexpr core::EventId kIsoTpConfigInvalid = 350;       // channel config rejected: channel inert
constexpr core::EventId kIsoTpWrongSequence = 351;       // CF with a wrong sequence number: reception aborted
constexpr core::EventId kIsoTpUnexpectedCf = 352;        // CF with no reception in progress: ignored
constexpr core::EventId kIsoTpUnexpectedFc = 353;        // FC with no transmission waiting for one: ignored
constexpr core::EventId kIsoTpRxAbortedByNew = 354;      // SF/FF during a reception: old one abandoned
constexpr core::EventId kIsoTpTimeoutAs = 355;           // N_As: bus did not take our frame: tx aborted
constexpr core::EventId kIsoTpTimeoutAr = 356;           // N_Ar: bus did not take our FC: rx aborted
constexpr core::EventId kIsoTpTimeoutBs = 357;           // N_Bs: no FC from the receiver: tx aborted
constexpr core::EventId kIsoTpTimeoutCr = 358;           // N_Cr: no CF from the sender: rx aborted
constexpr core::EventId kIsoTpPeerOverflow = 359;        // receiver answered FC OVERFLOW: tx aborted
constexpr core::EventId kIsoTpWaitLimit = 360;           // more than N_WFTmax FC.WAIT: tx aborted
constexpr core::EventId kIsoTpRxTooLong = 361;           // FF longer than our buffer: FC OVERFLOW sent
constexpr core::EventId kIsoTpFfTooShort = 362;          // FF with FF_DL < 8: ignored
constexpr core::EventId kIsoTpMalformed = 363;           // DLC too small, bad SF_DL, unknown N_PCI: ignored
constexpr core::EventId kIsoTpInvalidFlowStatus = 364;   // FC flow status 3..15: tx aborted
constexpr core::EventId kIsoTpRxOverrun = 365;           // completed message dropped: receive FIFO full
constexpr core::EventId kIsoTpSendBusy = 366;            // send() while a transmission is in progress
constexpr core::EventId kIsoTpSendInvalid = 367;         // send() of 0 or > 4095 bytes

}  // namespace rse::hal::events

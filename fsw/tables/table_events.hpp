// Event ids raised by fsw/tables (range 560-599). Documented in docs/tables.md.
//
// Every rejection has the id of its reason, 570 + TableReject, so the id alone
// tells an operator why a load, validate or activate was refused; the text names
// the table, the operation and, for a field fault, the field.
#pragma once

#include "fsw/core/event_log.hpp"
#include "fsw/tables/table_image.hpp"

namespace rse::tables::events {

constexpr core::EventId kTableActivated = 560;       // INFO: pending image applied at a frame boundary
constexpr core::EventId kTableValidated = 561;       // INFO: inactive image passed every check
constexpr core::EventId kTableLoaded = 562;          // INFO: inactive buffer holds as many bytes as its header says
constexpr core::EventId kTableStartupActive = 563;   // INFO: start-up image activated (one per table)
constexpr core::EventId kTableAborted = 564;         // INFO: inactive buffer (and any pending activation) dropped
constexpr core::EventId kTableMissing = 565;         // CRIT: no valid start-up image for a table; init fails
constexpr core::EventId kTableDuplicate = 566;       // CRIT: two start-up images for one table; init fails
constexpr core::EventId kTableStartupInvalid = 567;  // CRIT: start-up image list null or longer than the table count

constexpr core::EventId kRejectBase = 570;  // ERROR: 570 + TableReject (571 too short ... 587 no data)
constexpr core::EventId kRejectTooShort = 571;
constexpr core::EventId kRejectBadMagic = 572;
constexpr core::EventId kRejectUnknownTable = 573;
constexpr core::EventId kRejectWrongTable = 574;
constexpr core::EventId kRejectBadFormat = 575;
constexpr core::EventId kRejectBadLength = 576;
constexpr core::EventId kRejectBadCrc = 577;
constexpr core::EventId kRejectOutOfRange = 578;
constexpr core::EventId kRejectNotFinite = 579;
constexpr core::EventId kRejectInconsistent = 580;
constexpr core::EventId kRejectTooLarge = 581;
constexpr core::EventId kRejectChunkGap = 582;
constexpr core::EventId kRejectNotLoaded = 583;
constexpr core::EventId kRejectNotValidated = 584;
constexpr core::EventId kRejectNoPending = 585;
constexpr core::EventId kRejectActivationPending = 586;
constexpr core::EventId kRejectNoData = 587;

constexpr core::EventId rejectEventId(TableReject reason) {
    return static_cast<core::EventId>(kRejectBase + static_cast<core::EventId>(reason));
}
static_assert(rejectEventId(TableReject::kNoData) == kRejectNoData, "one reject id per reason, in order");
static_assert(kRejectBase + kTableRejectCount - 1 == kRejectNoData, "every reason has its id");
static_assert(kRejectBase + kTableRejectCount <= 600, "reject ids stay inside 560-599");

}  // namespace rse::tables::events

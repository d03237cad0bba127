#include "fsw/tables/table_service.hpp"

#include <cstring>

#include "fsw/tables/table_events.hpp"

namespace rse::tables {
namespace {

TableCheck refusal(TableReject reason) {
    TableCheck check;
    check.reason = reason;
    return check;
}

const char* tableName(TableId id) {
    const TableDesc* table = findTable(id);
    return table != nullptr ? table->name : "?";
}

// Named here rather than in the .def: which tables a running rover applies only
// at start-up is a property of their consumers, not of the table layout.
bool appliesAtNextStart(TableId id) { return id == TableId::kCanNodeMap; }

}  // namespace

const char* toString(TableBufferState state) {
    switch (state) {
        case TableBufferState::kEmpty:
            return "empty";
        case TableBufferState::kLoading:
            return "loading";
        case TableBufferState::kLoaded:
            return "loaded";
        case TableBufferState::kValidated:
            return "validated";
        case TableBufferState::kPending:
            return "pending";
    }
    return "?";
}

TableService::TableService(core::EventLog& events) : events_(events) {}

TableService::Slot* TableService::slotFor(TableId id) {
    const std::size_t index = tableIndex(id);
    return index < kTableCount ? &slots_[index] : nullptr;
}

const TableService::Slot* TableService::slotFor(TableId id) const {
    const std::size_t index = tableIndex(id);
    return index < kTableCount ? &slots_[index] : nullptr;
}

core::Status TableService::init(const TableImageRef* images, std::size_t count) {
    if ((images == nullptr && count > 0) || count > kTableCount) {
        events_.report(events::kTableStartupInvalid, core::Severity::kCritical,
                       "tables: start-up list of %zu images refused (at most %zu)", count, kTableCount);
        return core::Status::kInvalidArgument;
    }
    bool complete = true;
    bool seen[kTableCount] = {};
    for (std::size_t i = 0; i < count; ++i) {
        const TableImageRef& image = images[i];
        TableHeader header;
        const TableId id = readTableHeader(image.data, image.length, &header) ? static_cast<TableId>(header.tableId)
                                                                               : TableId{0};
        const std::size_t index = tableIndex(id);
        if (index == kTableCount) {
            // Not attributable to a table: the generic check says why (too short, bad magic ...).
            (void)reject(id, "start-up", checkTableImage(image.data, image.length));
            complete = false;
            continue;
        }
        if (seen[index]) {
            events_.report(events::kTableDuplicate, core::Severity::kCritical,
                           "table %s: second start-up image refused", tableName(id));
            complete = false;
            continue;
        }
        seen[index] = true;
        const TableCheck check = stage(id, image.data, image.length);
        if (!check.ok()) {
            (void)reject(id, "start-up", check);
            complete = false;
            continue;
        }
        applyStaged(id);
        Slot& slot = slots_[index];
        if (slot.state == TableBufferState::kPending) {
            slot.state = TableBufferState::kValidated;  // the start-up image overrides it; the upload stays loaded
        }
        events_.report(events::kTableStartupActive, core::Severity::kInfo, "table %s version %u active, crc 0x%08X",
                       tableName(id), slot.activeVersion, slot.activeCrc);
    }
    const TableDesc* descs = tableDescs(nullptr);
    for (std::size_t i = 0; i < kTableCount; ++i) {
        if (!slots_[i].active) {
            events_.report(events::kTableMissing, core::Severity::kCritical, "table %s: no valid start-up image",
                           descs[i].name);
            complete = false;
        }
    }
    return complete ? core::Status::kOk : core::Status::kInvalidArgument;
}

void TableService::run(const core::FrameContext&) {
    const TableDesc* descs = tableDescs(nullptr);
    for (std::size_t i = 0; i < kTableCount; ++i) {
        Slot& slot = slots_[i];
        if (slot.state != TableBufferState::kPending) {
            continue;
        }
        const std::uint32_t previous = slot.activeVersion;
        applyStaged(descs[i].id);
        slot.state = TableBufferState::kEmpty;
        slot.length = 0;
        events_.report(events::kTableActivated, core::Severity::kInfo,
                       "table %s activated: version %u -> %u, crc 0x%08X%s", descs[i].name, previous,
                       slot.activeVersion, slot.activeCrc,
                       appliesAtNextStart(descs[i].id) ? "; applies at next start" : "");
    }
}

TableCheck TableService::loadChunk(TableId id, std::uint32_t offset, const std::uint8_t* data, std::size_t length) {
    Slot* slot = slotFor(id);
    if (slot == nullptr) {
        return reject(id, "load", refusal(TableReject::kUnknownTable));
    }
    if (slot->state == TableBufferState::kPending) {
        return reject(id, "load", refusal(TableReject::kActivationPending));
    }
    if (data == nullptr && length > 0) {
        return reject(id, "load", refusal(TableReject::kNoData));
    }
    const std::size_t at = offset == 0 ? 0 : slot->length;
    if (offset != at) {
        return reject(id, "load", refusal(TableReject::kChunkGap));
    }
    if (length > kMaxTableImageSize - at) {
        return reject(id, "load", refusal(TableReject::kTooLarge));
    }
    if (length > 0) {
        std::memcpy(slot->buffer + at, data, length);
    }
    slot->length = at + length;
    const bool wasLoaded = slot->state == TableBufferState::kLoaded;
    TableHeader header;
    const bool complete = readTableHeader(slot->buffer, slot->length, &header) &&
                          slot->length - kTableHeaderSize == header.payloadLength;
    slot->state = complete ? TableBufferState::kLoaded : TableBufferState::kLoading;
    if (complete && !wasLoaded) {
        events_.report(events::kTableLoaded, core::Severity::kInfo, "table %s image loaded: %zu bytes, version %u",
                       tableName(id), slot->length, header.version);
    }
    return TableCheck{};
}

TableCheck TableService::validate(TableId id) {
    Slot* slot = slotFor(id);
    if (slot == nullptr) {
        return reject(id, "validate", refusal(TableReject::kUnknownTable));
    }
    if (slot->state == TableBufferState::kEmpty) {
        return reject(id, "validate", refusal(TableReject::kNotLoaded));
    }
    if (slot->state == TableBufferState::kPending) {
        return reject(id, "validate", refusal(TableReject::kActivationPending));
    }
    const TableCheck check = checkTableImage(slot->buffer, slot->length, id);
    if (!check.ok()) {
        return reject(id, "validate", check);
    }
    slot->state = TableBufferState::kValidated;
    TableHeader header;
    (void)readTableHeader(slot->buffer, slot->length, &header);
    events_.report(events::kTableValidated, core::Severity::kInfo, "table %s image validated: version %u, crc 0x%08X",
                   tableName(id), header.version, header.crc);
    return check;
}

TableCheck TableService::activate(TableId id) {
    Slot* slot = slotFor(id);
    if (slot == nullptr) {
        return reject(id, "activate", refusal(TableReject::kUnknownTable));
    }
    switch (slot->state) {
        case TableBufferState::kEmpty:
            return reject(id, "activate", refusal(TableReject::kNotLoaded));
        case TableBufferState::kPending:
            return reject(id, "activate", refusal(TableReject::kActivationPending));
        case TableBufferState::kLoading:
        case TableBufferState::kLoaded:
            return reject(id, "activate", refusal(TableReject::kNotValidated));
        case TableBufferState::kValidated:
            break;
    }
    // Checked again while decoding: the staged copy only ever holds a passing image.
    const TableCheck check = stage(id, slot->buffer, slot->length);
    if (!check.ok()) {
        slot->state = TableBufferState::kLoaded;
        return reject(id, "activate", check);
    }
    slot->state = TableBufferState::kPending;
    return check;
}

TableCheck TableService::abort(TableId id) {
    Slot* slot = slotFor(id);
    if (slot == nullptr) {
        return reject(id, "abort", refusal(TableReject::kUnknownTable));
    }
    if (slot->state == TableBufferState::kEmpty) {
        return reject(id, "abort", refusal(TableReject::kNoPending));
    }
    const TableBufferState was = slot->state;
    slot->state = TableBufferState::kEmpty;
    slot->length = 0;
    events_.report(events::kTableAborted, core::Severity::kInfo, "table %s inactive buffer dropped (was %s)",
                   tableName(id), toString(was));
    return TableCheck{};
}

TableCheck TableService::dump(TableId id, bool inactive, std::uint8_t* out, std::size_t capacity,
                              std::size_t* length) const {
    const Slot* slot = slotFor(id);
    if (slot == nullptr) {
        return refusal(TableReject::kUnknownTable);
    }
    if (out == nullptr || length == nullptr) {
        return refusal(TableReject::kNoData);
    }
    *length = 0;
    if (inactive) {
        if (slot->state == TableBufferState::kEmpty) {
            return refusal(TableReject::kNotLoaded);
        }
        if (capacity < slot->length) {
            return refusal(TableReject::kTooLarge);
        }
        if (slot->length > 0) {
            std::memcpy(out, slot->buffer, slot->length);
        }
        *length = slot->length;
        return TableCheck{};
    }
    if (!slot->active) {
        return refusal(TableReject::kNotLoaded);
    }
    const std::size_t written = encodeActive(id, slot->activeVersion, out, capacity);
    if (written == 0) {
        return refusal(TableReject::kTooLarge);
    }
    *length = written;
    return TableCheck{};
}

TableStatus TableService::status(TableId id) const {
    TableStatus s;
    const Slot* slot = slotFor(id);
    if (slot == nullptr) {
        return s;
    }
    s.inactiveState = slot->state;
    s.inactiveLength = static_cast<std::uint32_t>(slot->length);
    s.active = slot->active;
    s.activeVersion = slot->activeVersion;
    s.activeCrc = slot->activeCrc;
    s.activations = slot->activations;
    s.rejects = slot->rejects;
    s.lastReject = slot->lastReject;
    return s;
}

void TableService::resetCounters() {
    activations_ = 0;
    rejects_ = 0;
    for (Slot& slot : slots_) {
        slot.activations = 0;
        slot.rejects = 0;
        slot.lastReject = TableReject::kNone;
    }
}

TableCheck TableService::reject(TableId id, const char* operation, const TableCheck& check) {
    ++rejects_;
    Slot* slot = slotFor(id);
    if (slot != nullptr) {
        ++slot->rejects;
        slot->lastReject = check.reason;
    }
    const core::EventId eventId = events::rejectEventId(check.reason);
    const TableDesc* table = findTable(id);
    if (table == nullptr) {
        events_.report(eventId, core::Severity::kError, "table id %u %s rejected: %s", static_cast<unsigned>(id),
                       operation, toString(check.reason));
        return check;
    }
    const auto fieldIndex = static_cast<std::size_t>(check.field);
    if (check.field < 0 || fieldIndex >= table->fieldCount) {
        events_.report(eventId, core::Severity::kError, "table %s %s rejected: %s", table->name, operation,
                       toString(check.reason));
        return check;
    }
    const TableFieldDesc& field = table->fields[fieldIndex];
    if (check.reason == TableReject::kInconsistent) {
        std::size_t ruleCount = 0;
        const TableRuleDesc* rules = tableRules(&ruleCount);
        for (std::size_t i = 0; i < ruleCount; ++i) {
            if (rules[i].id == id && rules[i].lower == fieldIndex && rules[i].upper < table->fieldCount) {
                events_.report(eventId, core::Severity::kError, "table %s %s rejected: %s >= %s", table->name,
                               operation, field.name, table->fields[rules[i].upper].name);
                return check;
            }
        }
    }
    if (field.count > 1) {
        events_.report(eventId, core::Severity::kError, "table %s %s rejected: %s, field %s[%u]", table->name,
                       operation, toString(check.reason), field.name, static_cast<unsigned>(check.element));
    } else {
        events_.report(eventId, core::Severity::kError, "table %s %s rejected: %s, field %s", table->name, operation,
                       toString(check.reason), field.name);
    }
    return check;
}

TableCheck TableService::stage(TableId id, const std::uint8_t* image, std::size_t length) {
    Slot* slot = slotFor(id);
    TableCheck check = refusal(TableReject::kUnknownTable);
    switch (id) {
#define RSE_TABLE(Name, idValue, description)                    \
    case TableId::k##Name:                                       \
        check = decodeTable(image, length, &staged##Name##_);    \
        break;
#include "fsw/tables/table_defs.def"
    }
    TableHeader header;
    if (slot != nullptr && check.ok() && readTableHeader(image, length, &header)) {
        slot->stagedVersion = header.version;
        slot->stagedCrc = header.crc;
    }
    return check;
}

void TableService::applyStaged(TableId id) {
    Slot* slot = slotFor(id);
    if (slot == nullptr) {
        return;
    }
    switch (id) {
#define RSE_TABLE(Name, idValue, description) \
    case TableId::k##Name:                    \
        active##Name##_ = staged##Name##_;    \
        break;
#include "fsw/tables/table_defs.def"
    }
    slot->active = true;
    slot->activeVersion = slot->stagedVersion;
    slot->activeCrc = slot->stagedCrc;
    ++slot->activations;
    ++activations_;
}

std::size_t TableService::encodeActive(TableId id, std::uint32_t version, std::uint8_t* out,
                                       std::size_t capacity) const {
    switch (id) {
#define RSE_TABLE(Name, idValue, description) \
    case TableId::k##Name:                    \
        return encodeTable(active##Name##_, version, out, capacity);
#include "fsw/tables/table_defs.def"
    }
    return 0;
}

}  // namespace rse::tables

// The table service: holds the active parameter tables and manages ground
// updates (the cFS "table services" idea; docs/tables.md).
//
// Each table has an active copy (the typed struct flight code reads through the
// accessors) and an inactive buffer that a ground load fills:
//
//   loadChunk(offset 0, ...) ... loadChunk(offset n, ...)  -> LOADING / LOADED
//   validate()   full image check of the buffer            -> VALIDATED
//   activate()   decodes the validated image, stages it     -> PENDING
//   run()        applies every staged table                 -> EMPTY (the image is now active)
//
// Atomic at a frame boundary: the application puts this task FIRST in the
// rate-group table, at every minor frame. The executive is single-threaded and
// runs tasks in table order, so a staged table is applied before any other task
// of the frame runs and no task ever sees a half-applied table or a table that
// changes during a frame. activate() itself never touches the active copy.
//
// A rejected image or operation never touches the active copy either. Every
// rejection returns a TableCheck, counts (per table and in total), records the
// reason and raises its own event (table_events.hpp: 570 + reason) naming the
// table, the operation and, for a field fault, the field. Each activation is
// evented with the old and the incoming version and the CRC.
//
// The CAN node map is read by the CAN master at start-up only: an activated node
// map is stored and reported, but takes effect at the next start (its activation
// event says so).
//
// All storage is inside the object (one kMaxTableImageSize buffer per table);
// no heap; every loop is bounded by kTableCount, a table's field count or a
// buffer size.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/status.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::tables {

enum class TableBufferState : std::uint8_t {
    kEmpty = 0,  // nothing loaded (or the last image was activated)
    kLoading,    // chunks received, fewer bytes than the header announces (or no header yet)
    kLoaded,     // as many bytes as the header announces; not yet validated
    kValidated,  // passed every check; may be activated
    kPending,    // activated: applied at the start of the next frame
};
const char* toString(TableBufferState state);

struct TableStatus {
    TableBufferState inactiveState = TableBufferState::kEmpty;
    std::uint32_t inactiveLength = 0;  // bytes in the inactive buffer
    bool active = false;               // a table is in force (false only before init)
    std::uint32_t activeVersion = 0;
    std::uint32_t activeCrc = 0;       // CRC of the image the active table came from
    std::uint32_t activations = 0;     // since start or resetCounters(), start-up ones included
    std::uint32_t rejects = 0;
    TableReject lastReject = TableReject::kNone;
};

class TableService final : public core::Task {
public:
    explicit TableService(core::EventLog& events);

    // Start-up: checks and activates every image (each must be a different
    // table). A missing, duplicate or bad image is evented and init returns
    // kInvalidArgument naming the table in the event; tables already active
    // (from an earlier init) stay in force. On kOk every table is active.
    core::Status init(const TableImageRef* images, std::size_t count);

    // Applies staged activations; must run first in every minor frame.
    void run(const core::FrameContext& frame) override;

    // Ground side. offset 0 starts a fresh load into the table's inactive buffer
    // (dropping what it held); later chunks must start where the previous one
    // ended (else kChunkGap, the buffer unchanged) and the image may not exceed
    // kMaxTableImageSize (kTooLarge). Refused while an activation is pending.
    TableCheck loadChunk(TableId id, std::uint32_t offset, const std::uint8_t* data, std::size_t length);
    // Full image check of the inactive buffer (checkTableImage for this table).
    TableCheck validate(TableId id);
    // Stages a validated image; it becomes active at the next run().
    TableCheck activate(TableId id);
    // Drops the inactive buffer and any activation not yet applied (kNoPending if empty).
    TableCheck abort(TableId id);
    // Copies the active table, encoded as an image with its version (byte for
    // byte the image it came from), or the raw inactive buffer. out and length
    // must not be null; kTooLarge if capacity is too small, kNotLoaded if
    // there is nothing to dump.
    TableCheck dump(TableId id, bool inactive, std::uint8_t* out, std::size_t capacity, std::size_t* length) const;

    const RoverGeometryTable& roverGeometry() const { return activeRoverGeometry_; }
    const EstimatorNoiseTable& estimatorNoise() const { return activeEstimatorNoise_; }
    const PlannerTable& planner() const { return activePlanner_; }
    const HabitualTable& habitual() const { return activeHabitual_; }
    const CanNodeMapTable& canNodeMap() const { return activeCanNodeMap_; }
    const FaultResponseTable& faultResponse() const { return activeFaultResponse_; }
    const DriveHealthModelTable& driveHealthModel() const { return activeDriveHealthModel_; }
    const FollowerTable& follower() const { return activeFollower_; }
    const CoarseMapTable& coarseMap() const { return activeCoarseMap_; }
    const FaultProtectionTable& faultProtection() const { return activeFaultProtection_; }

    TableStatus status(TableId id) const;  // all zero for an unknown id
    std::uint32_t activations() const { return activations_; }
    std::uint32_t rejects() const { return rejects_; }
    void resetCounters();

private:
    struct Slot {
        std::uint8_t buffer[kMaxTableImageSize] = {};
        std::size_t length = 0;
        TableBufferState state = TableBufferState::kEmpty;
        bool active = false;
        std::uint32_t activeVersion = 0;
        std::uint32_t activeCrc = 0;
        std::uint32_t stagedVersion = 0;
        std::uint32_t stagedCrc = 0;
        std::uint32_t activations = 0;
        std::uint32_t rejects = 0;
        TableReject lastReject = TableReject::kNone;
    };

    Slot* slotFor(TableId id);
    const Slot* slotFor(TableId id) const;
    TableCheck reject(TableId id, const char* operation, const TableCheck& check);
    TableCheck stage(TableId id, const std::uint8_t* image, std::size_t length);  // decode into the staged copy
    void applyStaged(TableId id);                                                   // staged copy -> active
    std::size_t encodeActive(TableId id, std::uint32_t version, std::uint8_t* out, std::size_t capacity) const;

    core::EventLog& events_;
    Slot slots_[kTableCount];
    std::uint32_t activations_ = 0;
    std::uint32_t rejects_ = 0;

    // Typed active and staged copies, one pair per table.
#define RSE_TABLE(Name, id, description) \
    Name##Table active##Name##_{};       \
    Name##Table staged##Name##_{};
#include "fsw/tables/table_defs.def"
};

// One accessor per table above: a table added to the .def needs one too.
static_assert(kTableCount == 10, "add an accessor to TableService for every table");

}  // namespace rse::tables

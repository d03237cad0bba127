// Writing a RecordStore record without blocking a cyclic task (hal/nvm).
//
// A durable write costs a file system 0.7-5 ms (write, fsync, rename, fsync of
// the directory; bench_ground_link_costs on the development VM, the top with
// builds running beside): a third of the command task's 2 ms budget at best,
// more than all of it at worst. The task therefore never writes itself: it post()s the bytes
// and learns later, from takeResult(), that they are durable. Until then it
// must behave as if the old record were still the one on the medium.
//
//   post():       kOk when taken (the bytes are copied; the caller's buffer may be
//                 reused at once), kBusy while the previous write has not finished
//                 or its result has not been taken, kTooLarge above kMaxRecordBytes,
//                 kUnavailable when the writer cannot write at all.
//   takeResult(): true exactly once per posted write, when it has finished, with
//                 the store's status (kOk: durable); false while one is in flight
//                 or nothing was posted. Never blocks.
//
// Two writers: ImmediateRecordWriter writes inside post() (memory stores, unit
// tests, the lockstep rig: same-frame, deterministic), ThreadedRecordWriter
// (hal/nvm/threaded_record_writer.hpp) on a worker thread (rse-fsw's file).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "hal/nvm/record_store.hpp"

namespace rse::hal {

constexpr std::size_t kMaxRecordBytes = 256;  // largest record a writer takes

class RecordWriter {
public:
    virtual ~RecordWriter() = default;
    virtual core::Status post(const std::uint8_t* data, std::size_t length) = 0;
    virtual bool takeResult(core::Status* result) = 0;
};

// Writes in post(); the result waits for takeResult().
class ImmediateRecordWriter final : public RecordWriter {
public:
    void bind(RecordStore* store) { store_ = store; }

    core::Status post(const std::uint8_t* data, std::size_t length) override {
        if (store_ == nullptr) {
            return core::Status::kUnavailable;
        }
        if (pending_) {
            return core::Status::kBusy;
        }
        if (length > kMaxRecordBytes) {
            return core::Status::kTooLarge;
        }
        result_ = store_->write(data, length);
        pending_ = true;
        return core::Status::kOk;
    }
    bool takeResult(core::Status* result) override {
        if (!pending_) {
            return false;
        }
        pending_ = false;
        *result = result_;
        return true;
    }

private:
    RecordStore* store_ = nullptr;
    core::Status result_ = core::Status::kOk;
    bool pending_ = false;
};

}  // namespace rse::hal

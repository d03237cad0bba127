// A RecordWriter (hal/nvm/record_writer.hpp) whose writes run on a worker
// thread, so the blocking fsync never stalls the cyclic executive.
//
// One write at a time: post() copies the record into the writer's own buffer and
// wakes the worker; the worker calls the store's write() outside the lock and
// leaves the status for takeResult(). The cyclic side holds the lock only to copy
// a few hundred bytes or read a flag, never across a write. The thread and its
// stack are made in start() (initialisation); nothing is allocated afterwards.
// stop() lets a write in flight finish (nothing posted is lost), then joins.
// The store is the worker's while a write is in flight: the owner reads it (the
// start-up load) only before start() or when no write is pending.
#pragma once

#include <pthread.h>

#include <cstddef>
#include <cstdint>

#include "hal/nvm/record_writer.hpp"

namespace rse::hal {

class ThreadedRecordWriter final : public RecordWriter {
public:
    explicit ThreadedRecordWriter(RecordStore& store) : store_(store) {}
    ~ThreadedRecordWriter() override { stop(); }
    ThreadedRecordWriter(const ThreadedRecordWriter&) = delete;
    ThreadedRecordWriter& operator=(const ThreadedRecordWriter&) = delete;

    // kUnavailable (errno-style code in *error) when the thread cannot be made.
    core::Status start(int* error);
    // Finishes a write in flight, then ends the worker. Safe to call twice.
    void stop();
    bool running() const { return running_; }

    core::Status post(const std::uint8_t* data, std::size_t length) override;
    bool takeResult(core::Status* result) override;

private:
    static void* threadEntry(void* self);
    void work();

    RecordStore& store_;
    pthread_t thread_{};
    pthread_mutex_t mutex_ = PTHREAD_MUTEX_INITIALIZER;
    pthread_cond_t wake_ = PTHREAD_COND_INITIALIZER;
    bool running_ = false;   // owner's view: start() succeeded, stop() not yet called
    // Under mutex_:
    bool stopping_ = false;
    bool queued_ = false;    // bytes_ wait for the worker
    bool inFlight_ = false;  // posted, result not yet taken
    bool finished_ = false;  // result_ holds the finished write's status
    core::Status result_ = core::Status::kOk;
    std::uint8_t bytes_[kMaxRecordBytes] = {};
    std::size_t length_ = 0;
};

}  // namespace rse::hal

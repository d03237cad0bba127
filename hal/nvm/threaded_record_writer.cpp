#include "hal/nvm/threaded_record_writer.hpp"

#include <cstring>

namespace rse::hal {

core::Status ThreadedRecordWriter::start(int* error) {
    if (running_) {
        return core::Status::kOk;
    }
    pthread_mutex_lock(&mutex_);
    stopping_ = false;
    pthread_mutex_unlock(&mutex_);
    const int rc = pthread_create(&thread_, nullptr, &ThreadedRecordWriter::threadEntry, this);
    if (rc != 0) {
        if (error != nullptr) {
            *error = rc;
        }
        return core::Status::kUnavailable;
    }
    running_ = true;
    return core::Status::kOk;
}

void ThreadedRecordWriter::stop() {
    if (!running_) {
        return;
    }
    pthread_mutex_lock(&mutex_);
    stopping_ = true;
    pthread_cond_signal(&wake_);
    pthread_mutex_unlock(&mutex_);
    pthread_join(thread_, nullptr);
    running_ = false;
}

core::Status ThreadedRecordWriter::post(const std::uint8_t* data, std::size_t length) {
    if (!running_) {
        return core::Status::kUnavailable;
    }
    if (length > kMaxRecordBytes) {
        return core::Status::kTooLarge;
    }
    pthread_mutex_lock(&mutex_);
    core::Status status = core::Status::kBusy;
    if (!inFlight_) {
        std::memcpy(bytes_, data, length);
        length_ = length;
        queued_ = true;
        inFlight_ = true;
        finished_ = false;
        status = core::Status::kOk;
        pthread_cond_signal(&wake_);
    }
    pthread_mutex_unlock(&mutex_);
    return status;
}

bool ThreadedRecordWriter::takeResult(core::Status* result) {
    pthread_mutex_lock(&mutex_);
    const bool done = inFlight_ && finished_;
    if (done) {
        *result = result_;
        inFlight_ = false;
        finished_ = false;
    }
    pthread_mutex_unlock(&mutex_);
    return done;
}

void* ThreadedRecordWriter::threadEntry(void* self) {
    static_cast<ThreadedRecordWriter*>(self)->work();
    return nullptr;
}

// The worker copies nothing out: while queued_ or a write is under way, post()
// refuses (inFlight_), so bytes_ is stable without the lock.
void ThreadedRecordWriter::work() {
    pthread_mutex_lock(&mutex_);
    for (;;) {
        while (!queued_ && !stopping_) {
            pthread_cond_wait(&wake_, &mutex_);
        }
        if (!queued_) {
            break;  // stopping, nothing left to write
        }
        queued_ = false;
        pthread_mutex_unlock(&mutex_);
        const core::Status status = store_.write(bytes_, length_);
        pthread_mutex_lock(&mutex_);
        result_ = status;
        finished_ = true;
    }
    pthread_mutex_unlock(&mutex_);
}

}  // namespace rse::hal

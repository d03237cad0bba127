// hal/nvm ThreadedRecordWriter: the anti-replay store's writes leave the
// command task's thread. A gated store holds a write "in the fsync" until the
// test opens the gate, so the in-flight states are observed, not raced.
#include <pthread.h>
#include <time.h>

#include <cstdint>
#include <cstring>

#include "hal/nvm/record_store.hpp"
#include "hal/nvm/threaded_record_writer.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

class GatedStore final : public hal::RecordStore {
public:
    core::Status read(std::uint8_t*, std::size_t, std::size_t*) override { return core::Status::kNotFound; }
    core::Status write(const std::uint8_t* data, std::size_t length) override {
        pthread_mutex_lock(&mutex_);
        ++entered_;
        pthread_cond_broadcast(&changed_);
        while (!open_) {
            pthread_cond_wait(&changed_, &mutex_);
        }
        std::memcpy(bytes_, data, length);
        length_ = length;
        ++writes_;
        pthread_mutex_unlock(&mutex_);
        return fail_ ? core::Status::kUnavailable : core::Status::kOk;
    }
    void open() {
        pthread_mutex_lock(&mutex_);
        open_ = true;
        pthread_cond_broadcast(&changed_);
        pthread_mutex_unlock(&mutex_);
    }
    // Until the worker is inside write() for the n-th time.
    void awaitEntered(int n) {
        pthread_mutex_lock(&mutex_);
        while (entered_ < n) {
            pthread_cond_wait(&changed_, &mutex_);
        }
        pthread_mutex_unlock(&mutex_);
    }
    int writes() {
        pthread_mutex_lock(&mutex_);
        const int n = writes_;
        pthread_mutex_unlock(&mutex_);
        return n;
    }
    bool fail_ = false;
    std::uint8_t bytes_[hal::kMaxRecordBytes] = {};
    std::size_t length_ = 0;

private:
    pthread_mutex_t mutex_ = PTHREAD_MUTEX_INITIALIZER;
    pthread_cond_t changed_ = PTHREAD_COND_INITIALIZER;
    bool open_ = false;
    int entered_ = 0;
    int writes_ = 0;
};

// Polls like the command task does, a frame at a time, for at most ~5 s.
bool awaitResult(hal::RecordWriter& writer, core::Status* result) {
    for (int i = 0; i < 5000; ++i) {
        if (writer.takeResult(result)) {
            return true;
        }
        const timespec ms{0, 1000000};
        nanosleep(&ms, nullptr);
    }
    return false;
}

}  // namespace

TEST_GROUP(ThreadedRecordWriter) {
    GatedStore store;
};

TEST(ThreadedRecordWriter, PostReturnsAtOnceAndTheResultComesWhenTheWriteIsDone) {
    hal::ThreadedRecordWriter writer(store);
    CHECK(core::isOk(writer.start(nullptr)));
    std::uint8_t record[4] = {1, 2, 3, 4};
    CHECK(core::isOk(writer.post(record, sizeof record)));
    record[0] = 9;  // the writer copied it: the caller may reuse its buffer
    store.awaitEntered(1);
    core::Status result = core::Status::kOk;
    CHECK_FALSE(writer.takeResult(&result));  // in the "fsync": no result yet
    CHECK(writer.post(record, sizeof record) == core::Status::kBusy);  // one at a time
    store.open();
    CHECK(awaitResult(writer, &result));
    CHECK(core::isOk(result));
    LONGS_EQUAL(1, store.bytes_[0]);
    LONGS_EQUAL(4, store.length_);
    CHECK_FALSE(writer.takeResult(&result));  // reported once
    CHECK(core::isOk(writer.post(record, sizeof record)));  // free again
    CHECK(awaitResult(writer, &result));
    LONGS_EQUAL(9, store.bytes_[0]);
    LONGS_EQUAL(2, store.writes());
}

TEST(ThreadedRecordWriter, AFailedWriteIsReported) {
    hal::ThreadedRecordWriter writer(store);
    CHECK(core::isOk(writer.start(nullptr)));
    store.fail_ = true;
    store.open();
    const std::uint8_t record[1] = {7};
    CHECK(core::isOk(writer.post(record, sizeof record)));
    core::Status result = core::Status::kOk;
    CHECK(awaitResult(writer, &result));
    CHECK(result == core::Status::kUnavailable);
}

TEST(ThreadedRecordWriter, StopFinishesAWriteInFlight) {
    hal::ThreadedRecordWriter writer(store);
    CHECK(core::isOk(writer.start(nullptr)));
    const std::uint8_t record[2] = {5, 6};
    CHECK(core::isOk(writer.post(record, sizeof record)));
    store.awaitEntered(1);
    store.open();
    writer.stop();  // joins after the write, never abandons it
    LONGS_EQUAL(1, store.writes());
    CHECK_FALSE(writer.running());
}

TEST(ThreadedRecordWriter, RefusesWhatItCannotWrite) {
    hal::ThreadedRecordWriter writer(store);
    const std::uint8_t record[1] = {1};
    CHECK(writer.post(record, sizeof record) == core::Status::kUnavailable);  // not started
    CHECK(core::isOk(writer.start(nullptr)));
    std::uint8_t big[hal::kMaxRecordBytes + 1] = {};
    CHECK(writer.post(big, sizeof big) == core::Status::kTooLarge);
    store.open();
    writer.stop();
    LONGS_EQUAL(0, store.writes());
}

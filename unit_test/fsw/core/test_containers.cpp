#include "fsw/core/object_pool.hpp"
#include "fsw/core/ring_buffer.hpp"
#include "fsw/core/static_vector.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::ObjectPool;
using rse::core::RingBuffer;
using rse::core::StaticVector;
using rse::core::Status;

TEST_GROUP(StaticVector){};

TEST(StaticVector, PushBeyondCapacityIsRefusedAndKeepsContents) {
    StaticVector<int, 3> v;
    CHECK(Status::kOk == v.push_back(1));
    CHECK(Status::kOk == v.push_back(2));
    CHECK(Status::kOk == v.push_back(3));
    CHECK(v.full());
    CHECK(Status::kFull == v.push_back(4));
    LONGS_EQUAL(3, v.size());
    LONGS_EQUAL(3, *v.at(2));
}

TEST(StaticVector, OutOfRangeAccessReturnsNull) {
    StaticVector<int, 4> v;
    POINTERS_EQUAL(nullptr, v.at(0));
    CHECK(Status::kOk == v.push_back(7));
    CHECK(v.at(0) != nullptr);
    POINTERS_EQUAL(nullptr, v.at(1));
    POINTERS_EQUAL(nullptr, v.at(1000000));
}

TEST(StaticVector, EraseKeepsOrderAndRejectsBadIndex) {
    StaticVector<int, 5> v;
    for (int i = 0; i < 5; ++i) {
        CHECK(Status::kOk == v.push_back(i * 10));
    }
    CHECK(Status::kOk == v.erase(1));
    LONGS_EQUAL(4, v.size());
    LONGS_EQUAL(0, *v.at(0));
    LONGS_EQUAL(20, *v.at(1));
    LONGS_EQUAL(40, *v.at(3));
    CHECK(Status::kInvalidArgument == v.erase(4));
}

TEST(StaticVector, PopBackOnEmptyIsAnError) {
    StaticVector<int, 2> v;
    int out = -1;
    CHECK(Status::kEmpty == v.pop_back(&out));
    LONGS_EQUAL(-1, out);
    CHECK(Status::kOk == v.push_back(5));
    CHECK(Status::kOk == v.pop_back(&out));
    LONGS_EQUAL(5, out);
    CHECK(v.empty());
}

TEST_GROUP(RingBuffer){};

TEST(RingBuffer, FifoOrderAcrossWrapAround) {
    RingBuffer<int, 3> r;
    int out = 0;
    for (int round = 0; round < 5; ++round) {
        CHECK(Status::kOk == r.push(round));
        CHECK(Status::kOk == r.push(round + 100));
        CHECK(Status::kOk == r.pop(&out));
        LONGS_EQUAL(round, out);
        CHECK(Status::kOk == r.pop(&out));
        LONGS_EQUAL(round + 100, out);
    }
    CHECK(Status::kEmpty == r.pop(&out));
}

TEST(RingBuffer, PushWhenFullIsRefused) {
    RingBuffer<int, 2> r;
    CHECK(Status::kOk == r.push(1));
    CHECK(Status::kOk == r.push(2));
    CHECK(Status::kFull == r.push(3));
    LONGS_EQUAL(1, *r.peek());
}

TEST(RingBuffer, OverwriteDropsOldestAndSaysSo) {
    RingBuffer<int, 2> r;
    CHECK_FALSE(r.pushOverwrite(1));
    CHECK_FALSE(r.pushOverwrite(2));
    CHECK_TRUE(r.pushOverwrite(3));
    int out = 0;
    CHECK(Status::kOk == r.pop(&out));
    LONGS_EQUAL(2, out);
    CHECK(Status::kOk == r.pop(&out));
    LONGS_EQUAL(3, out);
}

TEST_GROUP(ObjectPool){};

TEST(ObjectPool, ExhaustionReturnsNullAndReleaseMakesRoom) {
    ObjectPool<double, 2> pool;
    double* a = pool.acquire();
    double* b = pool.acquire();
    CHECK(a != nullptr);
    CHECK(b != nullptr);
    CHECK(a != b);
    POINTERS_EQUAL(nullptr, pool.acquire());
    CHECK(Status::kOk == pool.release(a));
    POINTERS_EQUAL(a, pool.acquire());
    LONGS_EQUAL(0, pool.available());
}

TEST(ObjectPool, ForeignAndDoubleReleaseAreRejected) {
    ObjectPool<int, 2> pool;
    int outsider = 0;
    CHECK(Status::kInvalidArgument == pool.release(&outsider));
    CHECK(Status::kInvalidArgument == pool.release(nullptr));
    int* a = pool.acquire();
    CHECK(Status::kOk == pool.release(a));
    CHECK(Status::kInvalidArgument == pool.release(a));
    LONGS_EQUAL(2, pool.available());
}

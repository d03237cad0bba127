#include "unit_test/support/alloc_guard.hpp"

#include <Eigen/Core>
#include <atomic>
#include <cerrno>
#include <cstddef>

extern "C" {
// glibc's own allocator entry points, exported for exactly this kind of wrapper.
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
}

namespace {
std::atomic<std::uint64_t> g_allocations{0};
void countOne() { g_allocations.fetch_add(1, std::memory_order_relaxed); }
}  // namespace

extern "C" {

void* malloc(std::size_t size) noexcept {
    countOne();
    return __libc_malloc(size);
}

void* calloc(std::size_t count, std::size_t size) noexcept {
    countOne();
    return __libc_calloc(count, size);
}

void* realloc(void* pointer, std::size_t size) noexcept {
    countOne();
    return __libc_realloc(pointer, size);
}

void* memalign(std::size_t alignment, std::size_t size) noexcept {
    countOne();
    return __libc_memalign(alignment, size);
}

void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
    countOne();
    return __libc_memalign(alignment, size);
}

int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept {
    if (alignment < sizeof(void*) || (alignment & (alignment - 1)) != 0) {
        return EINVAL;
    }
    countOne();
    void* p = __libc_memalign(alignment, size);
    if (p == nullptr) {
        return ENOMEM;
    }
    *out = p;
    return 0;
}

}  // extern "C"

namespace rse::test {

std::uint64_t heapAllocations() { return g_allocations.load(std::memory_order_relaxed); }

AllocationWatch::AllocationWatch(bool forbidEigen) : start_(heapAllocations()), forbidEigen_(forbidEigen) {
    if (forbidEigen_) {
        Eigen::internal::set_is_malloc_allowed(false);
    }
}

AllocationWatch::~AllocationWatch() {
    if (forbidEigen_) {
        Eigen::internal::set_is_malloc_allowed(true);
    }
}

}  // namespace rse::test

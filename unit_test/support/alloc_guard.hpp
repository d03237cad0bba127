// Test-only heap allocation counter.
//
// alloc_guard.cpp replaces malloc, calloc, realloc, memalign, posix_memalign and
// aligned_alloc for the whole test binary (forwarding to glibc's own allocator),
// so every heap allocation is counted wherever it comes from: operator new in
// libstdc++, CppUTest, Eigen, stdio or our own code.
#pragma once

#include <cstdint>

namespace rse::test {

// Allocations counted since the binary started.
std::uint64_t heapAllocations();

// Counts the allocations made while it lives. With forbidEigen (the default)
// it also switches Eigen's EIGEN_RUNTIME_NO_MALLOC check on, so a dynamic Eigen
// allocation stops the test at the offending line instead of only being counted.
class AllocationWatch {
public:
    explicit AllocationWatch(bool forbidEigen = true);
    ~AllocationWatch();
    AllocationWatch(const AllocationWatch&) = delete;
    AllocationWatch& operator=(const AllocationWatch&) = delete;

    std::uint64_t count() const { return heapAllocations() - start_; }

private:
    std::uint64_t start_;
    bool forbidEigen_;
};

}  // namespace rse::test

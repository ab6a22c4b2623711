/// @file allocation_counter.hpp
/// Counts the heap allocations of a test program: malloc, calloc, realloc (Eigen's heap goes through
/// them) and operator new are replaced, and each call is counted while g_counting is set. Include it
/// in exactly one translation unit of a test program (it defines the replacements). AddressSanitizer
/// owns malloc: under it nothing is replaced, INERTIAL_ALLOCATIONS_NOT_COUNTED is defined, and the
/// counting tests report themselves skipped.
#pragma once

#include <atomic>
#include <cstddef>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(INERTIAL_TEST_UNDER_ASAN)
#define INERTIAL_ALLOCATIONS_NOT_COUNTED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define INERTIAL_ALLOCATIONS_NOT_COUNTED 1
#endif
#endif

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
[[maybe_unused]] void CountAllocation() {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

#ifndef INERTIAL_ALLOCATIONS_NOT_COUNTED
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void __libc_free(void*);
extern "C" void* malloc(std::size_t n) {
  CountAllocation();
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t n, std::size_t size) {
  CountAllocation();
  return __libc_calloc(n, size);
}
extern "C" void* realloc(void* p, std::size_t n) {
  CountAllocation();
  return __libc_realloc(p, n);
}
extern "C" void free(void* p) { __libc_free(p); }
void* operator new(std::size_t n) {
  CountAllocation();
  void* p = __libc_malloc(n == 0 ? 1 : n);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t) noexcept { __libc_free(p); }
#endif

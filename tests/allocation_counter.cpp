// The replacements of allocation_counter.hpp: malloc, calloc, realloc, free and the plain forms of
// operator new and delete, each counted while g_counting is set, then passed to glibc's own
// allocator. One copy per test program (CMake links this file into the programs that count).
#include "allocation_counter.hpp"

#include <cstddef>
#include <new>

std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

#ifndef INERTIAL_ALLOCATIONS_NOT_COUNTED
namespace {
void CountAllocation() {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

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

/// @file allocation_counter.hpp
/// Counts the heap allocations of a test program: malloc, calloc, realloc (Eigen's heap goes through
/// them) and operator new are replaced (allocation_counter.cpp, linked into the programs whose tests
/// count), and each call is counted while g_counting is set. AddressSanitizer owns malloc: under it
/// nothing is replaced, INERTIAL_ALLOCATIONS_NOT_COUNTED is defined, and the counting tests report
/// themselves skipped.
#pragma once

#include <atomic>

#if defined(__SANITIZE_ADDRESS__) || defined(INERTIAL_TEST_UNDER_ASAN)
#define INERTIAL_ALLOCATIONS_NOT_COUNTED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define INERTIAL_ALLOCATIONS_NOT_COUNTED 1
#endif
#endif

/// While true, every malloc, calloc, realloc and operator new of the process adds one to g_allocations.
extern std::atomic<bool> g_counting;
/// The allocations counted so far (reset it before a measured stretch).
extern std::atomic<long> g_allocations;

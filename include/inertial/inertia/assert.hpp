/// @file assert.hpp
/// INERTIAL_ASSERT: internal invariants of the core. Compiled in only with the CMake option
/// INERTIAL_ASSERTS=ON (Release with debug asserts) or in builds without NDEBUG; it prints the
/// failed condition with file and line and aborts. Boundaries (files, CLI, messages) never rely on
/// it: they validate input and report errors.
#pragma once

#include <cstdio>
#include <cstdlib>

#if defined(INERTIAL_ENABLE_ASSERTS) || !defined(NDEBUG)
#define INERTIAL_ASSERT(cond)                                                              \
  do {                                                                                     \
    if (!(cond)) {                                                                         \
      std::fprintf(stderr, "%s:%d: internal assertion failed: %s\n", __FILE__, __LINE__, \
                   #cond);                                                                 \
      std::abort();                                                                        \
    }                                                                                      \
  } while (false)
#else
#define INERTIAL_ASSERT(cond) \
  do {                        \
  } while (false)
#endif

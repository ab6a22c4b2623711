/// @file time_stamps.hpp
/// Test helper: `count` time stamps start, start + step, ... formatted with `format`.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace inertial::testing {

inline std::vector<std::string> Stamps(double start, double step, int count, const char* format = "%.17g") {
  std::vector<std::string> out;
  char cell[64];
  for (int i = 0; i < count; ++i) {
    std::snprintf(cell, sizeof(cell), format, start + step * i);
    out.push_back(cell);
  }
  return out;
}

}  // namespace inertial::testing
